#!/usr/bin/env bash
# vtkOpenGLAdaptiveVolumeMapper beside VTK's GPU mapper on the same frames of
# this machine's OpenGL device: the paper's Table IV (Riemann h 0.5 / 0.1,
# coupled and decoupled eps 0.01 / 0.001) and the piecewise method (eps
# 0.01 / 0.001), each with its time, its ratio to VTK's GPU mapper at h 0.5
# and its error against the CPU mapper's exact reference (the largest over
# RGBA, and the largest over RGBA of the percentage of pixels above 0.01 and
# 0.001). VTK's opacity model, the datasets' paper transfer functions, the
# default view and bench-engine.py's oblique one, median of FRAMES frames.
# Prints a Markdown table; writes the references into the current folder.
#   scripts/bench-gpu.sh [FRAMES] [WIDTHxHEIGHT]
# AVOS_DATASETS: any of bonsai bluntfin foot engine (default all four);
# AVOS_VIEWS: any of default oblique (default both); AVOS_GPU_METHODS: the
# methods, ";"-separated (default the list below; the first is the baseline).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
data="$root/../shared/data"
render="$root/build/bin/avos-render"
frames="${1:-3}"
size="${2:-800x600}"

methods=(
  "vtk-gpu --step 0.5" "vtk-gpu --step 0.1"
  "gpu-riemann --step 0.5" "gpu-riemann --step 0.1"
  "gpu-coupled --tolerance 0.01" "gpu-coupled --tolerance 0.001"
  "gpu-decoupled --tolerance 0.01" "gpu-decoupled --tolerance 0.001"
  "gpu-piecewise --tolerance 0.01" "gpu-piecewise --tolerance 0.001"
)
if [ -n "${AVOS_GPU_METHODS:-}" ]; then
  IFS=';' read -r -a methods <<< "$AVOS_GPU_METHODS"
fi

echo "$size, median (min) of $frames frames, VTK's opacity model; error against the CPU mapper's"
echo "reference (exact within 1e-9); % px: the largest over RGBA of the pixels above 0.01 / 0.001"
echo
echo "| dataset | view | method | s per frame | / VTK GPU h 0.5 | max error | % px > 0.01 | % px > 0.001 |"
echo "|---|---|---|---|---|---|---|---|"
for ds in ${AVOS_DATASETS:-bonsai bluntfin foot engine}; do
  case $ds in
    bonsai) volume=("$data/volumes/bonsai_zfp.vti" --tf "$data/tf/Bonsai.1.256x256x256.tf1d") ;;
    bluntfin)
      volume=("$data/volumes/BluntFin.1.256x128x64.raw" --tf
        "$data/tf/BluntFin.1.256x128x64.linear.tf1d")
      ;;
    foot) volume=("$data/volumes/foot_zfp.vti" --tf "$data/tf/Foot.tf1d") ;;
    engine) volume=("$data/volumes/engine_zfp.vti" --tf "$data/tf/Engine.1.256x256x128.tf1d") ;;
    *) echo "unknown dataset $ds" >&2; exit 2 ;;
  esac
  for v in ${AVOS_VIEWS:-default oblique}; do
    view=()
    if [ "$v" = oblique ]; then
      view=(--azimuth 37 --elevation 23 --zoom 1.3)
    fi
    reference="gpu-reference-$ds-$v.exr"
    xvfb-run -a -s "-screen 0 1280x1024x24" "$render" "${volume[@]}" "${view[@]}" --opacity vtk \
      --size "$size" --method reference --output "$reference" > /dev/null 2>&1
    baseline=""
    for m in "${methods[@]}"; do
      # shellcheck disable=SC2086
      if ! xvfb-run -a -s "-screen 0 1280x1024x24" "$render" "${volume[@]}" "${view[@]}" \
        --opacity vtk --size "$size" --frames "$frames" --method $m --compare "$reference" \
        --report gpu-report.json > /dev/null 2>&1; then
        echo "| $ds | $v | ${m//--/} | failed | | | | |"
        continue
      fi
      read -r median fastest worst above2 above3 < <(python3 -c "
import json
r = json.load(open('gpu-report.json')); c = r['compare']
print('%.3g %.3g %.2g %.3g %.3g' % (r['median_seconds'], r['min_seconds'],
      max(c['max_error_rgba']), max(c['percent_above_0.01']), max(c['percent_above_0.001'])))")
      baseline="${baseline:-$median}" # VTK's GPU mapper at h 0.5, the first method
      ratio=$(python3 -c "print(f'{$median / $baseline:.2f}')")
      echo "| $ds | $v | ${m//--/} | $median ($fastest) | $ratio | $worst | $above2 | $above3 |"
    done
  done
done
