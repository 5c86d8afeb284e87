# The installed package (docs/package.md). `cmake --install build --prefix P` puts
#   P/lib/libmopad_<folder>.a                 every project library (static)
#   P/include/mopad/<folder>/<folder>/*.h     its headers: one include root per library, as in
#                                             the build (cmake/IncludeRoots.cmake), so a user
#                                             of OpenMoPAD::x sees the headers of x and of what
#                                             x links, and no others
#   P/lib/cmake/OpenMoPAD/                    OpenMoPADConfig.cmake, its version file, targets
#   P/bin/mopad                               the CLI
#   P/share/OpenMoPAD/scenes/*.yaml           the committed scene specs (office_5rooms.yaml is
#                                             the default scene of `mopad run`)
# find_package(OpenMoPAD) gives OpenMoPAD::<folder> for every library (OpenMoPAD::sim,
# OpenMoPAD::autonomy, ...), the third-party packages of their link interfaces found again
# (cmake/OpenMoPADConfig.cmake.in). In the build the libraries keep their mopad::<folder> aliases.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(MOPAD_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/OpenMoPAD)

# mopad_install(): installs every library recorded by mopad_include_root, their headers, the
# CLI, the scene specs and the package config. Call once, after every add_subdirectory.
function(mopad_install)
  get_property(targets GLOBAL PROPERTY MOPAD_LIBRARIES)
  foreach(t IN LISTS targets)
    get_target_property(folder ${t} MOPAD_FOLDER)
    set_target_properties(${t} PROPERTIES EXPORT_NAME ${folder})
    install(TARGETS ${t} EXPORT OpenMoPADTargets
            ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
            LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}/
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mopad/${folder}/${folder}
            FILES_MATCHING PATTERN "*.h"
            PATTERN "*_internal.h" EXCLUDE PATTERN "*_impl.h" EXCLUDE)
  endforeach()
  install(TARGETS mopad RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes/
          DESTINATION ${CMAKE_INSTALL_DATADIR}/OpenMoPAD/scenes
          FILES_MATCHING PATTERN "*.yaml")
  install(EXPORT OpenMoPADTargets NAMESPACE OpenMoPAD:: DESTINATION ${MOPAD_INSTALL_CMAKEDIR})
  configure_package_config_file(
    ${PROJECT_SOURCE_DIR}/cmake/OpenMoPADConfig.cmake.in
    ${PROJECT_BINARY_DIR}/OpenMoPADConfig.cmake
    INSTALL_DESTINATION ${MOPAD_INSTALL_CMAKEDIR}
    PATH_VARS CMAKE_INSTALL_DATADIR)
  # 0.x: a minor version may change the API, so only the same minor version is compatible.
  write_basic_package_version_file(
    ${PROJECT_BINARY_DIR}/OpenMoPADConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/OpenMoPADConfig.cmake
                ${PROJECT_BINARY_DIR}/OpenMoPADConfigVersion.cmake
          DESTINATION ${MOPAD_INSTALL_CMAKEDIR})
endfunction()
