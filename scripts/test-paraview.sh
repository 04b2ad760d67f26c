#!/usr/bin/env bash
# Builds the AVoS ParaView plugin against Debian's ParaView 5.11 and tests it:
# pvpython loads it and runs reader -> contour -> decimation (and Volume on
# Surface), then pvbatch on 2 and 4 MPI ranks runs the same (each rank prints
# its work) and the totals are compared with the one-process run
# (Plugin/Testing/ComparePieces.py); volume images with the "AVoS Volume"
# representation on 1, 2 and 4 ranks against the one-process image, within
# what ParaView's compositing costs its own mapper (VolumeImages.py); the
# options ParaView's volume representation passes (VolumeOptions.py);
# pvpython turns a .tf1d file into a preset (Tf1dPreset.py); then the time
# and memory per rank on a larger volume are printed (Plugin/Testing/
# Scaling.py: figures, not assertions).
#
# python3-paraview conflicts with python3-vtk9 (both install vtkmodules), and
# paraview-dev's CMake files need it: this script installs ParaView's
# packages for the time it runs and always puts the VTK ones back
# (scripts/install-deps.sh, on any exit), so that scripts/test.sh works
# afterwards. Never run it beside another build or test of the project.
# Every ParaView run has a 10-minute limit: a hang fails the script.
# Output: out/paraview (build-paraview/ holds the plugin's build).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build-paraview"
out="$root/out/paraview"
data="${AVOS_SHARED_DATA_DIR:-$root/../shared/data}"

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
restore() {
  echo "Restoring the VTK packages (scripts/install-deps.sh)"
  "$root/scripts/install-deps.sh"
}
trap restore EXIT

export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  paraview paraview-dev python3-paraview python3-numpy openmpi-bin xvfb xauth \
  libopenmesh-dev libglm-dev libhwy-dev cmake build-essential >/dev/null

cmake -S "$root/Plugin" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --parallel "$(nproc)"
plugin="$build/lib/paraview-plugins/AVoS/AVoS.so"

# -noreset: Xvfb otherwise resets when its last client leaves, and a window
# opened meanwhile fails ("bad X server connection"), as in scripts/test.sh.
xvfb="-screen 0 1280x1024x24 -noreset"

rm -rf "$out"
mkdir -p "$out"
script="$root/Plugin/Testing/PipelinePieces.py"
echo "== pvpython, one process"
timeout 600 xvfb-run -a -s "$xvfb" pvpython "$script" "$plugin" "$data" "$out/ranks-1.json"
for ranks in 2 4; do
  echo "== pvbatch on $ranks MPI ranks"
  timeout 600 xvfb-run -a -s "$xvfb" mpiexec --allow-run-as-root --oversubscribe -n "$ranks" \
    pvbatch --symmetric "$script" "$plugin" "$data" "$out/ranks-$ranks.json"
done
python3 "$root/Plugin/Testing/ComparePieces.py" "$out"/ranks-{1,2,4}.json
echo "== images: AVoS Volume against ParaView's own, Volume on Surface, on 1, 2 and 4 ranks"
image="$root/Plugin/Testing/VolumeImage.py"
for ranks in 1 2 4; do
  timeout 600 xvfb-run -a -s "$xvfb" mpiexec --allow-run-as-root --oversubscribe -n "$ranks" \
    pvbatch "$image" "$plugin" "$data" "$out/avos-$ranks.png" "AVoS Volume"
  timeout 600 xvfb-run -a -s "$xvfb" mpiexec --allow-run-as-root --oversubscribe -n "$ranks" \
    pvbatch "$image" "$plugin" "$data" "$out/paraview-$ranks.png" "Volume"
  timeout 600 xvfb-run -a -s "$xvfb" mpiexec --allow-run-as-root --oversubscribe -n "$ranks" \
    pvbatch "$image" "$plugin" "$data" "$out/surface-$ranks.png" "Volume on Surface"
done
timeout 600 xvfb-run -a -s "$xvfb" pvbatch "$image" "$plugin" "$data" "$out/avos-riemann.png" "AVoS Volume" Riemann
/usr/bin/python3 "$root/Plugin/Testing/VolumeImages.py" "$out"
echo "== the options ParaView's volume representation passes (VolumeOptions.py)"
timeout 600 xvfb-run -a -s "$xvfb" pvbatch "$root/Plugin/Testing/VolumeOptions.py" "$plugin" "$data"
echo "== a .tf1d file as a ParaView preset"
timeout 600 xvfb-run -a -s "$xvfb" pvpython "$root/Plugin/Testing/Tf1dPreset.py" "$plugin" \
  "$data/tf/Bonsai.1.256x256x256.linear.tf1d" "$out" 2>&1 | tee "$out/preset.log"
# Creating the proxy must not run the reader with no file (it logged an error).
if grep -qE "ERR\||ERROR" "$out/preset.log"; then
  echo "the preset test logged an error" >&2
  exit 1
fi
echo "ParaView plugin tests passed"

# Figures, not assertions: time and peak memory per rank on a 160^3 volume.
echo "== scaling (Plugin/Testing/Scaling.py, 160^3 Marschner-Lobb)"
for ranks in 1 2 4; do
  timeout 600 xvfb-run -a -s "$xvfb" mpiexec --allow-run-as-root --oversubscribe -n "$ranks" \
    pvbatch --symmetric "$root/Plugin/Testing/Scaling.py" "$plugin" 160 "$out/scaling.jsonl"
done
