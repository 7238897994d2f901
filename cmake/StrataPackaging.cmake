# The Debian package (deploy/): `cmake --build build/release --target package`, or
# `cpack --config build/release/CPackConfig.cmake`, makes build/release/packages/strata_<version>_<arch>.deb
# with the binary (/usr/bin/strata), the web app (/usr/share/strata/web, from web/CMakeLists.txt), the
# systemd unit, the default configuration (a conffile) and the maintainer scripts (deploy/debian/).
# The binary and the web app have their install() rules next to their targets; the rest is here.

# Absolute destinations: these files belong where systemd and the admin look for them, whatever the prefix.
install(FILES ${PROJECT_SOURCE_DIR}/deploy/strata.service DESTINATION /lib/systemd/system)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/strata.ini DESTINATION /etc/strata)
file(GLOB STRATA_DOCS ${PROJECT_SOURCE_DIR}/docs/*.md)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${STRATA_DOCS} ${PROJECT_SOURCE_DIR}/deploy/strata.example.ini
        DESTINATION share/doc/strata)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME strata)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
string(CONCAT CPACK_PACKAGE_DESCRIPTION
       "Registers 3D scans, builds a Multi-Level Surface map, plans and drives to goals, and serves it all "
       "to a browser and to scripts over HTTP and WebSocket. Runs as the strata.service systemd unit.")
set(CPACK_PACKAGE_CONTACT "Strata maintainers <strata@localhost>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_PACKAGE_DIRECTORY ${PROJECT_BINARY_DIR}/packages)
set(CPACK_STRIP_FILES TRUE)  # the debug info stays in the build tree
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # strata_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# The shared libraries' packages, found by dpkg-shlibdeps (dpkg-dev); adduser for the postinst.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "adduser")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    ${PROJECT_SOURCE_DIR}/deploy/debian/postinst ${PROJECT_SOURCE_DIR}/deploy/debian/prerm
    ${PROJECT_SOURCE_DIR}/deploy/debian/postrm ${PROJECT_SOURCE_DIR}/deploy/debian/conffiles)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION TRUE)
include(CPack)
