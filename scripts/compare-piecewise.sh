#!/usr/bin/env bash
# The piecewise method against the paper's coupled rule and Riemann h 0.5 on
# BluntFin, Bonsai, Engine and Foot (paper transfer functions, extinction
# semantics, default view), side by side in one run: per dataset the exact
# piecewise reference, then each method (median of 3 frames after a warm-up
# frame) with its error against that reference. Prints a Markdown table;
# reports in out/piecewise/. With --old-reference, Bonsai's reference is also
# computed the way it was before the piecewise method (decoupled adaptive
# Simpson at eps 1e-9, steps 1e-7..0.25: minutes), for the speed-up.
#   scripts/compare-piecewise.sh [--old-reference] [--size WxH]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
render="${AVOS_BUILD_DIR:-$root/build}/bin/avos-render"
data="$root/../shared/data"
out="$root/out/piecewise"
old=0
size=800x600
while [ $# -gt 0 ]; do
  case "$1" in
    --old-reference) old=1 ;;
    --size) size="$2"; shift ;;
    *) echo "usage: $0 [--old-reference] [--size WxH]" >&2; exit 2 ;;
  esac
  shift
done
mkdir -p "$out"
run() { xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$render" "$@" >/dev/null 2>&1; }

datasets=(
  "BluntFin volumes/BluntFin.1.256x128x64.raw tf/BluntFin.1.256x128x64.linear.tf1d"
  "Bonsai volumes/bonsai_zfp.vti tf/Bonsai.1.256x256x256.linear.tf1d"
  "Engine volumes/engine_zfp.vti tf/Engine.1.256x256x128.linear.tf1d"
  "Foot volumes/foot_zfp.vti tf/Foot.tf1d")
methods=("riemann --step 0.5" "coupled --tolerance 0.01" "coupled --tolerance 0.001"
  "piecewise --tolerance 0.01" "piecewise --tolerance 0.001")
for entry in "${datasets[@]}"; do
  read -r name volume tf <<< "$entry"
  scene=("$data/$volume" --tf "$data/$tf" --size "$size")
  run "${scene[@]}" --method reference --output "$out/$name-reference.exr" \
    --report "$out/$name-reference.json"
  if [ "$old" = 1 ] && [ "$name" = Bonsai ]; then
    run "${scene[@]}" --method decoupled --tolerance 1e-9 --h0 0.125 --hmin 1e-7 --hmax 0.25 \
      --compare "$out/$name-reference.exr" --report "$out/$name-old-reference.json"
  fi
  for spec in "${methods[@]}"; do
    read -r method option value <<< "$spec"
    run "${scene[@]}" --method "$method" "$option" "$value" --frames 3 \
      --compare "$out/$name-reference.exr" --report "$out/$name-$method-$value.json"
  done
done

/usr/bin/python3 - "$out" <<'PY'
import glob, json, os, sys
out = sys.argv[1]
print("| dataset | method | s/frame (median) | samples/ray | cells/ray | pieces/ray | "
      "% pixels > 0.001 (worst channel) | max error |")
print("|---|---|---|---|---|---|---|---|")
for name in ["BluntFin", "Bonsai", "Engine", "Foot"]:
    for path in sorted(glob.glob(os.path.join(out, name + "-*.json"))):
        r = json.load(open(path))
        label = os.path.basename(path)[len(name) + 1:-5]
        c = r.get("compare")
        worst = max(c["percent_above_0.001"]) if c else 0.0
        maximum = max(c["max_error_rgba"]) if c else 0.0
        print("| %s | %s | %.3f | %.1f | %.1f | %.1f | %.4f | %.2e |" % (
            name, label, r["median_seconds"], r["mean_samples_per_ray"],
            r.get("mean_cells_per_ray", 0.0), r.get("mean_pieces_per_ray", 0.0), worst, maximum))
PY
