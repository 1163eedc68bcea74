#!/bin/sh
# The figures of docs/results/shape.md: each model of ../shared/data/models is rendered as
# binary masks at 1024 px (front, right, top, and with OBLIQUE=1 a fourth view at azimuth 45,
# elevation 30), reconstructed by pipelines/paper.yaml, organic.yaml and loft.yaml at
# RESOLUTION, and measured: the silhouette error from four views that were not given
# (azimuth 45 elevation 30, 135/20, -60/-25, 210/45; the true model's masks rendered with the
# same cameras, `conceptmesh compare`), the 3D error (mean two-sided surface distance, % of
# the diagonal, bench/hull/surface_distance), the drawn views' xor_pct of the written mesh
# (eval.silhouette_error), closed / 2-manifold (conceptmesh check) and the CPU seconds of
# the run (cpu_seconds of its report).
#
#   bench/hull/run_shape.sh [BUILD_DIR] [RESOLUTION] [MODELS] [PIPELINES] > rows.txt
#
# One line per model and pipeline:
#   model pipeline views resolution err3d_pct drawn_xor_pct unseen_xor_pct clean cpu_seconds
# MODELS: a space-separated subset of bench/models.txt names (default: all); PIPELINES: of
# pipelines/ (default: "paper organic loft"). Work files go to ${TMPDIR:-/tmp}/cm-shape.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-shape
res=${2:-256}
only=${3:-}
pipes=${4:-paper organic loft}
dist=$build/bin/surface_distance
viewset=front,right,top
tag=3v
if [ "${OBLIQUE:-0}" = 1 ]; then viewset=front,right,top,az45el30; tag=4v; fi
unseen_set=az45el30,az135el20,az-60el-25,az210el45
echo "$list" | while read -r name file up front; do
    if [ -n "$only" ] && ! echo " $only " | grep -q " $name "; then continue; fi
    views=$work/$name-$tag
    [ -f "$views/views.yaml" ] ||
        "$cm" render-views "$models/$file" --style mask --size 1024 --views "$viewset" --up "$up" --front "$front" \
            -o "$views" -q
    unseen=$work/$name-unseen
    [ -f "$unseen/views.yaml" ] ||
        "$cm" render-views "$models/$file" --style mask --size 1024 --views "$unseen_set" --up "$up" \
            --front "$front" -o "$unseen" -q
    for p in $pipes; do
        out=$work/$name-$tag-$res-$p
        (cd "$root" && "$cm" run "pipelines/$p.yaml" -q --set "views.manifest=$views/views.yaml" \
            --set "hull.resolution=$res" --set "write.path=$out.obj" --set "preview.path=$out.png" \
            --report "$out.json") >&2 || true
        err=$("$dist" "$out.obj" "$models/$file" --up "$up" --front "$front" |
            python3 -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["mean_pct"])')
        unseen_xor=$("$cm" compare "$out.obj" "$unseen/views.yaml" --json -q |
            python3 -c 'import json,sys; print("%.3f" % json.load(sys.stdin)["xor_pct"])')
        set -- $(python3 -c 'import json,sys
r = json.load(open(sys.argv[1]))
print("%.3f %.2f" % ([n for n in r["nodes"] if n["id"] == "score"][0]["metrics"]["xor_pct"], r["cpu_seconds"]))' "$out.json")
        if "$cm" check "$out.obj" > /dev/null 2>&1; then clean=yes; else clean=no; fi
        echo "$name $p $tag $res $err $1 $unseen_xor $clean $2"
    done
done
