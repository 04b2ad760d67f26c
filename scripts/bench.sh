#!/usr/bin/env bash
# The full paper evaluation on this machine: builds, runs avos-bench on
# BluntFin, Bonsai, Engine and Foot at 800x600 (tens of minutes on 2 cores;
# nothing else should run meanwhile), and copies what docs/RESULTS.md cites
# (report, CSV, plots) into docs/bench/. Every image stays in out/bench/.
# Extra arguments go to avos-bench (e.g. --datasets Bonsai --frames 5).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${AVOS_BUILD_DIR:-$root/build}"
out="$root/out/bench"

"$root/scripts/build.sh"
rm -rf "$out"
# -noreset: see scripts/test.sh.
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$build/bin/avos-bench" \
  --data "$root/../shared/data" --output "$out" "$@"
mkdir -p "$root/docs/bench"
cp "$out"/report.md "$out"/*.csv "$out"/*.png "$root/docs/bench/"
echo "docs/bench/ updated from $out"
