#!/usr/bin/env bash
# The bar for turnaround sheets (docs/results/sheet.md): per model, render-views draws front,
# right and top (art style), sheet_compose puts them on one sheet (side by side, blank gaps,
# a label under each), and the paper pipeline reconstructs from
#   sheet     the sheet (sheet: {image: sheet.png, views: [front, right, top]}),
#   aligned   the three drawings as separate files, aligned from their silhouettes as the
#             sheet's panels are (the manifest without scale, origin and bounds),
#   fixed     the three drawings with the exact cameras render-views writes;
# then compare --fit bbox measures each mesh against the separate drawings (views.yaml).
# Usage: bench/views/sheet_bar.sh BUILD_DIR [SIZE] [MODEL...]   (prints a Markdown table)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/bench/common.sh"
bench_setup "${1:?usage: sheet_bar.sh BUILD_DIR [SIZE] [MODEL...]}" conceptmesh-sheet-bar
size=${2:-1024}
shift $(($# < 2 ? $# : 2))
wanted=${*:-spot bob bunny}

xor() {
    "$cm" compare "$1" "$2" --fit bbox --up "$3" --front "$4" --json 2>/dev/null |
        python3 -c 'import json,sys; print("%.3f" % json.load(sys.stdin)["xor_pct"])'
}
run() { # manifest, mesh
    "$cm" run "$root/pipelines/paper.yaml" -q --set views.manifest="$1" --set write.path="$2" \
        --set preview.path="${2%.obj}.preview.png" >/dev/null
}

echo "| model | sheet (px) | panels found | xor % sheet | xor % separate, aligned | xor % separate, fixed cameras | sheet - aligned (pp) | sheet - fixed (pp) |"
echo "|---|---|---|---:|---:|---:|---:|---:|"
while read -r name file up front; do
    case " $wanted " in *" $name "*) ;; *) continue ;; esac
    d=$work/$name
    rm -rf "$d" && mkdir -p "$d"
    "$cm" render-views "$models/$file" -o "$d/views" --size "$size" --style art --views front,right,top \
        --up "$up" --front "$front" -q
    "$build/bin/sheet_compose" "$d/sheet.png" "$d/views/front.png" "$d/views/right.png" "$d/views/top.png"
    panels=$("$build/bin/sheet_compose" --panels "$d/panels.png" "$d/sheet.png" | grep -c '^panel')
    echo "sheet: {image: sheet.png, views: [front, right, top]}" >"$d/sheet.yaml"
    sed -e '/^bounds:/d' -e 's/, scale: [^,]*, origin: \[[^]]*\]//' "$d/views/views.yaml" >"$d/views/free.yaml"
    run "$d/sheet.yaml" "$d/sheet.obj"
    run "$d/views/free.yaml" "$d/aligned.obj"
    run "$d/views/views.yaml" "$d/fixed.obj"
    s=$(xor "$d/sheet.obj" "$d/views/views.yaml" +Y +Z)
    a=$(xor "$d/aligned.obj" "$d/views/views.yaml" +Y +Z)
    f=$(xor "$d/fixed.obj" "$d/views/views.yaml" +Y +Z)
    dims=$(python3 -c 'import struct,sys; b=open(sys.argv[1],"rb").read(24); print("%dx%d" % struct.unpack(">II", b[16:24]))' "$d/sheet.png")
    echo "| $name | $dims | $panels | $s | $a | $f | $(echo "$s - $a" | bc) | $(echo "$s - $f" | bc) |"
done <<<"$list"
