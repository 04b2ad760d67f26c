#!/usr/bin/env bash
# Builds AVoS with sanitizers in build-<mode>[-clang]/ and runs the test suite there:
#   scripts/test-sanitizers.sh address [--clang]   AddressSanitizer + UndefinedBehaviorSanitizer, every test
#   scripts/test-sanitizers.sh thread [--clang]    ThreadSanitizer, the multithreaded paths
# With gcc (the default) or Debian's clang-16 (--clang, installed if absent).
# Any report fails the run (the sanitizers abort on their first finding).
# Extra arguments go to ctest. Not part of scripts/test.sh: the sanitized
# build and run take several times as long.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mode="${1:-address}"
shift || true
compiler=gcc
if [ "${1:-}" = --clang ]; then
  compiler=clang
  shift
fi
case "$mode" in
  address) sanitize="address,undefined"; runtime=libasan.so; clang_runtime=asan ;;
  thread) sanitize="thread"; runtime=libtsan.so; clang_runtime=tsan ;;
  *) echo "usage: $0 address|thread [--clang] [ctest arguments]" >&2; exit 2 ;;
esac
build="$root/build-$mode"
compilers=()
if [ "$compiler" = clang ]; then
  build="$build-clang"
  if ! command -v clang++-16 >/dev/null ||
    [ ! -e "/usr/lib/llvm-16/lib/clang/16/lib/linux/libclang_rt.$clang_runtime-x86_64.so" ]; then
    SUDO=""; if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
    $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      clang-16 libclang-rt-16-dev
  fi
  compilers=(-DCMAKE_C_COMPILER=clang-16 -DCMAKE_CXX_COMPILER=clang++-16)
fi

"$root/scripts/install-deps.sh"
cmake -S "$root" -B "$build" "${compilers[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DAVOS_SANITIZE="$sanitize" \
  -DPython3_EXECUTABLE=/usr/bin/python3 -DAVOS_SHARED_DATA_DIR="$root/../shared/data" >/dev/null
cmake --build "$build" --parallel "$(nproc)"

# Leaks: VTK and Python keep allocations to exit by design; our objects are
# reference counted through VTK. Python loads our sanitized libraries into an
# unsanitized interpreter: the runtime is preloaded for the tests only (not
# for the X server).
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$root/Testing/tsan.supp"
# ThreadSanitizer sees synchronisation only through instrumented code and the
# pthread calls it intercepts: TBB (vtkSMPTools' default backend here) is not
# instrumented, so every hand-over between its workers and the calling thread
# would be reported as a race. VTK's std::thread backend runs the same
# functors on the same tiles with synchronisation ThreadSanitizer can see.
if [ "$mode" = thread ]; then
  export VTK_SMP_BACKEND_IN_USE=STDThread
fi
if [ "$compiler" = clang ]; then
  preload="/usr/lib/llvm-16/lib/clang/16/lib/linux/libclang_rt.$clang_runtime-x86_64.so"
else
  preload="$(gcc -print-file-name="$runtime")"
fi
cd "$build"
# The install test builds a consumer against the (sanitized) install with
# the plain compiler: not a sanitizer check.
labels=(-LE install)
if [ "$mode" = thread ]; then
  # The threaded paths: the mapper's tiles, Volume on Surface, decimation.
  labels+=(-L "rendering|vos|decimation")
fi
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
  env LD_PRELOAD="$preload" ctest --output-on-failure --timeout 3000 -j "$(nproc)" \
  "${labels[@]}" "$@"
