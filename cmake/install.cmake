# What `cmake --install` puts under the prefix, and the package files that let
# other projects find it:
#   bin/osplint
#   include/osplint/{diagnostic.h,osplint.h,osplint_c.h}
#   <libdir>/libosplint.so.* and libosplint.a
#   <libdir>/cmake/osplint/   find_package(osplint): osplint::osplint, osplint::osplint_static
#   <libdir>/pkgconfig/osplint.pc
#   share/doc/osplint/        README, LICENSE, the documentation, the rule pages, the examples
#   share/man/man1/, bash and zsh completions: docs/man/*.1, completions/{bash,zsh}/* when the tree has them
# Included from CMakeLists.txt when OSPLINT_INSTALL is on.
include(CMakePackageConfigHelpers)

set(OSPLINT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/osplint)

install(TARGETS osplint RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS osplint_shared osplint_static EXPORT osplintTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        PUBLIC_HEADER DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/osplint)
install(EXPORT osplintTargets NAMESPACE osplint:: DESTINATION ${OSPLINT_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/osplintConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/osplintConfig.cmake
                              INSTALL_DESTINATION ${OSPLINT_CMAKE_DIR})
# 0.x: a new minor version may change the interface.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/osplintConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/osplintConfig.cmake ${PROJECT_BINARY_DIR}/osplintConfigVersion.cmake
        DESTINATION ${OSPLINT_CMAKE_DIR})

# osplint.pc finds the prefix from where it lies (${pcfiledir}), so it stays
# right when the prefix is chosen at install time (cmake --install --prefix).
set(OSPLINT_PC_PREFIX "\${pcfiledir}/..")
string(REPLACE "/" ";" libdir_parts "${CMAKE_INSTALL_LIBDIR}")
foreach(part ${libdir_parts})
  string(APPEND OSPLINT_PC_PREFIX "/..")
endforeach()
configure_file(${PROJECT_SOURCE_DIR}/cmake/osplint.pc.in ${PROJECT_BINARY_DIR}/osplint.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/osplint.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}
        FILES_MATCHING PATTERN "*.md" PATTERN "*.svg" PATTERN "*.png" PATTERN "man" EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples DESTINATION ${CMAKE_INSTALL_DOCDIR})
# The JSON Schemas of osplint.toml and the catalog, for editors (#:schema).
install(FILES ${PROJECT_SOURCE_DIR}/schema/osplint.schema.json ${PROJECT_SOURCE_DIR}/schema/catalog.schema.json
        DESTINATION ${CMAKE_INSTALL_DATADIR}/osplint/schema)
# Manual pages and shell completions, where the tree has them.
file(GLOB OSPLINT_MAN_PAGES ${PROJECT_SOURCE_DIR}/docs/man/*.1)
if(OSPLINT_MAN_PAGES)
  install(FILES ${OSPLINT_MAN_PAGES} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endif()
foreach(shell bash zsh)
  file(GLOB completions ${PROJECT_SOURCE_DIR}/completions/${shell}/*)
  if(completions AND shell STREQUAL "bash")
    install(FILES ${completions} DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions)
  elseif(completions)
    install(FILES ${completions} DESTINATION ${CMAKE_INSTALL_DATADIR}/zsh/vendor-completions)
  endif()
endforeach()

include(${PROJECT_SOURCE_DIR}/cmake/package.cmake)
