#!/usr/bin/env bash
# Blueprint-style line art (docs/results/real-drawings.md, "Blueprint-style line art"): each
# model drawn by render-views --style blueprint (outline, creases and inner contours in one
# colour and width, no fill), then
#   - the true model's silhouette error against those views (compare --fit bbox), per view;
#   - the reconstruction (pipelines/paper.yaml) and its genus against the model's (conceptmesh
#     check: genus = components - euler / 2 of a closed mesh).
# Usage: bench/views/blueprint_bar.sh BUILD_DIR [SIZE] [MODELS] [WORK] [VIEWS] [COLOUR] [WIDTH]
#   MODELS: names from bench/models.txt, comma-separated (default: all)
#   VIEWS: render-views --views (default front,right,top; six views let opposite views
#   confirm the openings of line art)
set -euo pipefail
build=${1:?usage: blueprint_bar.sh BUILD_DIR [SIZE] [MODELS] [WORK] [VIEWS] [COLOUR] [WIDTH]}
size=${2:-1024}
wanted=${3:-all}
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
models=$(cd "$repo/../shared/data/models" && pwd)
exe="$build/bin/conceptmesh"
work=${4:-$(mktemp -d)}
views=${5:-front,right,top}
colour=${6:-#1f3f8f}
width=${7:-1.5}
mkdir -p "$work"

genus() {
    "$exe" check "$1" --json 2>/dev/null |
        python3 -c 'import json,sys; d=json.load(sys.stdin); print("%g" % (d["components"] - d["euler"] / 2))'
}

echo "| model | xor % per view ($views) | worst | genus of the model | genus of the reconstruction |"
echo "|---|---|---:|---:|---:|"
grep -v '^#' "$here/../models.txt" | tr -s ' ' | while read -r name file up front; do
    [[ "$wanted" == all || ",$wanted," == *",$name,"* ]] || continue
    d="$work/$name"
    "$exe" render-views "$models/$file" -o "$d" --style blueprint --line-colour "$colour" --line-width "$width" \
        --size "$size" --views "$views" --up "$up" --front "$front" -q
    xor=$("$exe" compare "$models/$file" "$d/views.yaml" --fit bbox --up "$up" --front "$front" --json 2>/dev/null |
        python3 -c 'import json,sys; d=json.load(sys.stdin); print(" ".join("%.2f" % v["xor_pct"] for v in d["views"]))')
    worst=$(echo "$xor" | tr ' ' '\n' | sort -g | tail -1)
    "$exe" run "$repo/pipelines/paper.yaml" -q --set views.manifest="$d/views.yaml" --set write.path="$d/mesh.obj" \
        --set preview.path="$d/preview.png" >/dev/null 2>&1 ||
        "$exe" run "$repo/pipelines/paper.yaml" -q --set views.manifest="$d/views.yaml" --set write.path="$d/mesh.obj"
    echo "| $name | ${xor// / \/ } | $worst | $(genus "$models/$file") | $(genus "$d/mesh.obj") |"
done
