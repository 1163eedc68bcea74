#!/usr/bin/env bash
# Bar 1 of docs/results/real-drawings.md: each model against its own sketchy line drawings.
#   render-views (style mask) -> sketch_views (outline 1-2 px, breaks 1-3 px) -> compare --fit bbox,
#   once with gap closing off (close_gaps: 0) and once with the default (0.4 % of 1024 px: 4.1 px).
# Usage: bench/views/real_drawings.sh BUILD_DIR [SIZE] [MODELS] [KEEP_DIR]   (prints a Markdown table)
#   MODELS: names from bench/models.txt, comma-separated (default spot,bob,bunny,armadillo,fertility)
set -euo pipefail
build=${1:?usage: real_drawings.sh BUILD_DIR [SIZE] [MODELS] [KEEP_DIR]}
size=${2:-1024}
wanted=${3:-spot,bob,bunny,armadillo,fertility}
here=$(cd "$(dirname "$0")" && pwd)
models=$(cd "$here/../../../shared/data/models" && pwd)
exe="$build/bin/conceptmesh"
work=${4:-$(mktemp -d)}
mkdir -p "$work"

# Per-view xor % of compare --fit bbox: "front right top" figures, 2 decimals.
per_view() {
    "$exe" compare "$1" "$2" --fit bbox --up "$3" --front "$4" --json 2>/dev/null |
        python3 -c 'import json,sys; d=json.load(sys.stdin); print(" ".join("%.2f" % v["xor_pct"] for v in d["views"]))'
}

echo "| model | close_gaps: 0 (front / right / top xor %) | default close_gaps (front / right / top xor %) | worst, after |"
echo "|---|---|---|---:|"
grep -v '^#' "$here/../models.txt" | tr -s ' ' | while read -r name file up front; do
    [[ ",$wanted," == *",$name,"* ]] || continue
    "$exe" render-views "$models/$file" -o "$work/$name-mask" --style mask --size "$size" --views front,right,top \
        --up "$up" --front "$front" -q
    "$build/bin/sketch_views" "$work/$name-mask/views.yaml" "$work/$name-off" --seed 7 --close-gaps 0
    "$build/bin/sketch_views" "$work/$name-mask/views.yaml" "$work/$name-on" --seed 7
    before=$(per_view "$models/$file" "$work/$name-off/views.yaml" "$up" "$front")
    after=$(per_view "$models/$file" "$work/$name-on/views.yaml" "$up" "$front")
    worst=$(echo "$after" | tr ' ' '\n' | sort -g | tail -1)
    echo "| $name | ${before// / \/ } | ${after// / \/ } | $worst |"
done
