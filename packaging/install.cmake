# Install rules and the Debian package (docs/wall.md, "Installing on a display machine"):
#   cmake --build build && (cd build && cpack)   ->   build/glcast_VERSION_amd64.deb
# The glcast command goes to bin/, the shim to LIBDIR/glcast/ (found from the command by the
# relative path in GLCAST_SHIM_FROM_BIN), the systemd unit of a display machine's tiles to
# lib/systemd/system/, display configs and docs to share/.

set(GLCAST_BIN ${CMAKE_INSTALL_FULL_BINDIR}/glcast)
set(GLCAST_DOCDIR ${CMAKE_INSTALL_FULL_DOCDIR})
configure_file(${CMAKE_SOURCE_DIR}/packaging/systemd/glcast-slave@.service.in
               ${CMAKE_BINARY_DIR}/packaging/glcast-slave@.service @ONLY)
# The same unit for the tests, running the build tree's glcast (tests/e2e/wall_machines_test.py).
set(GLCAST_BIN $<TARGET_FILE:glcast-cli>)
configure_file(${CMAKE_SOURCE_DIR}/packaging/systemd/glcast-slave@.service.in
               ${CMAKE_BINARY_DIR}/packaging/test/glcast-slave@.service.in @ONLY)
file(GENERATE OUTPUT ${CMAKE_BINARY_DIR}/packaging/test/glcast-slave@.service
     INPUT ${CMAKE_BINARY_DIR}/packaging/test/glcast-slave@.service.in)

install(TARGETS glcast-cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS glcast LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/glcast)
install(FILES ${CMAKE_BINARY_DIR}/packaging/glcast-slave@.service DESTINATION lib/systemd/system)
file(GLOB _display_configs ${CMAKE_SOURCE_DIR}/display_configs/*.json)
install(FILES ${_display_configs} DESTINATION ${CMAKE_INSTALL_DATADIR}/glcast/display_configs)
file(GLOB _docs ${CMAKE_SOURCE_DIR}/docs/*.md)
install(FILES ${_docs} ${CMAKE_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
# The licence (LICENSE, MIT) in Debian's machine-readable copyright format, where Debian keeps it.
install(FILES ${CMAKE_SOURCE_DIR}/packaging/copyright DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${CMAKE_SOURCE_DIR}/packaging/glcast.bash-completion DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions
        RENAME glcast)
# Manual pages, glcast(1) and glcast-COMMAND(1), made by help2man from each command's --help.
find_program(HELP2MAN help2man)
if(HELP2MAN)
  set(_man ${CMAKE_BINARY_DIR}/man)
  add_custom_command(OUTPUT ${_man}/glcast.1.gz
                     COMMAND sh ${CMAKE_SOURCE_DIR}/packaging/make_manpages.sh $<TARGET_FILE:glcast-cli> ${_man}
                             ${PROJECT_VERSION}
                     DEPENDS glcast-cli ${CMAKE_SOURCE_DIR}/packaging/make_manpages.sh
                     COMMENT "Manual pages from glcast's --help (help2man)")
  add_custom_target(manpages ALL DEPENDS ${_man}/glcast.1.gz)
  install(DIRECTORY ${_man}/ DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 FILES_MATCHING PATTERN "*.1.gz")
else()
  message(WARNING "help2man is missing (scripts/setup.sh installs it): the package will have no manual pages")
endif()
# A native package's changelog, where Debian keeps it.
configure_file(${CMAKE_SOURCE_DIR}/packaging/debian/changelog.in ${CMAKE_BINARY_DIR}/packaging/changelog @ONLY)
add_custom_command(OUTPUT ${CMAKE_BINARY_DIR}/packaging/changelog.gz
                   COMMAND gzip -9n < ${CMAKE_BINARY_DIR}/packaging/changelog > ${CMAKE_BINARY_DIR}/packaging/changelog.gz
                   DEPENDS ${CMAKE_BINARY_DIR}/packaging/changelog)
add_custom_target(debian_changelog ALL DEPENDS ${CMAKE_BINARY_DIR}/packaging/changelog.gz)
install(FILES ${CMAKE_BINARY_DIR}/packaging/changelog.gz DESTINATION ${CMAKE_INSTALL_DOCDIR})

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME glcast)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "glcast developers <glcast@glcast.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "unmodified OpenGL programs on tiled and curved display walls")
# (lines of at most 80 characters: Debian's policy for the extended description)
set(CPACK_PACKAGE_DESCRIPTION "A preloaded shim publishes every GL call of a program with its reply;\n\
slaves on display machines replay them per tile, over ZeroMQ with CURVE,\n\
and add falling snow, snow cover and soft shadows.")
set(CPACK_STRIP_FILES ON)
set(CPACK_PACKAGING_INSTALL_PREFIX ${CMAKE_INSTALL_PREFIX})
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # glcast_VERSION_amd64.deb
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
# The linked libraries come from dpkg-shlibdeps; the ones the slave's backends and the shim open
# at run time (dlopen) are named here.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libegl1, libgl1, libosmesa6, libgl1-mesa-dri, libglx-mesa0, libegl-mesa0")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "xvfb, mesa-utils")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${CMAKE_SOURCE_DIR}/packaging/debian/postinst)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
