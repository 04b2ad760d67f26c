#!/usr/bin/env bash
# Figures of docs/RESULTS.md for the mapper's modes beside VTK's mappers, on
# Bonsai and Foot (or AVOS_DATASETS, any of: bonsai foot engine bluntfin)
# (800x600, 2 threads, VTK's opacity model, median of 3 frames; the default
# view, or AVOS_VIEW's avos-render options: "--azimuth 37 --elevation 23 --zoom 1.3" is
# scripts/bench-engine.py's oblique view),
# each image compared with a fine one of ours (shaded: the certified reference):
#   scripts/bench-modes.sh shading [BUILD_DIR]       section 5: shaded and unshaded
#   scripts/bench-modes.sh gradient [BUILD_DIR]      section 5: gradient opacity G = 0 at
#     |g| = 0 rising to 1 at 20 scalar units per world unit, unshaded and shaded (VTK's
#     fixed-point mapper reads G per average voxel spacing: the same axis at spacing 1)
#   scripts/bench-modes.sh projections [BUILD_DIR]   section 6: additive and average
#   scripts/bench-modes.sh intensity [BUILD_DIR]     section 4: maximum, minimum, clipped
# Writes its images and reports into the current folder.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
part="${1:?usage: $0 shading|gradient|projections|intensity [BUILD_DIR]}"
R="${2:-$root/build}/bin/avos-render"
read -r -a view <<< "${AVOS_VIEW:-}"
D="$root/../shared/data"

# run DATASET LABEL REFERENCE ARGS...: renders, compares, prints one line.
run() {
  local ds="$1" label="$2" ref="$3"
  shift 3
  if ! xvfb-run -a "$R" "${volume[@]}" "${view[@]}" --opacity vtk --size 800x600 \
    --frames "${frames:-3}" "$@" \
    --compare "$ref" --report r.json > /dev/null 2>&1; then
    echo "$ds $label: failed"
    return
  fi
  python3 -c "
import json; r = json.load(open('r.json')); c = r['compare']
print('$ds', '$label', 'median %.3f s' % r['median_seconds'], 'max error R %.3g' % c['max_error_rgba'][0],
      '% > 0.01 (R G B A):', ' '.join('%.3g' % v for v in c['percent_above_0.01']))"
}
reference() { # FILE ARGS...: ours, fine, once
  local file="$1"
  shift
  xvfb-run -a "$R" "${volume[@]}" "${view[@]}" --opacity vtk --size 800x600 "$@" --output "$file" \
    > /dev/null 2>&1
}

for ds in ${AVOS_DATASETS:-bonsai foot}; do
  case $ds in
    bonsai) volume=("$D/volumes/bonsai_zfp.vti" --tf "$D/tf/Bonsai.1.256x256x256.tf1d") ;;
    foot) volume=("$D/volumes/foot_zfp.vti" --tf "$D/tf/Foot.tf1d") ;;
    engine) volume=("$D/volumes/engine_zfp.vti" --tf "$D/tf/Engine.1.256x256x128.tf1d") ;;
    bluntfin) volume=("$D/volumes/BluntFin.1.256x128x64.raw" --tf "$D/tf/BluntFin.1.256x128x64.tf1d") ;;
    *) echo "unknown dataset $ds" >&2; exit 2 ;;
  esac
  case "$part" in
    shading)
      reference $ds-shaded.exr --method reference --shade
      for shade in "" --shade; do
        for m in vtk-fixed-point riemann "coupled --tolerance 0.01" "coupled --tolerance 0.001" \
          "piecewise --tolerance 0.01" "piecewise --tolerance 0.001"; do
          # shellcheck disable=SC2086
          run $ds "$m ${shade:-unshaded}" $ds-shaded.exr --method $m $shade
        done
      done ;;
    gradient)
      go=(--gradient-opacity 0,0,20,1)
      for shade in "" --shade; do
        # shellcheck disable=SC2086
        reference $ds-gradient$shade.exr --method reference "${go[@]}" $shade
        for m in vtk-fixed-point riemann "coupled --tolerance 0.01" "coupled --tolerance 0.001" \
          "piecewise --tolerance 0.01" "piecewise --tolerance 0.001"; do
          # shellcheck disable=SC2086
          run $ds "$m gradient opacity ${shade:-unshaded}" $ds-gradient$shade.exr --method $m \
            "${go[@]}" $shade
        done
      done ;;
    projections)
      for blend in additive average; do
        reference $ds-$blend.exr --blend $blend --tolerance 1e-6
        methods=("coupled --tolerance 0.01" "coupled --tolerance 0.001" vtk-gpu)
        [ $blend = additive ] && methods+=(vtk-fixed-point)
        for m in "${methods[@]}"; do
          # shellcheck disable=SC2086
          run $ds "$blend $m" $ds-$blend.exr --blend $blend --method $m
        done
      done ;;
    intensity)
      for blend in maximum minimum; do
        reference $ds-$blend.exr --blend $blend --method piecewise
        for m in piecewise vtk-fixed-point; do
          run $ds "$blend $m" $ds-$blend.exr --blend $blend --method $m
        done
      done
      # A clipping plane through the middle and the cross of cropping regions.
      cut=(--clip 1,0.3,0.2,128,128,128 --crop 60,180,60,180,40,200 --crop-mode cross)
      reference $ds-cut.exr --method piecewise --tolerance 1e-4 "${cut[@]}"
      for m in "piecewise --tolerance 0.01" riemann vtk-fixed-point; do
        # shellcheck disable=SC2086
        run $ds "clipped, cropped $m" $ds-cut.exr --method $m "${cut[@]}"
      done ;;
    *) echo "unknown part $part" >&2; exit 2 ;;
  esac
done
