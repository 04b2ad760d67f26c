#!/usr/bin/env bash
# The paper's Table IV on this machine's OpenGL device: frames per second of
# vtkOpenGLAdaptiveVolumeMapper (Riemann h 0.5 / 0.1, coupled and decoupled
# eps 0.01 / 0.001) beside VTK's GPU mapper (h 0.5 / 0.1) on the same frames,
# Bonsai and BluntFin with their paper transfer functions, 800x600, median of
# FRAMES frames. Prints a Markdown table.
#   scripts/bench-gpu.sh [FRAMES] [WIDTHxHEIGHT]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
data="$root/../shared/data"
render="$root/build/bin/avos-render"
frames="${1:-3}"
size="${2:-800x600}"

declare -A volume=(
  [Bonsai]="$data/volumes/bonsai_zfp.vti --tf $data/tf/Bonsai.1.256x256x256.tf1d"
  [BluntFin]="$data/volumes/BluntFin.1.256x128x64.raw --tf $data/tf/BluntFin.1.256x128x64.linear.tf1d"
)
methods=(
  "vtk-gpu --step 0.5" "vtk-gpu --step 0.1"
  "gpu-riemann --step 0.5" "gpu-riemann --step 0.1"
  "gpu-coupled --tolerance 0.01" "gpu-coupled --tolerance 0.001"
  "gpu-decoupled --tolerance 0.01" "gpu-decoupled --tolerance 0.001"
)

echo "$size, median (min) of $frames frames, VTK's opacity model"
echo
echo "| dataset | method | s per frame | frames per second |"
echo "|---|---|---|---|"
for name in Bonsai BluntFin; do
  for m in "${methods[@]}"; do
    # shellcheck disable=SC2086
    line=$(xvfb-run -a -s "-screen 0 1280x1024x24" "$render" ${volume[$name]} --opacity vtk \
      --size "$size" --frames "$frames" --method $m | grep "median")
    median=$(sed -n 's/.*median \([0-9.e-]*\) s, min \([0-9.e-]*\) s.*/\1/p' <<<"$line")
    min=$(sed -n 's/.*median \([0-9.e-]*\) s, min \([0-9.e-]*\) s.*/\2/p' <<<"$line")
    fps=$(python3 -c "print(f'{1.0 / $median:.2f}')")
    echo "| $name | ${m//--/} | $median ($min) | $fps |"
  done
done
