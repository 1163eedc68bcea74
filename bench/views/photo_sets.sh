#!/usr/bin/env bash
# docs/results/real-drawings.md, "Photographs against dark cloth": the calibrated sets of
# ../shared/data/multiview, each carved and extracted (bench/views/dino_carve.yaml) by this
# build and by a baseline build, and each mesh's silhouette error through the cameras
# (compare, xor %): the dinoSparseRing (bench/hull/multiview_manifests: background black,
# threshold 0.19), its photographs with a dark cloth reaching the frame (bench/views/dino_cloth:
# auto.yaml, and auto_estimated.yaml with the threshold estimated), both against the authors'
# masks (mask.yaml, made the authors' way, about 3 px beyond the plaster) and, for the cloth
# sets, against the masks traced on the plaster (traced.yaml); the same photographs with
# `background: black` (black.yaml: the cloth not modelled, threshold 0.19, and
# black_estimated.yaml); and the TUM bunny against its own silhouettes.
# Usage: bench/views/photo_sets.sh BUILD_DIR BASELINE_BUILD_DIR [WORK_DIR]   (prints a Markdown table)
#   BASELINE_BUILD_DIR needs bin/conceptmesh only (the tools come from BUILD_DIR).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:?usage: photo_sets.sh BUILD_DIR BASELINE_BUILD_DIR [WORK_DIR]}
base=${2:?usage: photo_sets.sh BUILD_DIR BASELINE_BUILD_DIR [WORK_DIR]}
work=${3:-$(mktemp -d)}
data=$(cd "$here/../../../shared/data" && pwd)
mkdir -p "$work/cloth"
"$build/bin/multiview_manifests" "$work" "$data"
"$build/bin/dino_cloth" "$data/multiview/middlebury_dinoSparseRing" "$work/cloth" >/dev/null
sed 's/, threshold: 0.19}/}/' "$work/cloth/auto.yaml" >"$work/cloth/auto_estimated.yaml"
sed 's/, threshold: 0.19}/}/' "$work/cloth/black.yaml" >"$work/cloth/black_estimated.yaml"
# The reference of each set: the authors' masks for the dino's, the given silhouettes for the bunny.
reference() { case $1 in tum_bunny) echo "$work/tum_bunny.yaml" ;; *) echo "$work/cloth/mask.yaml" ;; esac; }
manifest() { case $1 in dino | tum_bunny) echo "$work/$1.yaml" ;; *) echo "$work/cloth/$1.yaml" ;; esac; }
# xor_pct to three decimals, measured by EXE (default: this build).
xor() { "${3:-$build/bin/conceptmesh}" compare "$1" "$2" --json | python3 -c 'import json,sys; print("%.3f" % json.load(sys.stdin)["xor_pct"])'; }
echo "| set | baseline: xor % against the reference | this build | baseline: against its own silhouettes | this build | baseline: against the traced masks | this build |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for set in dino auto auto_estimated black black_estimated tum_bunny; do
    row="| $set"
    own=""
    traced=""
    for exe in "$base/bin/conceptmesh" "$build/bin/conceptmesh"; do
        tag=$([[ $exe == "$base"/* ]] && echo base || echo new)
        out=$work/$set-$tag.obj
        "$exe" run "$here/dino_carve.yaml" --set views.manifest="$(manifest $set)" --set write.path="$out" -q >/dev/null 2>&1
        row="$row | $(xor "$out" "$(reference $set)")"
        # Its own silhouettes as the build that made the mesh extracts them.
        own="$own | $(xor "$out" "$(manifest $set)" "$exe")"
        # The cloth sets also against the masks traced on the plaster itself.
        case $set in dino | tum_bunny) traced="$traced | -" ;; *) traced="$traced | $(xor "$out" "$work/cloth/traced.yaml")" ;; esac
    done
    echo "$row$own$traced |"
done
