#!/usr/bin/env bash
# Installs every build and test dependency of mcpose from Debian packages.
# Usage: scripts/install_deps.sh   (as root, or with sudo available)
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libpng-dev zlib1g-dev libturbojpeg0-dev libmatio-dev libtinyobjloader-dev nlohmann-json3-dev libcli11-dev
  libspdlog-dev libfmt-dev libeigen3-dev libnanoflann-dev libmeshoptimizer-dev libqhull-dev
  libhwy-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev libosmesa6-dev
  verilator yosys
  clang libclang-rt-14-dev
  chromium fonts-dejavu-core pngquant
  python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-dask python3-distributed
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install_deps: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install_deps: all Debian packages already installed"
fi
