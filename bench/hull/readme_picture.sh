#!/usr/bin/env bash
# The README's first picture (docs/images/drawings-to-model.png): the bundled example's three
# drawings (examples/spot: front, right, top), the model pipelines/loft.yaml makes of them and,
# for comparison, the visual hull of pipelines/paper.yaml, both rendered by Blender (Workbench,
# bench/hull/shape_render.py) from the front right, above.
# Usage: bench/hull/readme_picture.sh BUILD_DIR OUT.png [WORK]
set -euo pipefail
build=${1:?usage: readme_picture.sh BUILD_DIR OUT.png [WORK]}
out=${2:?usage: readme_picture.sh BUILD_DIR OUT.png [WORK]}
repo=$(cd "$(dirname "$0")/../.." && pwd)
work=${3:-$(mktemp -d)}
mkdir -p "$work"
for p in loft paper; do
    (cd "$repo" && "$build/bin/conceptmesh" run "pipelines/$p.yaml" -q --set write.path="$work/spot-$p.obj" \
        --set preview.path="$work/spot-$p.preview.png")
done
# The example's OBJ is in the project's frame (front +Z): azimuth 135 is its front right.
SHAPE_AZ=135 blender -b --factory-startup --python "$repo/bench/hull/shape_render.py" -- 512 "$work/render" \
    "$work/spot-loft.obj" "$work/spot-paper.obj" > "$work/blender.log"
tiles=()
for v in front right top; do
    oiiotool "$repo/examples/spot/$v.png" --ch R,G,B --resize 224x224 -o "$work/t-$v.png"
    tiles+=("$work/t-$v.png")
done
for k in 0 1; do
    oiiotool "$work/render-$k.png" --ch R,G,B --cut 80,75,410,405 --resize 224x224 -o "$work/t-model-$k.png"
    tiles+=("$work/t-model-$k.png")
done
oiiotool "${tiles[@]}" --mosaic:pad=4 5x1 -o "$out"
echo "$out"
