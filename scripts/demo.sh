#!/usr/bin/env bash
# Command 1: installs what is needed, builds, and runs the main job: avos-render
# on Bonsai with the paper's transfer function (../shared/data), the
# piecewise adaptive method at eps = 0.001 (every channel of every pixel
# within 0.001), and VTK's fixed-point mapper on the same frame for
# comparison. Without ../shared/data, the Python example renders the analytic
# sphere instead. Writes images and JSON reports to out/; extra arguments go
# to avos-render (e.g. --size 400x300 --azimuth 30).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${AVOS_BUILD_DIR:-$root/build}"
data="$root/../shared/data"
out="$root/out"

"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
mkdir -p "$out"

headless=(xvfb-run -a -s "-screen 0 1280x1024x24 -noreset")
if [[ -f "$data/volumes/bonsai_zfp.vti" ]]; then
  scene=("$data/volumes/bonsai_zfp.vti" --tf "$data/tf/Bonsai.1.256x256x256.linear.tf1d")
  "${headless[@]}" "$build/bin/avos-render" "${scene[@]}" --method piecewise --tolerance 0.001 \
    --output "$out/volume.png" --report "$out/report.json" "$@"
  "${headless[@]}" "$build/bin/avos-render" "${scene[@]}" --method piecewise --tolerance 0.001 \
    --output "$out/volume.exr" "$@" > /dev/null
  "${headless[@]}" "$build/bin/avos-render" "${scene[@]}" --method vtk-fixed-point --step 0.5 \
    --output "$out/vtk-fixed-point.png" --report "$out/vtk-fixed-point.json" "$@"
else
  PYTHONPATH="$build/python" "${headless[@]}" \
    /usr/bin/python3 "$root/Examples/Python/render_volume.py" --output "$out"
fi
echo "Wrote $(ls "$out" | tr '\n' ' ')to $out"
