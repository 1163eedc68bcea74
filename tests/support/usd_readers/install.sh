#!/bin/sh
# install.sh DIR: installs the two USD readers the tests load written files with (npm:
# TinyUSDZ's WebAssembly build and three.js, whose USDLoader reads .usda and .usdz) into
# DIR/node_modules, at the versions the tests were written against. The tests call it when
# the packages are missing (tests running at once wait for one another here); .ci/run calls
# it before the suite runs.
set -e
dir=$1
[ -n "$dir" ] || { echo "usage: $0 DIR" >&2; exit 2; }
mkdir -p "$dir"
cd "$dir"
exec 9>.install-lock
command -v flock >/dev/null && flock 9
[ -f node_modules/tinyusdz/tinyusdz.wasm ] && [ -f node_modules/three/examples/jsm/loaders/USDLoader.js ] && exit 0
[ -f package.json ] || echo '{"private": true}' >package.json
npm install --no-audit --no-fund --save-exact --loglevel=error tinyusdz@0.9.0-rc10 three@0.187.0
