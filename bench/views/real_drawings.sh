#!/usr/bin/env bash
# Bar 1 of docs/results/real-drawings.md: each model against its own sketchy line drawings.
#   render-views (style mask) -> sketch_views (an outline stroke of a given width, centred on
#   the true outline with wobble, breaks 1-3 px) -> compare --fit bbox, at each stroke width;
#   and the worst view's IoU against the masks with their openings filled (views_iou).
# Usage: bench/views/real_drawings.sh BUILD_DIR [SIZE] [MODELS] [KEEP_DIR] [WIDTHS] [PLACE]   (prints a Markdown table)
#   MODELS: names from bench/models.txt, comma-separated (default spot,bob,bunny,armadillo,fertility)
#   WIDTHS: stroke widths, comma-separated, each W or A:B (wavering from A to B px; default 1:2,3,5)
#   PLACE: centre (default: the stroke centred on the outline, as an artist draws) or inside
#   (half a stroke inside it, as a renderer draws its outline)
set -euo pipefail
build=${1:?usage: real_drawings.sh BUILD_DIR [SIZE] [MODELS] [KEEP_DIR] [WIDTHS] [PLACE]}
size=${2:-1024}
wanted=${3:-spot,bob,bunny,armadillo,fertility}
here=$(cd "$(dirname "$0")" && pwd)
models=$(cd "$here/../../../shared/data/models" && pwd)
exe="$build/bin/conceptmesh"
work=${4:-$(mktemp -d)}
widths=${5:-1:2,3,5}
place=${6:-centre}
mkdir -p "$work"

# Per-view xor % of compare --fit bbox: "front right top" figures, 2 decimals.
per_view() {
    "$exe" compare "$1" "$2" --fit bbox --up "$3" --front "$4" --json 2>/dev/null |
        python3 -c 'import json,sys; d=json.load(sys.stdin); print(" ".join("%.2f" % v["xor_pct"] for v in d["views"]))'
}

# The worst per-view IoU of views_iou A.yaml B.yaml.
worst_iou() {
    "$build/bin/views_iou" "$1" "$2" 2>/dev/null | awk '$1 == "worst" { print $3 }'
}

echo "| model | stroke width (px) | front / right / top xor % | worst | worst IoU, openings filled |"
echo "|---|---|---|---:|---:|"
grep -v '^#' "$here/../models.txt" | tr -s ' ' | while read -r name file up front; do
    [[ ",$wanted," == *",$name,"* ]] || continue
    "$exe" render-views "$models/$file" -o "$work/$name-mask" --style mask --size "$size" --views front,right,top \
        --up "$up" --front "$front" -q
    # The masks with their openings filled: what line art can show (an opening is bounded
    # by the outline stroke, which line art cannot tell from the inside of a part).
    sed -E 's/\{image: ([a-z]+\.png),/{image: \1, holes: fill,/' "$work/$name-mask/views.yaml" \
        > "$work/$name-mask/filled.yaml"
    for width in ${widths//,/ }; do
        d="$work/$name-w${width/:/-}-$place"
        "$build/bin/sketch_views" "$work/$name-mask/views.yaml" "$d" --seed 7 --width "$width" --place "$place"
        xor=$(per_view "$models/$file" "$d/views.yaml" "$up" "$front")
        worst=$(echo "$xor" | tr ' ' '\n' | sort -g | tail -1)
        echo "| $name | ${width/:/-} | ${xor// / \/ } | $worst | $(worst_iou "$d/views.yaml" "$work/$name-mask/filled.yaml") |"
    done
done
