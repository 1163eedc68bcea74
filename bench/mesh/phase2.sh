#!/bin/sh
# The figures of docs/results/phase2.md: each model of ../shared/data/models is rendered at
# 1024 px from front, right and top (binary silhouettes by default, as bench/accuracy), run
# through the full paper pipeline (bench/mesh/phase2.yaml, resolution 256), and its Marching
# Cubes mesh handed to phase2_eval (smoothing variants, reduction sweep against quadric
# decimation). Writes one JSON per model and the tables and plot (phase2_report.py).
#
#   bench/mesh/phase2.sh [BUILD_DIR] [STYLE] [MAX_ANGLE]
#
# Work files go to ${TMPDIR:-/tmp}/cm-phase2; with RESUME=1, models whose figures are
# already there are not run again.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
style=${2:-mask}
angle=${3:-20}
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-phase2

echo "$list" | while read -r name file up front; do
    if [ "${RESUME:-0}" = 1 ] && [ -s "$work/$name-eval.json" ] && [ -s "$work/$name-pipeline.json" ]; then
        continue
    fi
    views=$work/$name-$style
    [ -f "$views/views.yaml" ] ||
        "$cm" render-views "$models/$file" --style "$style" --size 1024 --up "$up" --front "$front" -o "$views" -q
    echo "$name: pipeline" >&2
    (cd "$root" && /usr/bin/time -f "%e s %M KiB" -o "$work/$name.time" \
        "$cm" run bench/mesh/phase2.yaml -q --set "views.manifest=$views/views.yaml" \
        --set "reduce.max_angle_deg=$angle" \
        --set "write_mc.path=$work/$name-mc.ply" --set "write.path=$work/$name-paper.ply" \
        --report "$work/$name-pipeline.json")
    echo "$name: sweep" >&2
    "$build/bin/phase2_eval" "$work/$name-mc.ply" "$views/views.yaml" > "$work/$name-eval.json"
done
python3 "$root/bench/mesh/phase2_report.py" "$work" "$build"
