# Fuzz targets (scripts/fuzz.sh).
#
# Each target is a file defining LLVMFuzzerTestOneInput. In a normal build it
# becomes a replay executable (Testing/Fuzz/FuzzReplayMain.cxx) and a test that
# runs it on the target's corpus: the seed inputs and every input that once
# found a defect. With AVOS_FUZZ=ON (Clang only) it links libFuzzer instead,
# and all of AVoS's code is instrumented for coverage and checked by
# AddressSanitizer and UndefinedBehaviorSanitizer; scripts/fuzz.sh then builds
# only the fuzz targets and the libraries they use.

option(AVOS_FUZZ "Build the fuzz targets with libFuzzer (Clang) instead of their replays" OFF)
if (AVOS_FUZZ)
  if (NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "AVOS_FUZZ needs Clang (libFuzzer); CMAKE_CXX_COMPILER is "
      "${CMAKE_CXX_COMPILER_ID}.")
  endif ()
  if (NOT AVOS_SANITIZE STREQUAL "address,undefined")
    message(FATAL_ERROR "AVOS_FUZZ needs AVOS_SANITIZE=address,undefined.")
  endif ()
  target_compile_options(avos_warnings INTERFACE -fsanitize=fuzzer-no-link)
endif ()

# avos_add_fuzz_target(<name> TEST <test name> SOURCE <file> CORPUS <folder>
#                      LIBRARIES <targets>... LABELS <labels>...)
function (avos_add_fuzz_target name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "TEST;SOURCE;CORPUS" "LIBRARIES;LABELS")
  set(target "avosFuzz${name}")
  add_executable(${target} "${arg_SOURCE}")
  target_link_libraries(${target} PRIVATE ${arg_LIBRARIES} avos_warnings)
  target_include_directories(${target} PRIVATE "${AVoS_SOURCE_DIR}/Testing/Fuzz")
  if (AVOS_FUZZ)
    target_link_options(${target} PRIVATE -fsanitize=fuzzer)
    return ()
  endif ()
  target_sources(${target} PRIVATE "${AVoS_SOURCE_DIR}/Testing/Fuzz/FuzzReplayMain.cxx")
  file(GLOB corpus CONFIGURE_DEPENDS "${arg_CORPUS}/*")
  add_test(NAME "${arg_TEST}" COMMAND ${target} ${corpus})
  set_tests_properties("${arg_TEST}" PROPERTIES LABELS "${arg_LABELS}")
endfunction ()
