#!/usr/bin/env bash
# Installs every Debian 12 package the project needs to build, test and run.
# Idempotent: packages already present are skipped, so a second run is quick.
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake ninja-build pkg-config clang-format
  # the .deb (CPack: dpkg-shlibdeps) and its desktop entry's check
  dpkg-dev desktop-file-utils
  # fuzzing (libFuzzer) and the sanitizer build
  clang libclang-rt-14-dev
  # libraries (see ../shared/STACK.md for how they are linked)
  qt6-base-dev libqt6opengl6-dev qt6-charts-dev
  libvtk9-dev libpcl-dev libopencv-dev libeigen3-dev
  libtiff-dev libgdal-dev libembree-dev libnanoflann-dev robin-map-dev nlohmann-json3-dev libcli11-dev libsqlite3-dev libssl-dev libminizip-dev
  cyclonedds-dev cyclonedds-tools
  libgtest-dev libgmock-dev libbenchmark-dev
  # real terrain for the mapping tests: USGS's Jacksboro fault DEM
  # (docs/mapping.md), shipped as matplotlib's sample data
  python-matplotlib-data
  # running the GUI and its tests without a monitor; the 3-D views' text
  # in the GUI's own font (fontconfig finds it)
  xvfb xauth libgl1-mesa-dri libfontconfig-dev fonts-dejavu-core
  # the network bench's namespaces and veth pairs (tests/network)
  iproute2
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
