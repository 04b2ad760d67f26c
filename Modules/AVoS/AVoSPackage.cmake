# The installed CMake package (find_package(AVoS)), its test from outside the
# build tree, and the Debian package (cpack -G DEB).
include(CMakePackageConfigHelpers)

set(avos_cmake_destination "${CMAKE_INSTALL_LIBDIR}/cmake/avos")

# The VTK modules that the AVoS modules' public interfaces name (their public
# DEPENDS): what a consumer's find_package(AVoS) must find of VTK.
set(AVOS_VTK_PUBLIC_COMPONENTS "")
foreach (avos_module IN LISTS avos_modules)
  get_property(avos_depends GLOBAL PROPERTY "_vtk_module_${avos_module}_depends")
  foreach (avos_depend IN LISTS avos_depends)
    if (avos_depend MATCHES "^VTK::(.+)$")
      list(APPEND AVOS_VTK_PUBLIC_COMPONENTS "${CMAKE_MATCH_1}")
    endif ()
  endforeach ()
endforeach ()
list(REMOVE_DUPLICATES AVOS_VTK_PUBLIC_COMPONENTS)
list(SORT AVOS_VTK_PUBLIC_COMPONENTS)
string(REPLACE ";" " " AVOS_VTK_PUBLIC_COMPONENTS "${AVOS_VTK_PUBLIC_COMPONENTS}")
set(AVOS_VTK_VERSION "${VTK_VERSION_MAJOR}.${VTK_VERSION_MINOR}")

configure_package_config_file(
  "${CMAKE_CURRENT_LIST_DIR}/AVoSConfig.cmake.in"
  "${CMAKE_BINARY_DIR}/${avos_cmake_destination}/AVoSConfig.cmake"
  INSTALL_DESTINATION "${avos_cmake_destination}"
  PATH_VARS AVOS_PYTHON_SITE_PACKAGES)
# 0.x: a minor version may break the interface.
write_basic_package_version_file(
  "${CMAKE_BINARY_DIR}/${avos_cmake_destination}/AVoSConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES
  "${CMAKE_BINARY_DIR}/${avos_cmake_destination}/AVoSConfig.cmake"
  "${CMAKE_BINARY_DIR}/${avos_cmake_destination}/AVoSConfigVersion.cmake"
  DESTINATION "${avos_cmake_destination}")

if (BUILD_TESTING)
  # Installs the build into a fresh prefix and uses it as a stranger would:
  # the examples configured and built against it with find_package(AVoS) and
  # run, and `import avos` from the installed package.
  add_test(NAME AVoS::Install
    COMMAND "${CMAKE_COMMAND}"
      "-DBUILD_DIR=${CMAKE_BINARY_DIR}"
      "-DSOURCE_DIR=${CMAKE_SOURCE_DIR}"
      "-DWORK_DIR=${CMAKE_BINARY_DIR}/Testing/Temporary/install"
      "-DPYTHON=${Python3_EXECUTABLE}"
      "-DSITE_PACKAGES=${AVOS_PYTHON_SITE_PACKAGES}"
      "-DLIBDIR=${CMAKE_INSTALL_LIBDIR}"
      "-DDATA_DIR=${AVOS_SHARED_DATA_DIR}"
      -P "${CMAKE_SOURCE_DIR}/Testing/Install/TestInstall.cmake")
  # Alone: it builds the examples on every core.
  set_tests_properties(AVoS::Install PROPERTIES
    LABELS "install" RUN_SERIAL TRUE TIMEOUT 900)
endif ()

# The Debian package: `cpack -G DEB` in a build configured with
# CMAKE_INSTALL_PREFIX=/usr (scripts/package.sh).
set(CPACK_PACKAGE_NAME "avos")
set(CPACK_PACKAGE_VENDOR "AVoS")
set(CPACK_PACKAGE_CONTACT "AVoS developers <avos@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGING_INSTALL_PREFIX "${CMAKE_INSTALL_PREFIX}")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION "science")
# The shared libraries it links (VTK, OpenMesh, OpenImageIO, Highway, ...)
# from dpkg-shlibdeps; the Python package imports VTK's.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3, python3-vtk9")
# find_package(AVoS) finds VTK's and GLM's CMake packages.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libvtk9-dev, libglm-dev")
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
include(CPack)
