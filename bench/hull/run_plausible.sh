#!/bin/sh
# The figures of docs/results/plausible.md: each model of ../shared/data/models is rendered
# as binary masks at 1024 px (front, right, top, and with OBLIQUE=1 a fourth view at azimuth
# 45, elevation 30), reconstructed by pipelines/paper.yaml and pipelines/organic.yaml at
# RESOLUTION, and measured: the 3D error against the true model (mean two-sided surface
# distance, % of the bounding-box diagonal, bench/hull/surface_distance), the silhouette
# error xor_pct of the written mesh (eval.silhouette_error), closed / 2-manifold /
# self-intersections (conceptmesh check) and the wall time of the whole run.
#
#   bench/hull/run_plausible.sh [BUILD_DIR] [RESOLUTION] [MODELS] > rows.txt
#
# One line per model and pipeline: model pipeline views resolution err3d_pct xor_pct clean seconds.
# MODELS is a space-separated subset of bench/models.txt names (default: all).
# Work files go to ${TMPDIR:-/tmp}/cm-plausible.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-plausible
res=${2:-256}
only=${3:-}
dist=$build/bin/surface_distance
viewset=front,right,top
tag=3v
if [ "${OBLIQUE:-0}" = 1 ]; then viewset=front,right,top,az45el30; tag=4v; fi
echo "$list" | while read -r name file up front; do
    if [ -n "$only" ] && ! echo " $only " | grep -q " $name "; then continue; fi
    views=$work/$name-$tag
    [ -f "$views/views.yaml" ] ||
        "$cm" render-views "$models/$file" --style mask --size 1024 --views "$viewset" --up "$up" --front "$front" \
            -o "$views" -q
    for p in paper organic; do
        out=$work/$name-$tag-$res-$p
        start=$(date +%s.%N)
        (cd "$root" && "$cm" run "pipelines/$p.yaml" -q --set "views.manifest=$views/views.yaml" \
            --set "hull.resolution=$res" --set "write.path=$out.obj" --set "preview.path=$out.png" \
            --report "$out.json") >&2 || true
        end=$(date +%s.%N)
        secs=$(echo "$start $end" | awk '{ printf "%.2f", $2 - $1 }')
        err=$("$dist" "$out.obj" "$models/$file" --up "$up" --front "$front" |
            python3 -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["mean_pct"])')
        xor=$(python3 -c 'import json,sys
r = json.load(open(sys.argv[1]))
print("%.3f" % [n for n in r["nodes"] if n["id"] == "score"][0]["metrics"]["xor_pct"])' "$out.json")
        if "$cm" check "$out.obj" > /dev/null 2>&1; then clean=yes; else clean=no; fi
        echo "$name $p $tag $res $err $xor $clean $secs"
    done
done
