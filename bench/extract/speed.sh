#!/bin/sh
# Bar 3 of docs/results/extract.md: adaptive Dual Marching Cubes against Marching Cubes
# followed by one mesh.reduce pass to the same face count, on one model at one resolution,
# RUNS times each, alternating (A B A B ...), so both see the same load. Per run: the CPU
# seconds (user + system, all threads: the run report's cpu_seconds) and wall seconds of the
# extractor node, and of the reduction for A; the faces.
#
#   bench/extract/speed.sh [BUILD_DIR] [MODEL] [RESOLUTION] [RUNS] > speed.tsv
#
# Work files go to ${TMPDIR:-/tmp}/cm-extract-speed.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-extract-speed
model=${2:-spot}
res=${3:-512}
runs=${4:-3}
line=$(echo "$list" | grep -E "^$model ")
[ -n "$line" ] || { echo "speed.sh: no model $model in bench/models.txt" >&2; exit 1; }
set -- $line
views=$work/$model
[ -f "$views/views.yaml" ] ||
    "$cm" render-views "$models/$2" --style mask --size 1024 --up "$3" --front "$4" -o "$views" -q
sets="--set views.manifest=$views/views.yaml --set hull.resolution=$res"
dmc=$work/dmc.yaml
mcr=$work/mc-reduce.yaml
sed "s/extract.marching_cubes/extract.dual_marching_cubes/" "$root/bench/extract/extract.yaml" > "$dmc"
# Node figures of a run report: faces, CPU and wall seconds of the nodes named.
figures() {
    python3 - "$@" <<'P'
import json, sys
nodes = {n["id"]: n for n in json.load(open(sys.argv[1]))["nodes"]}
sel = [nodes[i] for i in sys.argv[2:]]
print("%d\t%.3f\t%.3f" % (sel[-1]["metrics"]["faces"], sum(n["cpu_seconds"] for n in sel),
                          sum(n["seconds"] for n in sel)))
P
}
printf 'model\tres\trun\tmethod\tfaces\tcpu_s\twall_s\tload1\n'
i=1
while [ $i -le "$runs" ]; do
    # shellcheck disable=SC2086
    (cd "$root" && "$cm" run "$dmc" -q $sets --set "write.path=$work/dmc.ply" --report "$work/dmc.json") >&2
    f=$(figures "$work/dmc.json" surface)
    printf '%s\t%s\t%s\tdmc\t%s\t%s\n' "$model" "$res" $i "$f" "$(cut -d' ' -f1 /proc/loadavg)"
    target=$(echo "$f" | cut -f1)
    sed "s/inputs: { mesh: surface }/inputs: { mesh: reduce }/" "$root/bench/extract/extract.yaml" > "$mcr"
    printf '  - id: reduce\n    stage: mesh.reduce\n    inputs: { mesh: surface }\n    params: { max_angle_deg: 40, target_faces: %s }\n' \
        "$target" >> "$mcr"
    # shellcheck disable=SC2086
    (cd "$root" && "$cm" run "$mcr" -q $sets --set "write.path=$work/mcr.ply" --report "$work/mcr.json") >&2
    printf '%s\t%s\t%s\tmc\t%s\t%s\n' "$model" "$res" $i "$(figures "$work/mcr.json" surface)" "$(cut -d' ' -f1 /proc/loadavg)"
    printf '%s\t%s\t%s\tmc+reduce\t%s\t%s\n' "$model" "$res" $i "$(figures "$work/mcr.json" surface reduce)" \
        "$(cut -d' ' -f1 /proc/loadavg)"
    i=$((i + 1))
done
