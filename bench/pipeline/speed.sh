#!/bin/sh
# Speed and memory of phase 1 (docs/results/speed.md): views rendered at 2048 px from
# front, right and top, then hull.carve + hull.marching_intersections +
# extract.marching_cubes at each resolution. Per stage: wall seconds from the run report
# (--report); for the process: peak resident memory from /usr/bin/time -v.
#
#   bench/pipeline/speed.sh [BUILD_DIR] [RESOLUTIONS] [MODELS] > table.md
#
# BUILD_DIR defaults to build/release, RESOLUTIONS to "256 512 1024 2048", MODELS to
# "spot armadillo bunny". Work files go to ${TMPDIR:-/tmp}/cm-speed.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-build/release}
resolutions=${2:-256 512 1024 2048}
models=${3:-spot armadillo bunny}
case $build in /*) ;; *) build=$root/$build ;; esac
cm=$build/bin/conceptmesh
data=$root/../shared/data/models
work=${TMPDIR:-/tmp}/cm-speed
mkdir -p "$work"

axes() {   # file --up --front, from bench/models.txt
    line=$(grep -v '^#' "$root/bench/models.txt" | tr -s ' ' | grep "^$1 ") || { echo "unknown model $1" >&2; exit 2; }
    echo "$line" | cut -d' ' -f2-
}

# Wall seconds mean little on a shared machine. "chain CPU s" is the CPU time (user + sys,
# all threads) of the run minus that of a run that only reads the views (views_only.yaml):
# the carve, refine and extract work itself; on two idle cores the chain's wall time is
# between half of it and all of it. "load" is the load average when the run started.
echo "| model | resolution | carve s | refine s | extract s | chain s | growth | faces | peak RSS MiB | chain CPU s | load |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
cpu_of() {   # user + sys seconds from a /usr/bin/time -v log
    awk -F: '/User time|System time/ { s += $2 } END { printf "%.2f", s }' "$1"
}
for name in $models; do
    set -- $(axes "$name")
    views=$work/$name-2048
    [ -f "$views/views.yaml" ] ||
        "$cm" render-views "$data/$1" --style mask --size 2048 --up "$2" --front "$3" -o "$views" -q
    (cd "$root" && /usr/bin/time -v "$cm" run bench/pipeline/views_only.yaml -q \
        --set "views.manifest=$views/views.yaml") 2> "$work/$name-views.time"
    base=$(cpu_of "$work/$name-views.time")
    prev=""
    for r in $resolutions; do
        report=$work/$name-$r.json
        load=$(cut -d' ' -f1 /proc/loadavg)
        (cd "$root" && /usr/bin/time -v "$cm" run bench/pipeline/chain.yaml -q \
            --set "views.manifest=$views/views.yaml" --set "hull.resolution=$r" --report "$report") \
            2> "$work/$name-$r.time"
        rss=$(awk -F: '/Maximum resident set size/ { printf "%d", $2 / 1024 }' "$work/$name-$r.time")
        cpu=$(cpu_of "$work/$name-$r.time" | awk -v b="$base" '{ printf "%.1f", $1 - b }')
        row=$(python3 - "$report" "$prev" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
n = {x["id"]: x for x in r["nodes"]}
s = [n[k]["seconds"] for k in ("hull", "refine", "surface")]
chain = sum(s)
prev = sys.argv[2]
growth = "%.1fx" % (chain / float(prev)) if prev else ""
faces = int(n["surface"]["metrics"]["faces"])
print("%d %.2f %.2f %.2f %.2f %s %s" % (n["hull"]["params"]["resolution"], s[0], s[1], s[2], chain,
                                      growth or "-", format(faces, ",")))
PY
)
        set -- $row
        echo "| $name | $1 | $2 | $3 | $4 | $5 | $6 | $7 | $rss | $cpu | $load |"
        prev=$5
    done
done
