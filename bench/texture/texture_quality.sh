#!/usr/bin/env bash
# docs/results/texture.md: the textured result against flat-coloured concept art with ink lines.
#   flat_art (front, right, top; fills + ink, and the fills alone) -> pipelines/textured.yaml
#   (write.height 0: the views' units, so the cameras fit) -> compare (delta E per view, inside
#   the silhouette eroded by 3 px) against the drawings as drawn and against their fills ->
#   texture_sheet (drawing | textured mesh | delta E map, and a three-quarter view).
# Usage: bench/texture/texture_quality.sh BUILD_DIR [SIZE] [MODELS] [OUT_DIR]   (prints a Markdown table)
#   MODELS: names from bench/models.txt, comma-separated (default spot,bob,bunny,armadillo,fertility)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
source "$root/bench/common.sh"
bench_setup "${1:?usage: texture_quality.sh BUILD_DIR [SIZE] [MODELS] [OUT_DIR]}" texture-quality
size=${2:-512}
wanted=${3:-spot,bob,bunny,armadillo,fertility}
out=${4:-$work}
mkdir -p "$out"

# "mean / over10" per view of a compare --json, e.g. "2.1 (1.3 %)" three times.
colour() {
    python3 -c 'import json,sys; d=json.load(sys.stdin); print(" | ".join("%.2f (%.1f %%)" % (v["mean_delta_e"], v["over10_pct"]) for v in d["colour"]))'
}

echo "| model | charts | against the fills: front / right / top, mean dE (share > 10) | against the drawings as drawn (ink included) |"
echo "|---|---:|---|---|"
while read -r name file up front; do
    [[ ",$wanted," == *",$name,"* ]] || continue
    "$build/bin/flat_art" "$models/$file" "$up" "$front" "$work/$name" "$size"
    "$cm" run "$root/pipelines/textured.yaml" -q --set views.manifest="$work/$name/art/views.yaml" \
        --set write.path="$work/$name/$name.glb" --set write.height=0 --report "$work/$name/run.json"
    charts=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); n=[x for x in d["nodes"] if x["id"]=="texture"][0]; print(int(n["metrics"]["charts"]))' "$work/$name/run.json" 2>/dev/null || echo "?")
    fills=$("$cm" compare "$work/$name/$name.glb" "$work/$name/fill/views.yaml" --json -q | colour)
    drawn=$("$cm" compare "$work/$name/$name.glb" "$work/$name/art/views.yaml" --json -q | colour)
    "$build/bin/texture_sheet" "$work/$name/$name.glb" "$work/$name/art/views.yaml" "$out/texture_$name.png" 240
    echo "| $name | $charts | $fills | $drawn |"
done <<< "$list"
