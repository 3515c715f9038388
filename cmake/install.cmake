# Install rules, the CMake package (find_package(rangekit) -> rangekit::core, rangekit::sim,
# rangekit::uls, rangekit::ls5, rangekit::record, rangekit::hub), the pkg-config file and the
# Debian package (make package).

set(RANGEKIT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/rangekit)

install(TARGETS ${RANGEKIT_LIBRARIES} EXPORT rangekitTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/rangekit ${RANGEKIT_GENERATED_INCLUDE}/rangekit
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT development)
install(EXPORT rangekitTargets NAMESPACE rangekit:: DESTINATION ${RANGEKIT_CMAKE_DIR} COMPONENT development)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/rangekitConfig.cmake.in
  ${PROJECT_BINARY_DIR}/rangekitConfig.cmake INSTALL_DESTINATION ${RANGEKIT_CMAKE_DIR})
# 0.x: a minor version may break the API, so only the same minor is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rangekitConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/rangekitConfig.cmake ${PROJECT_BINARY_DIR}/rangekitConfigVersion.cmake
  DESTINATION ${RANGEKIT_CMAKE_DIR} COMPONENT development)

# Relocatable: the prefix is found from where the .pc file lies (the .deb installs under /usr).
file(RELATIVE_PATH RANGEKIT_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
configure_file(${PROJECT_SOURCE_DIR}/cmake/rangekit.pc.in ${PROJECT_BINARY_DIR}/rangekit.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/rangekit.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT development)

if(TARGET rangekit)
  install(TARGETS rangekit RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/packaging/rangekit.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/packaging/rangekit.bash-completion
    DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/bash-completion/completions RENAME rangekit COMPONENT runtime)
endif()
# The gateway service (docs/deploy.md): the systemd unit, the sample site file (a conffile)
# and the FTDI latency udev rule, commented out. Under the prefix /usr (the .deb) they go
# where systemd, udev and dpkg look; under any other prefix into PREFIX/share/rangekit,
# as samples, so that `cmake --install --prefix DIR` writes nothing outside DIR.
if(TARGET rangekit)
  install(CODE "set(RANGEKIT_PACKAGING_SOURCE \"${PROJECT_SOURCE_DIR}/packaging\")" COMPONENT runtime)
  install(CODE [[
    if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
      set(rangekit_unit_dir /lib/systemd/system)
      set(rangekit_udev_dir /lib/udev/rules.d)
      set(rangekit_config_dir /etc/rangekit)
    else()
      set(rangekit_unit_dir ${CMAKE_INSTALL_PREFIX}/share/rangekit/systemd)
      set(rangekit_udev_dir ${CMAKE_INSTALL_PREFIX}/share/rangekit/udev)
      set(rangekit_config_dir ${CMAKE_INSTALL_PREFIX}/share/rangekit)
    endif()
    file(INSTALL ${RANGEKIT_PACKAGING_SOURCE}/systemd/rangekit.service DESTINATION ${rangekit_unit_dir})
    file(INSTALL ${RANGEKIT_PACKAGING_SOURCE}/udev/99-rangekit-ftdi-latency.rules DESTINATION ${rangekit_udev_dir})
    file(INSTALL ${RANGEKIT_PACKAGING_SOURCE}/site.toml DESTINATION ${rangekit_config_dir})
  ]] COMPONENT runtime)
endif()
# The Wireshark dissector (docs/tap.md): Debian's Wireshark 4.0 loads every .lua in its global
# Lua plugin folder, /usr/lib/<multiarch>/wireshark/plugins (`tshark -G folders`), of any version.
if(TARGET rangekit)
  install(FILES ${PROJECT_SOURCE_DIR}/packaging/wireshark/rangekit.lua
    DESTINATION lib/${CMAKE_LIBRARY_ARCHITECTURE}/wireshark/plugins COMPONENT runtime)
endif()
file(GLOB RANGEKIT_DOCS ${PROJECT_SOURCE_DIR}/docs/*.md)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${RANGEKIT_DOCS} DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)

# make package: one .deb with the tool, the libraries, headers, docs, man page
# and completion. Its dependencies come from dpkg-shlibdeps on the binary plus
# the -dev packages a consumer of the static libraries needs.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME rangekit)
set(CPACK_PACKAGE_VENDOR rangekit)
set(CPACK_PACKAGE_CONTACT "rangekit maintainers <rangekit@users.noreply.github.com>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION electronics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "nlohmann-json3-dev, libtomlplusplus-dev, libsqlite3-dev, libboost1.81-dev, libssl-dev, libmosquitto-dev, libpq-dev")
if(TARGET _rangekit)
  # The Python package: built for this interpreter's version, and it hands out NumPy arrays.
  math(EXPR next_minor "${Python3_VERSION_MINOR} + 1")
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "${CPACK_DEBIAN_PACKAGE_DEPENDS}, python3 (>= ${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}), python3 (<< ${Python3_VERSION_MAJOR}.${next_minor}), python3-numpy")
endif()
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
# The service's user (postinst makes it with adduser, postrm's purge removes it), stopping
# on removal, and /etc/rangekit/site.toml kept across upgrades: CPack 3.25 lists no conffile itself.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${CPACK_DEBIAN_PACKAGE_DEPENDS}, adduser")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${PROJECT_SOURCE_DIR}/packaging/debian/conffiles
  ${PROJECT_SOURCE_DIR}/packaging/debian/postinst ${PROJECT_SOURCE_DIR}/packaging/debian/prerm
  ${PROJECT_SOURCE_DIR}/packaging/debian/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_STRIP_FILES ON)
include(CPack)
