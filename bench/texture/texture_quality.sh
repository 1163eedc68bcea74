#!/usr/bin/env bash
# docs/results/texture.md: the textured result against flat-coloured concept art with ink lines.
#   flat_art (front, right, top; fills + ink, and the fills alone) -> pipelines/textured.yaml
#   (write.height 0: the views' units, so the cameras fit) -> compare (delta E per view, inside
#   the silhouette eroded by 3 px) against the drawings without their ink pixels (the bar's
#   reading), against the fills alone, and against the drawings as drawn (ink counts as error)
#   -> texture_sheet (drawing | textured mesh | delta E map, and a three-quarter view).
# Usage: bench/texture/texture_quality.sh BUILD_DIR [SIZE] [MODELS] [OUT_DIR] [-- --set texture.X=Y ...]
#   prints a Markdown table; MODELS: names from bench/models.txt, comma-separated (default: all);
#   what follows -- goes to `conceptmesh run` (e.g. --set texture.balance_rounds=0).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
source "$root/bench/common.sh"
args=()
while (($#)) && [[ $1 != -- ]]; do
    args+=("$1")
    shift
done
(($#)) && shift # the --; what is left goes to conceptmesh run
bench_setup "${args[0]:?usage: texture_quality.sh BUILD_DIR [SIZE] [MODELS] [OUT_DIR] [-- RUN_OPTIONS]}" texture-quality
size=${args[1]:-512}
wanted=${args[2]:-spot,bob,bunny,armadillo,fertility,fandisk,camel,man}
out=${args[3]:-$work}
mkdir -p "$out"

# "mean (over10)" per view of a compare --json, joined by " / "; $1 = "" or "no_ink_".
colour() {
    python3 -c 'import json,sys; p=sys.argv[1]; d=json.load(sys.stdin); print(" / ".join("%.2f (%.1f %%)" % (v[p+"mean_delta_e"], v[p+"over10_pct"]) for v in d["colour"]))' "$1"
}

echo "| model | charts | the drawing without its ink: front / right / top, mean dE (share > 10) | the fills alone | the drawing as drawn (ink counts) |"
echo "|---|---:|---|---|---|"
while read -r name file up front; do
    [[ ",$wanted," == *",$name,"* ]] || continue
    "$build/bin/flat_art" "$models/$file" "$up" "$front" "$work/$name" "$size"
    "$cm" run "$root/pipelines/textured.yaml" -q --set views.manifest="$work/$name/art/views.yaml" \
        --set write.path="$work/$name/$name.glb" --set write.height=0 \
        --set preview.path="$work/$name/preview.png" --report "$work/$name/run.json" "$@"
    charts=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); n=[x for x in d["nodes"] if x["id"]=="texture"][0]; print(int(n["metrics"]["charts"]))' "$work/$name/run.json" 2>/dev/null || echo "?")
    fills=$("$cm" compare "$work/$name/$name.glb" "$work/$name/fill/views.yaml" --json -q | colour "")
    art=$("$cm" compare "$work/$name/$name.glb" "$work/$name/art/views.yaml" --json -q)
    noink=$(colour no_ink_ <<< "$art")
    drawn=$(colour "" <<< "$art")
    "$build/bin/texture_sheet" "$work/$name/$name.glb" "$work/$name/art/views.yaml" "$out/texture_$name.png" 240
    echo "| $name | $charts | $noink | $fills | $drawn |"
done <<< "$list"
