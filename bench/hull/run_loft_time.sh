#!/bin/sh
# The time section of docs/results/shape.md: `loft.yaml` against `paper.yaml` on the shape
# bench's masks (front, right, top at 1024 px, made as bench/hull/run_shape.sh makes them),
# the two pipelines run one after the other ROUNDS times (alternated, so a change of load
# falls on both), one line per run with the wall seconds and the CPU seconds of the run
# report (`seconds`, `cpu_seconds`), those of `hull.plausible` and of the smoothing, and the
# load average when it ended. CPU seconds count the time TBB's threads spend waiting for work
# too (spinning before they sleep), which a quiet machine lets them do at full speed: report
# wall and CPU, and THREADS=1 for the work alone.
#
#   bench/hull/run_loft_time.sh [BUILD_DIR] [RESOLUTION] [MODELS] [ROUNDS] > rows.txt
#
# One line per run: model pipeline round wall_s cpu_s plausible_cpu_s smooth_cpu_s load steps,
# where steps are `hull.plausible`'s wall seconds per step (its `step_seconds`, docs/hull.md),
# name=seconds joined by commas, "-" for `paper.yaml`.
# MODELS: a space-separated subset of bench/models.txt names (default: spot bob bunny man
# camel); ROUNDS default 3. Work files go to ${TMPDIR:-/tmp}/cm-shape (shared with
# run_shape.sh: the masks are made once).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-shape
res=${2:-512}
only=${3:-spot bob bunny man camel}
rounds=${4:-3}
threads=${THREADS:-0}
for r in $(seq 1 "$rounds"); do
    echo "$list" | while read -r name file up front; do
        if ! echo " $only " | grep -q " $name "; then continue; fi
        views=$work/$name-3v
        [ -f "$views/views.yaml" ] ||
            "$cm" render-views "$models/$file" --style mask --size 1024 --views front,right,top --up "$up" \
                --front "$front" -o "$views" -q
        for p in paper loft; do
            out=$work/$name-3v-$res-$p-time
            (cd "$root" && "$cm" run "pipelines/$p.yaml" -q --threads "$threads" \
                --set "views.manifest=$views/views.yaml" --set "hull.resolution=$res" \
                --set "write.path=$out.obj" --set "preview.path=$out.png" --report "$out.json") >&2
            python3 -c 'import json,sys
r = json.load(open(sys.argv[1]))
n = {x["id"]: x for x in r["nodes"]}
cpu = lambda k: n[k]["cpu_seconds"] if k in n else 0.0
steps = n["plausible"]["metrics"].get("step_seconds", {}) if "plausible" in n else {}
order = "voxels views priors smooth cover volume genus handles crossings".split()  # the run order
steps = sorted(steps.items(), key=lambda kv: order.index(kv[0]) if kv[0] in order else len(order))
print("%s %s %s %.2f %.2f %.2f %.2f %s %s" % (sys.argv[2], sys.argv[3], sys.argv[4], r["seconds"],
      r["cpu_seconds"], cpu("plausible"), cpu("smooth"), sys.argv[5],
      ",".join("%s=%.3f" % kv for kv in steps) or "-"))' "$out.json" "$name" "$p" "$r" \
                "$(cut -d' ' -f1 /proc/loadavg)"
        done
    done
done
