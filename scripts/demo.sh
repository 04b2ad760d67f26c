#!/usr/bin/env bash
# Command 1: installs what is needed, builds, and runs the main job on the
# default dataset: Bonsai with the paper's transfer function when ../shared/data
# is present, else the analytic sphere. Writes images and a report to out/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${AVOS_BUILD_DIR:-$root/build}"
out="$root/out"

"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
mkdir -p "$out"

python_dir="$(find "$build/lib" -type d -name avos -path '*-packages/avos' | head -n 1)"
PYTHONPATH="$(dirname "$python_dir")" xvfb-run -a -s "-screen 0 1280x1024x24" \
  /usr/bin/python3 "$root/Examples/Python/render_volume.py" \
  --data "$root/../shared/data" --output "$out" "$@"
echo "Wrote $(ls "$out" | tr '\n' ' ')to $out"
