#!/usr/bin/env bash
# Installs the Debian packages conceptmesh builds against, when any is missing.
# Idempotent: does nothing (and needs no network) when all are present.
set -euo pipefail
pkgs=(cmake g++ ninja-build ccache pkg-config
      libopenvdb-dev libboost-iostreams-dev libtbb-dev
      libopenimageio-dev openimageio-tools libopenexr-dev
      libopenmesh-dev libyaml-cpp-dev libvalijson-dev libtinygltf-dev
      nlohmann-json3-dev libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev
      libmeshoptimizer-dev libpng-dev libmimalloc-dev
      libssl-dev libjs-three)
pkgs+=(libeigen3-dev) # the 3x3 QEF of extract.dual_marching_cubes
pkgs+=(librsvg2-dev)  # SVG drawings, rasterised by librsvg
# The Python module (python/, docs/python.md) and its tests; python3-openvdb gives Volume.grid().
pkgs+=(pybind11-dev python3-dev python3-numpy python3-pytest python3-openvdb)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "conceptmesh: installing ${missing[*]}" >&2
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
