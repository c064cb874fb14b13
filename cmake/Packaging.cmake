# CPack: three Debian packages from the install components (`make package`, or `cpack` in a build
# directory):
#   lathectl           the program, data/materials.toml, the examples, lathectl(1), docs
#   lathectl-linuxcnc  the HAL modules, their (9) pages, the sample configuration,
#                      lathectl-linuxcnc-sim; Depends: linuxcnc-uspace, lathectl (= same version)
#   python3-lathectl   the Python package `import lathectl` (python/, when the module is built)
#                      under /usr/lib/python3/dist-packages; Depends: the python3 and numpy ABIs it
#                      was built for, lathectl (= same version) for the data and examples
# The lathectl-dev component (static library, headers, CMake package) is not packaged: the library
# is a static archive built with this project's flags and no stable ABI, for projects that build
# lathectl from source (`cmake --install` installs it for find_package(lathectl)).
# Shared-library dependencies come from dpkg-shlibdeps (dpkg-dev); binaries are stripped.
set(LATHECTL_PACKAGE_MAINTAINER
    "lathectl maintainers <maintainers@users.noreply.h-seed-a8f1b182.example>"
    CACHE STRING "Maintainer field of the .deb packages")
set(LATHECTL_PACKAGE_RELEASE 1 CACHE STRING "Debian revision of the .deb packages")

set(LATHECTL_DEB_SOURCE lathectl)
set(LATHECTL_DEB_VERSION ${PROJECT_VERSION}-${LATHECTL_PACKAGE_RELEASE})

# Changelog date: the commit's (reproducible), else now.
set(LATHECTL_CHANGELOG_DATE "")
if(GIT_FOUND AND NOT LATHECTL_GIT_COMMIT STREQUAL "unknown")
  execute_process(COMMAND ${GIT_EXECUTABLE} log -1 --format=%cD
                  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                  OUTPUT_VARIABLE LATHECTL_CHANGELOG_DATE OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
endif()
if(NOT LATHECTL_CHANGELOG_DATE)
  string(TIMESTAMP LATHECTL_CHANGELOG_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)
endif()

set(_pkgdir ${PROJECT_BINARY_DIR}/packaging)
configure_file(${PROJECT_SOURCE_DIR}/packaging/copyright ${_pkgdir}/copyright @ONLY)
configure_file(${PROJECT_SOURCE_DIR}/packaging/changelog.in ${_pkgdir}/changelog @ONLY)
add_custom_command(OUTPUT ${_pkgdir}/changelog.Debian.gz
  COMMAND ${LATHECTL_GZIP} -9nc ${_pkgdir}/changelog > ${_pkgdir}/changelog.Debian.gz
  DEPENDS ${_pkgdir}/changelog VERBATIM)
add_custom_target(deb_changelog ALL DEPENDS ${_pkgdir}/changelog.Debian.gz)

set(_packages lathectl)
if(TARGET lathectl_adaptive)
  list(APPEND _packages lathectl-linuxcnc)
endif()
if(TARGET _lathectl)
  list(APPEND _packages python3-lathectl)
endif()
foreach(pkg ${_packages})
  install(FILES ${_pkgdir}/copyright ${_pkgdir}/changelog.Debian.gz
          DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/${pkg} COMPONENT ${pkg})
endforeach()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME lathectl)
set(CPACK_PACKAGE_VENDOR "lathectl")
set(CPACK_PACKAGE_CONTACT "${LATHECTL_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_COMPONENTS_ALL ${_packages})
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # <package>_<version>-<release>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_RELEASE ${LATHECTL_PACKAGE_RELEASE})
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${LATHECTL_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SOURCE ${LATHECTL_DEB_SOURCE})

set(CPACK_DEBIAN_LATHECTL_PACKAGE_NAME lathectl)
set(CPACK_DEBIAN_LATHECTL_PACKAGE_SECTION science)
set(CPACK_COMPONENT_LATHECTL_DESCRIPTION
"adaptive lathe control: simulator and design calculators
lathectl implements the automatic and adaptive lathe control systems of five
engineering documents: real-time controllers that run the same code in
simulation and on a machine, plant models (hydraulic feed slides, copying
slides, cutting process, slender-part chatter, in-process gauging) to run them
closed-loop, and the documents' design formulas as calculators.
.
This package holds the lathectl command (run, check, demo, lobes, design), the
material library and the example scenarios, machines and NC programs. The
LinuxCNC realtime components are in lathectl-linuxcnc.")

set(CPACK_DEBIAN_LATHECTL-LINUXCNC_PACKAGE_NAME lathectl-linuxcnc)
set(CPACK_DEBIAN_LATHECTL-LINUXCNC_PACKAGE_SECTION electronics)
set(CPACK_DEBIAN_LATHECTL-LINUXCNC_PACKAGE_DEPENDS
    "linuxcnc-uspace, python3, lathectl (= ${LATHECTL_DEB_VERSION})")
# lathectl_publish's MQTT client (shop data out, docs/shop-data.md); its SHDR needs nothing.
set(CPACK_DEBIAN_LATHECTL-LINUXCNC_PACKAGE_RECOMMENDS "python3-paho-mqtt")
set(CPACK_DEBIAN_LATHECTL-LINUXCNC_PACKAGE_SUGGESTS "mosquitto")
set(CPACK_COMPONENT_LATHECTL-LINUXCNC_DESCRIPTION
"adaptive lathe control: LinuxCNC HAL components
Realtime HAL components for LinuxCNC (uspace) built from the same controller
code as the lathectl simulator: lathectl_adaptive (adaptive feed and cutting
speed control), lathectl_modfeed (chatter suppression by modulated feed), and
the simulated processes lathectl_plant and lathectl_chatter.
.
Also a sample configuration (sim/lathectl in LinuxCNC's configuration picker)
and lathectl-linuxcnc-sim, which runs an NC program headless on the simulated
lathe and records the HAL signals.")

# The extension module's ABIs, as Debian's own extension packages declare them (dh_python3,
# dh_numpy3): the python3 it was built for (cpython-311: >= 3.11~, << 3.12), and numpy's C ABI
# (numpy's headers compiled in: python3-numpy-abiN, with the oldest numpy of the same C API, from
# /usr/share/numpy3/versions).
if(TARGET _lathectl)
  set(_py "${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}")
  math(EXPR _py_next "${Python_VERSION_MINOR} + 1")
  set(_numpy_deps python3-numpy)
  if(EXISTS /usr/share/numpy3/versions)
    file(STRINGS /usr/share/numpy3/versions _abi REGEX "^abi ")
    file(STRINGS /usr/share/numpy3/versions _api_min REGEX "^api-min-version ")
    string(REGEX REPLACE "^abi +" "" _abi "${_abi}")
    string(REGEX REPLACE "^api-min-version +" "" _api_min "${_api_min}")
    if(_abi AND _api_min)
      set(_numpy_deps "python3-numpy (>= ${_api_min}), python3-numpy-abi${_abi}")
    endif()
  endif()
  if(_numpy_deps STREQUAL "python3-numpy")
    message(WARNING "/usr/share/numpy3/versions unreadable: python3-lathectl depends on any numpy")
  endif()
  set(CPACK_DEBIAN_PYTHON3-LATHECTL_PACKAGE_NAME python3-lathectl)
  set(CPACK_DEBIAN_PYTHON3-LATHECTL_PACKAGE_SECTION python)
  set(_python_deps "python3 (>= ${_py}~), python3 (<< ${Python_VERSION_MAJOR}.${_py_next})")
  set(CPACK_DEBIAN_PYTHON3-LATHECTL_PACKAGE_DEPENDS
      "${_python_deps}, ${_numpy_deps}, lathectl (= ${LATHECTL_DEB_VERSION})")
  # `lathectl sweep --scheduler`'s driver (lathectl.sweep_dask) and the workers of its cluster.
  set(CPACK_DEBIAN_PYTHON3-LATHECTL_PACKAGE_SUGGESTS "python3-distributed")
  set(CPACK_COMPONENT_PYTHON3-LATHECTL_DESCRIPTION
"adaptive lathe control: Python 3 package
The Python module lathectl, built from the same C++ as the lathectl program:
scenarios of the five lathe control systems run closed-loop (summaries and
channels as numpy arrays), stability lobes of a machine's modes or of a
measured frequency response (CSV or UFF58), modal fitting, the engineering
documents' design calculators, and the machine-side controller objects for
one's own loops.
.
It uses the material library and the examples of the lathectl package.")
endif()

include(CPack)
