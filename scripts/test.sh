#!/usr/bin/env bash
# Command 2: installs what is needed, builds, and runs the whole test suite
# under a virtual X server. Exits non-zero on any failure.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${AVOS_BUILD_DIR:-$root/build}"

"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"

cd "$build"
# Rendering tests need an X display (Debian's VTK is GLX only): Mesa's
# llvmpipe renders on the CPU inside Xvfb. -noreset: by default the server
# resets when its last client leaves, and a window opened meanwhile fails
# ("bad X server connection"), which a tool that opens and closes windows
# one after another (avos-bench) meets at random.
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
  ctest --output-on-failure --timeout 1500 -j "$(nproc)" "$@"
