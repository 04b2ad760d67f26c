# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DPYTHON=...
#   -DSITE_PACKAGES=... -DLIBDIR=... -DDATA_DIR=... -P TestInstall.cmake
#
# Installs the build into WORK_DIR/prefix and uses it from outside: the
# examples (Examples/Cxx) configured and built against it with
# find_package(AVoS) and run, the private headers checked absent, and the
# installed `avos` Python package imported, its libraries from the prefix.
foreach (var BUILD_DIR SOURCE_DIR WORK_DIR PYTHON SITE_PACKAGES LIBDIR DATA_DIR)
  if (NOT DEFINED ${var})
    message(FATAL_ERROR "TestInstall.cmake needs -D${var}=...")
  endif ()
endforeach ()

function (run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if (NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result}):\n${out}\n${err}")
  endif ()
  message(STATUS "${what}: ok")
  set(output "${out}" PARENT_SCOPE)
endfunction ()

set(prefix "${WORK_DIR}/prefix")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

run("install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}")

# Public headers only.
foreach (header vtkAdaptiveVolumeMapper.h vtkVolumeOnSurfaceFilter.h avosVersion.h
    avos/numerics/PiecewiseIntegrator.h)
  if (NOT EXISTS "${prefix}/include/avos/${header}" AND NOT EXISTS "${prefix}/include/${header}")
    message(FATAL_ERROR "public header ${header} was not installed")
  endif ()
endforeach ()
file(GLOB_RECURSE private RELATIVE "${prefix}" "${prefix}/include/avos*.h" "${prefix}/include/*/avos*.h")
list(FILTER private EXCLUDE REGEX "avosVersion.h$|Module.h$")
file(GLOB_RECURSE engine RELATIVE "${prefix}" "${prefix}/include/avos/engine/*")
if (private OR engine)
  message(FATAL_ERROR "private headers installed: ${private} ${engine}")
endif ()

# A C++ consumer: the examples, against the prefix only.
run("configure the examples against the install" "${CMAKE_COMMAND}"
  -S "${SOURCE_DIR}/Examples/Cxx" -B "${WORK_DIR}/examples"
  "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_BUILD_TYPE=Release)
run("build the examples" "${CMAKE_COMMAND}" --build "${WORK_DIR}/examples" --parallel 2)
run("run the pipeline example" "${WORK_DIR}/examples/avos-example-pipeline"
  "${WORK_DIR}/pipeline.png")
if (NOT output MATCHES "AVoS [0-9.]+: [1-9][0-9]* rays")
  message(FATAL_ERROR "unexpected output of the pipeline example: ${output}")
endif ()
set(volume "${DATA_DIR}/volumes/Neghip.1.64x64x64.raw")
if (EXISTS "${volume}")
  run("run the isosurface example" "${WORK_DIR}/examples/avos-example-isosurface"
    "${volume}" 60 0.5 "${WORK_DIR}/neghip.vtp")
endif ()
# The examples link the installed libraries, not the build's.
file(READ "${WORK_DIR}/examples/CMakeCache.txt" cache)
if (NOT cache MATCHES "AVoS_DIR:PATH=${prefix}/")
  message(FATAL_ERROR "the examples did not find AVoS in ${prefix}")
endif ()

# Python: the installed package, from a folder outside the build.
set(script [=[
import os, sys
import avos
prefix = os.path.realpath(sys.argv[1])
for module in (avos, avos.avosIO, avos.avosRenderingAdaptiveVolume):
    assert os.path.realpath(module.__file__).startswith(prefix), module.__file__
source = avos.vtkAnalyticVolumeSource()
source.Update()
assert source.GetOutput().GetNumberOfPoints() > 0
mapper = avos.vtkAdaptiveVolumeMapper()
mapper.SetIntegrationMethodToPiecewiseAdaptive()
print("import avos", avos.__version__, "from", os.path.dirname(avos.__file__))
]=])
file(WRITE "${WORK_DIR}/use_avos.py" "${script}")
run("import avos from the install" "${CMAKE_COMMAND}" -E chdir "${WORK_DIR}"
  "${CMAKE_COMMAND}" -E env --unset=LD_LIBRARY_PATH "PYTHONPATH=${prefix}/${SITE_PACKAGES}"
  "${PYTHON}" "${WORK_DIR}/use_avos.py" "${prefix}")
message(STATUS "${output}")
