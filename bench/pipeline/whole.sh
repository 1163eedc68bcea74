#!/bin/sh
# Speed of the whole method (docs/results/speed.md): pipelines/paper.yaml from three views
# rendered at 2048 px (front, right, top), at each resolution, RUNS times. Per node: wall and
# CPU seconds from the run report (--report; cpu_seconds is the process's user + system time
# while the node ran); for the process: wall, CPU and peak memory from /usr/bin/time -v.
#
#   bench/pipeline/whole.sh [BUILD_DIR] [RESOLUTIONS] [MODEL] [RUNS] > table.md
#
# Defaults: build/release, "512 1024 2048", camel, 3. Work files go to ${TMPDIR:-/tmp}/cm-whole.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-whole
resolutions=${2:-512 1024 2048}
model=${3:-camel}
runs=${4:-3}
set -- $(echo "$list" | grep "^$model ") || { echo "unknown model $model" >&2; exit 2; }
views=$work/$model-2048
[ -f "$views/views.yaml" ] ||
    "$cm" render-views "$models/$2" --style mask --size 2048 --up "$3" --front "$4" -o "$views" -q
echo "| resolution | run | load | views | hull | refine | surface | smooth | reduce | write+preview+error | process wall s | process CPU s | peak MiB | faces MC -> out | xor_pct |"
echo "|---:|---:|---:|---|---|---|---|---|---|---|---:|---:|---:|---|---:|"
for r in $resolutions; do
    i=1
    while [ "$i" -le "$runs" ]; do
        load=$(cut -d' ' -f1 /proc/loadavg)
        (cd "$work" && /usr/bin/time -v -o "$work/time.log" "$cm" run "$root/pipelines/paper.yaml" -q \
            --set "views.manifest=$views/views.yaml" --set "hull.resolution=$r" \
            --set "write.path=$work/out.obj" --set "preview.path=$work/out.png" --report "$work/report.json")
        python3 - "$work/report.json" "$work/time.log" "$r" "$i" "$load" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
t = {}
for line in open(sys.argv[2]):
    k, _, v = line.strip().partition(": ")
    t[k] = v
n = {x["id"]: x for x in r["nodes"]}
cell = lambda *ids: "%.2f (%.2f)" % (max(n[i]["seconds"] for i in ids), max(n[i]["cpu_seconds"] for i in ids))
h, m, s = ("0:" + t["Elapsed (wall clock) time (h:mm:ss or m:ss)"]).split(":")[-3:]
wall = 3600 * float(h) + 60 * float(m) + float(s)
cpu = float(t["User time (seconds)"]) + float(t["System time (seconds)"])
print("| %s | %s | %s | %s | %s | %.2f | %.2f | %.0f | %s -> %s | %.3f |" % (
    sys.argv[3], sys.argv[4], sys.argv[5],
    " | ".join(cell(k) for k in ("views", "hull", "refine", "surface", "smooth", "reduce")),
    cell("write", "preview", "score"), wall, cpu, float(t["Maximum resident set size (kbytes)"]) / 1024,
    format(int(n["surface"]["metrics"]["faces"]), ","), format(int(n["reduce"]["metrics"]["faces"]), ","),
    n["score"]["metrics"]["xor_pct"]))
PY
        i=$((i + 1))
    done
done
