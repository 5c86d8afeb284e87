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
# unless PRIVATE is given) and records libraries, with their folder, for the link graph
# (cmake/LinkGraph.cmake) and the install (cmake/Install.cmake).
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
  # Installed, the same scheme: include/mopad/<folder>/<folder>/ holds the headers
  # (cmake/Install.cmake), so a package user sees the headers of what it links and no others.
  target_include_directories(${target} ${scope} $<BUILD_INTERFACE:${root}>
                             $<INSTALL_INTERFACE:include/mopad/${folder}>)
  get_target_property(type ${target} TYPE)
  if(type MATCHES "LIBRARY")
    # A sanitized build's installed libraries: their users compile and link with the same
    # sanitizers (the runtimes; and Eigen's allocation ABI differs under __SANITIZE_ADDRESS__, so
    # a matrix freed by unsanitized code is a bad free). cmake/Sanitizers.cmake gives the build
    # tree its flags globally.
    if(mopad_sanitize_flags)
      target_compile_options(${target} INTERFACE "$<INSTALL_INTERFACE:${mopad_sanitize_flags}>")
      target_link_options(${target} INTERFACE "$<INSTALL_INTERFACE:${mopad_sanitize_flags}>")
    endif()
    set_property(GLOBAL APPEND PROPERTY MOPAD_LIBRARIES ${target})
    set_property(TARGET ${target} PROPERTY MOPAD_FOLDER ${folder})
  endif()
endfunction()
