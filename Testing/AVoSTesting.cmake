# Test harness shared by every AVoS module.
#
# - AVOS_SHARED_DATA_DIR: the real volumes and transfer functions (../shared/data
#   beside the source tree). Tests that need them skip (exit code 125) when absent.
# - Baselines are plain PNG files in <module>/Testing/Data/Baseline; ExternalData
#   only needs a local object store to accept them.
# - Python tests run with VTK's vtkpython (Debian ships VTK 9.1's as vtkpython-9.0
#   and defines no VTK::vtkpython target), with the build's `avos` package on
#   PYTHONPATH.

set(AVOS_SHARED_DATA_DIR "${CMAKE_CURRENT_SOURCE_DIR}/../shared/data"
  CACHE PATH "Folder with the shared volumes/ and tf/ used by tests and benchmarks")
get_filename_component(AVOS_SHARED_DATA_DIR "${AVOS_SHARED_DATA_DIR}" ABSOLUTE)

if (NOT BUILD_TESTING)
  return ()
endif ()

set(ExternalData_OBJECT_STORES "${CMAKE_BINARY_DIR}/ExternalData/Objects")

if (NOT TARGET VTK::vtkpython)
  find_program(AVOS_VTKPYTHON NAMES vtkpython vtkpython-9.1 vtkpython-9.0
    DOC "VTK's Python interpreter, used to run the Python tests")
  if (AVOS_VTKPYTHON)
    add_executable(VTK::vtkpython IMPORTED)
    set_target_properties(VTK::vtkpython PROPERTIES IMPORTED_LOCATION "${AVOS_VTKPYTHON}")
  endif ()
endif ()

set(AVOS_PYTHONPATH "${CMAKE_BINARY_DIR}/${AVOS_PYTHON_SITE_PACKAGES}")

# avos_add_python_tests(<test.py[,NO_VALID]>...): one test per script, labelled `python`,
# run by vtkpython with the build's `avos` package importable. The scripts use
# vtkmodules.test.Testing, which reads -D (shared data) and -V (baseline).
function (avos_add_python_tests)
  if (NOT TARGET VTK::vtkpython OR NOT AVOS_WRAP_PYTHON)
    return ()
  endif ()
  vtk_add_test_python(JUST_VALID ${ARGN})
  foreach (script IN LISTS ARGN)
    get_filename_component(name "${script}" NAME_WE)
    set(test "${_vtk_build_test}Python-${name}")
    set_property(TEST "${test}" APPEND PROPERTY LABELS python)
    set_property(TEST "${test}" APPEND PROPERTY ENVIRONMENT "PYTHONPATH=${AVOS_PYTHONPATH}")
  endforeach ()
endfunction ()

# avos_test_cxx_executable(<exe> <tests-var> [options]): vtk_test_cxx_executable
# with floating-point exceptions off (Mesa's llvmpipe raises SIGFPE while
# creating a window) and the shared test helpers on the include path.
set(AVOS_TESTING_INCLUDE_DIR "${CMAKE_CURRENT_LIST_DIR}/Cxx")
macro (avos_test_cxx_executable exe tests)
  vtk_test_cxx_executable(${exe} ${tests} DISABLE_FLOATING_POINT_EXCEPTIONS ${ARGN})
  if (TARGET ${exe})
    target_include_directories(${exe} PRIVATE "${AVOS_TESTING_INCLUDE_DIR}")
    target_link_libraries(${exe} PRIVATE avos_warnings)
  endif ()
endmacro ()

# avos_label_cxx_tests(<label> <Test.cxx>...): adds a category label to C++
# tests of the current module: `core` (no window) or `rendering` (image tests).
function (avos_label_cxx_tests label)
  foreach (source IN LISTS ARGN)
    get_filename_component(name "${source}" NAME_WE)
    set_property(TEST "${_vtk_build_test}Cxx-${name}" APPEND PROPERTY LABELS "${label}")
  endforeach ()
endfunction ()
