#!/usr/bin/env bash
# docs/results/real-drawings.md, "Texture, preview and output": the drawings of
# ../shared/data/drawings through pipelines/textured.yaml (write.height 0: the views' units,
# so the cameras fit the written model) and through pipelines/dmc.yaml, per drawing:
#   Marching Cubes' faces and the written faces (and their ratio), the texture's mean delta E
#   against the drawing's fill per view (bench/texture/fill_delta_e: strokes masked, against
#   the fill's mean over 13 x 13 px and against the fill's pixels), whether dmc.yaml wrote its
#   mesh, and WORK/NAME.preview.png, WORK/NAME.png (Blender, three-quarter, when installed).
# The manifests are written into WORK: which image is which view is read off the drawings
# (the shrimp's and the sculpture's views turned a quarter where the source drew them so).
# Usage: bench/texture/drawings_texture.sh BUILD_DIR [WORK_DIR] [NAMES]   (prints a Markdown table;
#   BLENDER=none skips the renders)
#   NAMES: comma-separated from shrimp,abstract,gopher,gopher_line,morevna (default: all)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:?usage: drawings_texture.sh BUILD_DIR [WORK_DIR] [NAMES]}
case $build in /*) ;; *) build=$root/$build ;; esac
work=${2:-$(mktemp -d)}
wanted=${3:-shrimp,abstract,gopher,gopher_line,morevna}
data=$(cd "$root/../shared/data/drawings" && pwd)
cm=$build/bin/conceptmesh
mkdir -p "$work"

# NAME VIEW=IMAGE...: WORK/NAME/views.yaml (an IMAGE ending in @90 is turned 90 degrees clockwise).
manifest() {
    local name=$1 dir=$work/$1
    shift
    mkdir -p "$dir"
    echo "views:" >"$dir/views.yaml"
    for pair in "$@"; do
        local view=${pair%%=*} image=${pair#*=}
        if [[ $image == *@90 ]]; then
            image=${image%@90}
            oiiotool "$data/$image" --rotate90 -o "$dir/$view.png"
            image=$dir/$view.png
        else
            image=$data/$image
        fi
        echo "  $view: $image" >>"$dir/views.yaml"
    done
}
manifest shrimp front=sketchrec_shrimp/side.png right=sketchrec_shrimp/back.png top=sketchrec_shrimp/top.png@90
manifest abstract front=sketchrec_abstract/bottom.png right=sketchrec_abstract/side.png@90 top=sketchrec_abstract/front.png
manifest gopher front=gopher/front.png right=gopher/side.png
manifest gopher_line front=gopher/front.png right=gopher/side_lineart.png
manifest morevna front=morevna_saha_body/front.png right=morevna_saha_body/side.png

metric() { # REPORT NODE KEY
    python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); n=[x for x in d["nodes"] if x["id"]==sys.argv[2]][0]; print(int(n["metrics"][sys.argv[3]]))' "$@"
}

echo "| drawing | MC faces | written faces | ratio | texture delta E against the fill, per view (against its pixels) | dmc.yaml |"
echo "|---|---:|---:|---:|---|---|"
for name in shrimp abstract gopher gopher_line morevna; do
    [[ ",$wanted," == *",$name,"* ]] || continue
    m=$work/$name/views.yaml
    "$cm" run "$root/pipelines/textured.yaml" --set views.manifest="$m" --set write.path="$work/$name.glb" \
        --set write.height=0 --set preview.path="$work/$name.preview.png" --report "$work/$name.json" -q
    mc=$(metric "$work/$name.json" surface faces)
    out=$(metric "$work/$name.json" reduce faces)
    de=$("$build/bin/fill_delta_e" "$work/$name.glb" "$m" | awk '{printf "%s%s %s (%s)", sep, $1, $2, $3; sep=" / "}')
    if "$cm" run "$root/pipelines/dmc.yaml" --set views.manifest="$m" --set write.path="$work/$name-dmc.obj" \
        --set preview.path="$work/$name-dmc.preview.png" --report "$work/$name-dmc.json" -q 2>"$work/$name-dmc.err"; then
        dmc="written, $(metric "$work/$name-dmc.json" write faces) faces"
    else
        dmc="refused: $(tail -1 "$work/$name-dmc.err")"
    fi
    ratio=$(python3 -c "print('%.1f %%' % (100.0 * $out / $mc))")
    echo "| $name | $mc | $out | $ratio | $de | $dmc |"
    oiiotool "$work/$name.preview.png" --resize 0x480 -o "$work/$name.preview.small.png" 2>/dev/null || true
    if [[ ${BLENDER:-blender} != none ]] && command -v blender >/dev/null; then
        blender -b --factory-startup --python "$root/bench/texture/blender_render.py" -- "$work/$name.glb" \
            "$work/$name.png" 320 >/dev/null 2>&1 || true
    fi
done
