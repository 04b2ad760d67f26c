#!/usr/bin/env bash
# Runs each fuzz target under libFuzzer for SECONDS (default 60), with
# AddressSanitizer and UndefinedBehaviorSanitizer; exits non-zero on the first
# crash or timeout, leaving the input in build-fuzz/run/<target>/ (copy it
# into the target's corpus folder: its replay test then keeps it fixed).
#   scripts/fuzz.sh [SECONDS]
# Targets (Testing/AVoSFuzz.cmake): the numerical core's integrators, the
# .tf1d reader and the volvis .raw reader (name, scalar type, size, extent).
# Built with Debian's clang-16 and libFuzzer in build-fuzz/ (AVOS_FUZZ=ON).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
build="$root/build-fuzz"

"$root/scripts/install-deps.sh"
# libclang-rt-16-dev holds the fuzzer and sanitizer runtimes clang-16 links.
if ! command -v clang++-16 >/dev/null ||
  ! ls /usr/lib/llvm-16/lib/clang/16/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  SUDO=""; if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    clang-16 libfuzzer-16-dev libclang-rt-16-dev
fi

CC=clang-16 CXX=clang++-16 cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DAVOS_FUZZ=ON -DAVOS_SANITIZE=address,undefined -DAVOS_WRAP_PYTHON=OFF \
  -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build "$build" --parallel "$(nproc)" --target \
  avosFuzzIntegrators avosFuzzTransferFunction1DReader avosFuzzVolvisRawReader

export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
run() { # target corpus [extra seed folder]
  local name="$1" corpus="$2" extra="${3:-}"
  local dir="$build/run/$name"
  mkdir -p "$dir/corpus"
  cp -n "$corpus"/* "$dir/corpus/" 2>/dev/null || true
  echo "== $name: $seconds s"
  (cd "$dir" && "$build/bin/avosFuzz$name" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 corpus $extra)
}

run Integrators "$root/Modules/Numerics/Testing/Fuzz/corpus"
# The shared data's transfer functions are extra seeds (read, never copied).
tf="$root/../shared/data/tf"
run TransferFunction1DReader "$root/Modules/IO/Testing/Fuzz/corpus-tf1d" \
  "$([ -d "$tf" ] && echo "$tf")"
run VolvisRawReader "$root/Modules/IO/Testing/Fuzz/corpus-raw"
