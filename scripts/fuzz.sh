#!/usr/bin/env bash
# Runs each fuzz target under libFuzzer for SECONDS (default 60), with
# AddressSanitizer and UndefinedBehaviorSanitizer; exits non-zero on the first
# crash, leaving the crashing input in build-fuzz/<target>/ (make it a file of
# the target's corpus: its replay test then keeps it fixed).
#   scripts/fuzz.sh [SECONDS]
# Targets: the numerical core's integrators (Modules/Numerics/Testing/Fuzz).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
out="$root/build-fuzz"

"$root/scripts/install-deps.sh"
command -v clang++ >/dev/null || {
  SUDO=""; if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends clang
}

run() { # name source corpus
  local name="$1" source="$2" corpus="$3"
  mkdir -p "$out/$name/corpus"
  clang++ -std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
    -I "$root/Modules/Numerics/include" "$source" -o "$out/$name/fuzzer"
  cp -n "$corpus"/* "$out/$name/corpus/" 2>/dev/null || true
  echo "== $name: $seconds s"
  (cd "$out/$name" && ./fuzzer -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 corpus)
}

run integrators "$root/Modules/Numerics/Testing/Fuzz/FuzzIntegrators.cxx" \
  "$root/Modules/Numerics/Testing/Fuzz/corpus"
