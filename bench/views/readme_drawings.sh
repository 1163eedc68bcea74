#!/usr/bin/env bash
# The README's picture of drawings as they come (docs/images/drawings-blueprint-marker.png):
# top row, spot drawn as a blueprint (render-views --style blueprint: outline, creases and
# inner contours in blue, no fill) and the model pipelines/loft.yaml makes of it; bottom row,
# bob drawn in marker (bench/texture/flat_art ... marker: fills laid in diagonal marker strokes,
# black ink outlines) and the textured model of pipelines/textured.yaml, both rendered by
# Blender from the front right. Only the project's own renders go into the picture.
# Usage: bench/views/readme_drawings.sh BUILD_DIR OUT.png [WORK]
set -euo pipefail
build=${1:?usage: readme_drawings.sh BUILD_DIR OUT.png [WORK]}
out=${2:?usage: readme_drawings.sh BUILD_DIR OUT.png [WORK]}
repo=$(cd "$(dirname "$0")/../.." && pwd)
work=${3:-$(mktemp -d)}
exe="$build/bin/conceptmesh"
mkdir -p "$work"

"$exe" render-views "$repo/../shared/data/models/spot.obj" -o "$work/blueprint" --style blueprint --size 512 \
    --line-width 2 --views front,right,top --up +Y --front -Z -q
"$exe" run "$repo/pipelines/loft.yaml" -q --set views.manifest="$work/blueprint/views.yaml" \
    --set write.path="$work/spot.glb" --set preview.path="$work/spot.preview.png"
"$build/bin/flat_art" "$repo/../shared/data/models/bob_tri.obj" +Y -X "$work/bob" 512 marker
"$exe" run "$repo/pipelines/textured.yaml" -q --set views.manifest="$work/bob/art/views.yaml" \
    --set write.path="$work/bob.glb" --set preview.path="$work/bob.preview.png"
# spot's model is untextured (white): under a darker sky.
for m in spot:0.15 bob:0.8; do
    blender -b --factory-startup --python "$repo/bench/texture/blender_render.py" -- "$work/${m%:*}.glb" \
        "$work/${m%:*}.png" 440 "${m#*:}" >/dev/null
done

# Each picture fitted into a 220 px tile with a 6 px margin: drawings on white, renders on grey.
oiiotool --pattern constant:color=1,1,1,1 232x232 4 -o "$work/white.png"
oiiotool --pattern constant:color=0.8,0.8,0.8,1 232x232 4 -o "$work/grey.png"
oiiotool --pattern constant:color=0.42,0.42,0.42,1 232x232 4 -o "$work/dark.png"
tile() {
    oiiotool "$1" --ch R,G,B,A=1.0 --fit:pad=1 220x220 --origin +6+6 --fullsize 232x232 "$work/$3.png" --over \
        --ch R,G,B -o "$2"
}
tiles=()
for v in front right top; do tile "$work/blueprint/$v.png" "$work/t-spot-$v.png" white; tiles+=("$work/t-spot-$v.png"); done
tile "$work/spot.png" "$work/t-spot-model.png" dark
tiles+=("$work/t-spot-model.png")
for v in front right top; do tile "$work/bob/art/$v.png" "$work/t-bob-$v.png" white; tiles+=("$work/t-bob-$v.png"); done
tile "$work/bob.png" "$work/t-bob-model.png" grey
tiles+=("$work/t-bob-model.png")
oiiotool "${tiles[@]}" --mosaic 4x2 -o "$out"
echo "$out"
