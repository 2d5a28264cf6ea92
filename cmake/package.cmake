# The Debian package (cpack -G DEB in the build directory): everything
# `cmake --install` installs, under /usr, for Debian 12 (bookworm).
# Included from cmake/install.cmake.
set(CPACK_PACKAGE_NAME osplint)
set(CPACK_PACKAGE_VENDOR "osplint")
set(CPACK_PACKAGE_CONTACT "osplint <https://github.com/osplint/osplint/issues>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "static analyzer for Okuma OSP part programs")
string(CONCAT CPACK_PACKAGE_DESCRIPTION
  "osplint reads .MIN/.SSB/.SUB/.LIB/.NC part programs for Okuma OSP controls, follows the modal\n"
  "state through them, and checks every call of the custom cycle macros and the standard fixed\n"
  "cycles against the manuals. It ships the osplint command (check, explain, trace, the language\n"
  "server) and the C and C++ library libosplint with its headers, CMake package and pkg-config file.")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_HOMEPAGE_URL ${PROJECT_HOMEPAGE_URL})
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)

set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # osplint_VERSION_ARCH.deb
set(CPACK_DEBIAN_PACKAGE_SECTION devel)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# The run-time libraries the command and libosplint.so link, as Debian 12
# names them (tests/scripts/package_deb.sh checks every NEEDED entry against
# this list).
set(CPACK_DEBIAN_PACKAGE_DEPENDS
    "libc6 (>= 2.36), libgcc-s1 (>= 12), libstdc++6 (>= 12), libfmt9 (>= 9.1.0), libtree-sitter0 (>= 0.20.7), libtomlplusplus3 (>= 3.3.0)")
if(OSPLINT_SANITIZE)
  # A sanitizer build (for the tests) links the sanitizers' run-time libraries.
  string(APPEND CPACK_DEBIAN_PACKAGE_DEPENDS ", libasan8, libubsan1")
endif()
# A shlibs file for libosplint.so, and the ldconfig trigger with it.
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY ">=")
# Linking libosplint.a needs the development files of its dependencies.
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libfmt-dev, libtree-sitter-dev, libtomlplusplus-dev, pkg-config")

include(CPack)
