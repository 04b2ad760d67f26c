#!/usr/bin/env bash
# Configures (once) and builds AVoS in build/ (or $AVOS_BUILD_DIR). Idempotent:
# an existing build is reused and only what changed is rebuilt.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${AVOS_BUILD_DIR:-$root/build}"

# Re-running the configure step on an existing build only regenerates what changed.
cmake -S "$root" -B "$build" \
  -DCMAKE_BUILD_TYPE=Release \
  -DPython3_EXECUTABLE=/usr/bin/python3 \
  -DAVOS_SHARED_DATA_DIR="$root/../shared/data" >/dev/null
cmake --build "$build" --parallel "$(nproc)"
