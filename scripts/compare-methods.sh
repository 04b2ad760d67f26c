#!/usr/bin/env bash
# Side-by-side run of every method on one scene (default: Bonsai with its paper
# transfer function in VTK's opacity semantics, 800x600): time per frame and
# error against the reference, one avos-render call per method, all in one run
# on this machine. Results: out/compare/<method>.json and a summary table.
#   scripts/compare-methods.sh [avos-render options, e.g. --size 400x300]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
render="${AVOS_BUILD_DIR:-$root/build}/bin/avos-render"
data="$root/../shared/data"
out="$root/out/compare"
mkdir -p "$out"
scene=("$data/volumes/bonsai_zfp.vti" --tf "$data/tf/Bonsai.1.256x256x256.linear.tf1d"
  --opacity vtk "$@")
run() { xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$render" "${scene[@]}" "$@"; }

run --method reference --output "$out/reference.exr" --report "$out/reference.json"
for spec in "riemann --step 0.5" "riemann --step 0.1" \
  "coupled --tolerance 0.01" "coupled --tolerance 0.005" "coupled --tolerance 0.001" \
  "decoupled --tolerance 0.01" "decoupled --tolerance 0.005" "decoupled --tolerance 0.001" \
  "vtk-fixed-point --step 0.5" "vtk-gpu --step 0.5"; do
  read -r method option value <<< "$spec"
  name="$method-${option#--}-$value"
  run --method "$method" "$option" "$value" --frames 3 --compare "$out/reference.exr" \
    --report "$out/$name.json" | grep -v '^$'
done
