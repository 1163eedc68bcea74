#!/usr/bin/env bash
# Runs clang-tidy (the checks in .clang-tidy) on the given sources, or on every .cpp of
# src/ without arguments. Needs a configured build: build/release/compile_commands.json.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-tidy >/dev/null || { echo "tidy.sh: clang-tidy is not installed (apt-get install clang-tidy)" >&2; exit 2; }
[ -f build/release/compile_commands.json ] || { echo "tidy.sh: configure first (cmake --preset release)" >&2; exit 2; }
if [ $# -eq 0 ]; then set -- $(git ls-files 'src/*.cpp'); fi
# The build's GCC-only warning flags are unknown to clang.
exec clang-tidy -p build/release --quiet --extra-arg=-Wno-unknown-warning-option "$@"
