# CPack: Debian packages of the install rules' components (scripts/package.sh,
# docs/building.md), one package per component:
#
#   libhairscatter-dev    component dev: headers, CMake package, pkg-config file (all)
#   python3-hairscatter   component python: the Python module, when it is built
#
# Included from the top-level CMakeLists.txt after the install rules.

set(HAIRSCATTER_PACKAGE_MAINTAINER "The hairscatter authors" CACHE STRING
    "Maintainer field of the DEB packages (Name <email>)")

# Debian wants the licence as /usr/share/doc/<package>/copyright. EXCLUDE_FROM_ALL keeps it
# out of a plain `cmake --install`; CPack installs component by component, which includes it.
install(FILES "${PROJECT_SOURCE_DIR}/LICENSE" DESTINATION "${CMAKE_INSTALL_DATADIR}/doc/libhairscatter-dev"
        RENAME copyright COMPONENT dev EXCLUDE_FROM_ALL)
set(CPACK_COMPONENTS_ALL dev)
if(HAIRSCATTER_BUILD_PYTHON)
  install(FILES "${PROJECT_SOURCE_DIR}/LICENSE" DESTINATION "${CMAKE_INSTALL_DATADIR}/doc/python3-hairscatter"
          RENAME copyright COMPONENT python EXCLUDE_FROM_ALL)
  list(APPEND CPACK_COMPONENTS_ALL python)
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_PACKAGE_VENDOR "The hairscatter authors")
set(CPACK_PACKAGE_CONTACT "${HAIRSCATTER_PACKAGE_MAINTAINER}")
set(CPACK_RESOURCE_FILE_LICENSE "${PROJECT_SOURCE_DIR}/LICENSE")
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# Each package's Description starts with its own summary line (the first line of
# CPACK_DEBIAN_<COMPONENT>_DESCRIPTION); a non-empty common summary would be put above both.
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "")

set(CPACK_DEBIAN_DEV_PACKAGE_NAME libhairscatter-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_ARCHITECTURE all)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS libglm-dev)
set(CPACK_DEBIAN_DEV_DESCRIPTION
    "physically based hair fiber scattering (C++17 headers)
hairscatter is a header-only C++17 library of hair fiber scattering models
(Marschner, Chiang, Huang, far field, tabulated) with eval, pdf and sample, and
dual scattering. This package holds the headers, the CMake package
(find_package(hairscatter)) and the pkg-config file.")

# The module is built for one interpreter (its file is _core.cpython-3XY-<triplet>.so), so
# the package accepts that Python 3 only, as Debian's own python3-* extension packages do;
# libc and libstdc++ come from the module's ELF dependencies (dpkg-shlibdeps, in dpkg-dev).
if(HAIRSCATTER_BUILD_PYTHON)
  if(NOT HAIRSCATTER_PYTHON_VERSION MATCHES "^3\\.([0-9]+)$")
    message(FATAL_ERROR "hairscatter: no Python 3 version for the DEB package (got '${HAIRSCATTER_PYTHON_VERSION}')")
  endif()
  math(EXPR _hairscatter_python_next "${CMAKE_MATCH_1} + 1")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-hairscatter)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
      "python3 (>= ${HAIRSCATTER_PYTHON_VERSION}~), python3 (<< 3.${_hairscatter_python_next}), python3-numpy")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SHLIBDEPS ON)
  set(CPACK_DEBIAN_PYTHON_DESCRIPTION
      "physically based hair fiber scattering (Python 3 module)
The Python module of hairscatter: every fiber model from keyword arguments, eval,
pdf, sample and albedo vectorised over numpy arrays in float32 or float64, the
colour and lobe controls, and dual-scattering tables.")
endif()

include(CPack)
