#!/usr/bin/env bash
# Shaded against unshaded rendering, ours against VTK's fixed-point mapper, on
# Bonsai and Foot (800x600, 2 threads, VTK's opacity model, median of 3
# frames), each image compared with a shaded reference (coupled, eps 1e-4):
# the figures of docs/RESULTS.md section 5. Writes into the current folder.
#   scripts/bench-shading.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
R="${1:-$root/build}/bin/avos-render"
D="$root/../shared/data"
for ds in bonsai foot; do
  if [ $ds = bonsai ]; then V=$D/volumes/bonsai_zfp.vti; T=$D/tf/Bonsai.1.256x256x256.tf1d; else V=$D/volumes/foot_zfp.vti; T=$D/tf/Foot.tf1d; fi
  xvfb-run -a $R $V --tf $T --opacity vtk --method coupled --tolerance 1e-4 --shade --size 800x600 --output $ds-ref.exr 2>/dev/null
  for shade in "" "--shade"; do
    for m in "vtk-fixed-point" "riemann" "coupled --tolerance 0.01" "coupled --tolerance 0.001"; do
      xvfb-run -a $R $V --tf $T --opacity vtk --method $m $shade --size 800x600 --frames 3 --compare $ds-ref.exr --report r.json > /dev/null 2>&1
      python3 -c "
import json; r=json.load(open('r.json')); c=r.get('compare',{})
print('$ds', '$m', '$shade' or 'unshaded', 'median %.3f s'%r['median_seconds'], '%% > 0.01 (R G B A):', ' '.join('%.3g' % v for v in c['percent_above_0.01']))"
    done
  done
done
