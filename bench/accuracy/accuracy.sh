#!/bin/sh
# The accuracy table of docs/results/accuracy.md: each model of ../shared/data/models is
# rendered at 1024 px from front, right and top, reconstructed by phase 1 of the method
# (views -> hull -> refine -> surface, no smoothing or reduction) at each resolution, and
# the result re-rendered through the same cameras and compared (xor_pct, the paper's error).
#
#   bench/accuracy/accuracy.sh [BUILD_DIR] [STYLE] [RESOLUTIONS] > table.md
#
# BUILD_DIR defaults to build/release, STYLE to mask (binary silhouettes; "art" renders
# shaded drawings whose silhouettes views.load extracts), RESOLUTIONS to "256 128".
# Work files go to ${TMPDIR:-/tmp}/cm-accuracy.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
style=${2:-mask}
resolutions=${3:-256 128}
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-accuracy

header="| model |"
rule="|---|"
for r in $resolutions; do header="$header xor_pct @ $r |"; rule="$rule---:|"; done
echo "$header"
echo "$rule"
sums=""
n=0
echo "$list" | {
    while read -r name file up front; do
        views=$work/$name-$style
        [ -f "$views/views.yaml" ] ||
            "$cm" render-views "$models/$file" --style "$style" --size 1024 --up "$up" --front "$front" -o "$views" -q
        row="| $name |"
        for r in $resolutions; do
            mesh=$work/$name-$style-$r.ply
            (cd "$root" && "$cm" run bench/accuracy/reconstruct.yaml -q --set "views.manifest=$views/views.yaml" \
                --set "hull.resolution=$r" --set "write.path=$mesh" --report "$work/$name-$style-$r.json") >&2
            x=$("$cm" compare "$mesh" "$views/views.yaml" --json -q |
                python3 -c 'import json,sys; print("%.3f" % json.load(sys.stdin)["xor_pct"])')
            row="$row $x |"
            echo "$name $r $x" >> "$work/values-$style.txt"
        done
        echo "$row"
        n=$((n + 1))
    done
    # Means per resolution, from this run's values.
    row="| **mean** |"
    for r in $resolutions; do
        m=$(tail -n $((n * $(echo $resolutions | wc -w))) "$work/values-$style.txt" |
            awk -v r="$r" '$2 == r { s += $3; c++ } END { printf "%.3f", s / c }')
        row="$row **$m** |"
    done
    echo "$row"
}
