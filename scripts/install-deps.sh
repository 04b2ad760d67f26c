#!/usr/bin/env bash
# Installs the Debian (bookworm) packages AVoS needs, only those missing.
set -euo pipefail

packages=(
  build-essential cmake
  libvtk9-dev python3-vtk9
  libopenmesh-dev libglm-dev
  # OpenImageIO's CMake package names the tools and the Imath Python module too.
  libopenimageio-dev openimageio-tools python3-imath
  libgtest-dev libbenchmark-dev
  # The ray-casting engine's SIMD kernels (runtime dispatch).
  libhwy-dev
  # The avos-render test writes a DICOM series.
  python3-pydicom
  xvfb xauth
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "Installing: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
