# Each library sees only the headers of what it links (docs/architecture.md, "Arrows one way").
#
# Sources include root-relative paths ("modelling/room_model.h"). Instead of one include
# directory for everyone (the repository root, through which any library could include any
# header), each folder gets an include root of its own, build/include/<folder>/, holding one
# symbolic link <folder> -> the source folder. A library adds its root PUBLIC, so the roots
# reach exactly the targets that link it (through PUBLIC links, on to their users): an include of
# a library the target does not link fails to compile.
#
# mopad_include_root(<target> <folder> [PRIVATE]): gives <target> the root of <folder> (PUBLIC
# unless PRIVATE is given) and records libraries for the link graph (cmake/LinkGraph.cmake).
function(mopad_include_root target folder)
  set(root ${PROJECT_BINARY_DIR}/include/${folder})
  if(NOT EXISTS ${root}/${folder})
    file(MAKE_DIRECTORY ${root})
    file(CREATE_LINK ${PROJECT_SOURCE_DIR}/${folder} ${root}/${folder} SYMBOLIC)
  endif()
  set(scope PUBLIC)
  if(ARGV2 STREQUAL "PRIVATE")
    set(scope PRIVATE)
  endif()
  target_include_directories(${target} ${scope} ${root})
  get_target_property(type ${target} TYPE)
  if(type MATCHES "LIBRARY")
    set_property(GLOBAL APPEND PROPERTY MOPAD_LIBRARIES ${target})
  endif()
endfunction()
