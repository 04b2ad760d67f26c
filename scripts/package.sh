#!/usr/bin/env bash
# Builds AVoS's Debian package (in build-deb/, prefix /usr) and checks it on
# this machine as a user would: `apt-get install ./avos_*.deb` gives
# avos-render, `import avos` (no PYTHONPATH) and find_package(AVoS) (the
# examples built against it and run); `apt-get remove avos` then leaves none
# of its files behind. Installs and removes a system package: run as root or
# with sudo, on a machine without another AVoS package installed.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${AVOS_PACKAGE_BUILD_DIR:-$root/build-deb}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi

"$root/scripts/install-deps.sh"
# dpkg-shlibdeps (the package's dependencies from the libraries it links).
dpkg-query -W -f='${Status}' dpkg-dev 2>/dev/null | grep -q "install ok installed" ||
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends dpkg-dev
if dpkg-query -W -f='${Status}' avos 2>/dev/null | grep -q "install ok installed"; then
  echo "package.sh: an avos package is installed already; remove it first" >&2
  exit 1
fi

# Debian's own layout: /usr, and Python packages in lib/python3/dist-packages.
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=/usr \
  -DAVOS_PYTHON_SITE_PACKAGES=lib/python3/dist-packages -DBUILD_TESTING=OFF \
  -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build "$build" --parallel "$(nproc)"
rm -f "$build"/avos_*.deb
(cd "$build" && cpack -G DEB >/dev/null)
deb="$(ls "$build"/avos_*.deb)"
echo "package: $deb"
dpkg-deb --field "$deb" Package Version Depends Recommends

$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$deb" >/dev/null
mapfile -t files < <(dpkg-query -L avos | while read -r f; do [ -f "$f" ] && echo "$f"; done)
echo "installed: ${#files[@]} files"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
avos-render --help | head -1
env -u PYTHONPATH /usr/bin/python3 -c \
  'import avos; assert avos.__file__.startswith("/usr/lib/"), avos.__file__; print("import avos", avos.__version__, "from", avos.__file__)'
cmake -S "$root/Examples/Cxx" -B "$work/examples" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/examples" --parallel "$(nproc)" >/dev/null
grep -q "AVoS_DIR:PATH=/usr/lib/" "$work/examples/CMakeCache.txt"
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$work/examples/avos-example-pipeline" \
  "$work/pipeline.png"

$SUDO env DEBIAN_FRONTEND=noninteractive apt-get remove -y -qq avos >/dev/null
left=0
for f in "${files[@]}"; do
  if [ -e "$f" ]; then echo "left behind: $f" >&2; left=1; fi
done
if [ "$left" -ne 0 ]; then exit 1; fi
echo "removed: no file of the package is left"
