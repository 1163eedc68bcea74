#!/usr/bin/env bash
# Round trip of every model in ../shared/data/models through render-views and compare:
#   render-views (mask and art styles) -> compare --fit bbox of the same model against its own views,
#   once with the exact cameras render-views writes (scale, origin, bounds) and once with those
#   deleted, so that views.load aligns the views from their silhouettes as it does for drawings;
#   and the IoU between the silhouettes views.load extracts from the art and from the masks.
# Usage: bench/views/views_roundtrip.sh BUILD_DIR [SIZE] [VIEWS]   (prints a Markdown table)
set -euo pipefail
build=${1:?usage: views_roundtrip.sh BUILD_DIR [SIZE] [VIEWS]}
size=${2:-1024}
views=${3:-front,right,top}
here=$(cd "$(dirname "$0")" && pwd)
models=$(cd "$here/../../../shared/data/models" && pwd)
exe="$build/bin/conceptmesh"
iou="$build/bin/views_iou"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# model file, then its own up and front axes (bench/models.txt).
table=$(grep -v '^#' "$here/../models.txt" | tr -s ' ' | cut -d' ' -f2-)

# xor_pct of compare --fit bbox as a number with 3 decimals.
xor() {
    "$exe" compare "$1" "$2" --fit bbox --up "$3" --front "$4" --json 2>/dev/null |
        python3 -c 'import json,sys; print("%.3f" % json.load(sys.stdin)["xor_pct"])'
}
# The manifest without the exact cameras: views.load aligns the views from their silhouettes.
free_manifest() {
    sed -e '/^bounds:/d' -e 's/, scale: [^,]*, origin: \[[^]]*\]//' "$1/views.yaml" > "$1/free.yaml"
}

echo "| model | faces | xor % mask, exact cameras | xor % art, exact cameras | xor % mask, aligned | xor % art, aligned | IoU art vs mask (worst view) | render-views art (s) |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
while read -r file up front; do
    name=${file%.*}
    faces=$(awk 'NR==1 && $1=="OFF"{getline; print $2; exit} /^f /{n++} END{if(n) print n}' "$models/$file")
    "$exe" render-views "$models/$file" -o "$work/$name-mask" --style mask --size "$size" --views "$views" --up "$up" --front "$front" -q
    start=$(date +%s.%N)
    "$exe" render-views "$models/$file" -o "$work/$name-art" --style art --size "$size" --views "$views" --up "$up" --front "$front" >/dev/null 2>&1
    secs=$(echo "$(date +%s.%N) - $start" | bc)
    free_manifest "$work/$name-mask"
    free_manifest "$work/$name-art"
    xm=$(xor "$models/$file" "$work/$name-mask/views.yaml" "$up" "$front")
    xa=$(xor "$models/$file" "$work/$name-art/views.yaml" "$up" "$front")
    fm=$(xor "$models/$file" "$work/$name-mask/free.yaml" "$up" "$front")
    fa=$(xor "$models/$file" "$work/$name-art/free.yaml" "$up" "$front")
    wi=$("$iou" "$work/$name-art/views.yaml" "$work/$name-mask/views.yaml" | awk '/^worst/{print $3}')
    printf '| %s | %s | %s | %s | %s | %s | %s | %.1f |\n' "$file" "$faces" "$xm" "$xa" "$fm" "$fa" "$wi" "$secs"
done <<< "$table"
