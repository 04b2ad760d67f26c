#!/usr/bin/env bash
# The additive and average projections, ours (integrated) against VTK's
# mappers (sampled at h 0.5), on Bonsai and Foot (800x600, 2 threads, VTK's
# opacity model, median of 3 frames); each image compared with ours at
# eps 1e-6: the figures of docs/RESULTS.md section 6. Writes into the
# current folder.   scripts/bench-projections.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
R="${1:-$root/build}/bin/avos-render"
D="$root/../shared/data"
for ds in bonsai foot; do
  if [ $ds = bonsai ]; then V=$D/volumes/bonsai_zfp.vti; T=$D/tf/Bonsai.1.256x256x256.tf1d; else V=$D/volumes/foot_zfp.vti; T=$D/tf/Foot.tf1d; fi
  for blend in additive average; do
    xvfb-run -a $R $V --tf $T --opacity vtk --blend $blend --tolerance 1e-6 --size 800x600 \
      --output $ds-$blend-ref.exr > /dev/null 2>&1
    methods=("coupled --tolerance 0.01" "coupled --tolerance 0.001" "vtk-gpu")
    [ $blend = additive ] && methods+=("vtk-fixed-point")
    for m in "${methods[@]}"; do
      xvfb-run -a $R $V --tf $T --opacity vtk --blend $blend --method $m --size 800x600 \
        --frames 3 --compare $ds-$blend-ref.exr --report r.json > /dev/null 2>&1 || { echo "$ds $blend $m failed"; continue; }
      python3 -c "
import json; r=json.load(open('r.json')); c=r['compare']
print('$ds', '$blend', '$m', 'median %.3f s'%r['median_seconds'], 'max error R %.3g' % c['max_error_rgba'][0], '%% > 0.01 (R G B A):', ' '.join('%.3g' % v for v in c['percent_above_0.01']))"
    done
  done
done
