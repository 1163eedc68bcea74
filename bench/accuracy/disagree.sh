#!/bin/sh
# The tables of docs/results/disagree.md: drawings that disagree, reconstructed with and
# without reconciliation, each drawing scored as an artist judges a model (the model rendered
# from its view, fitted to the drawing by a similarity: the share of the drawing not covered,
# missing, and covered beyond it, extra; bench/views/score_drawings).
#
#   bench/accuracy/disagree.sh [BUILD_DIR] [SEEDS] [MODELS] > tables.md
#
# Perturbed renders: each model of ../shared/data/models rendered at 1024 px from front,
# right and top (masks), every view but the first redrawn by bench/views/perturb_views
# (each axis scaled by up to 8 %, turned by up to 3 deg, shifted by up to 1 %, wobbled by up
# to 0.6 % of the side; SEEDS default "1 2 3"), reconstructed by phase 1 of the method
# (bench/accuracy/reconstruct.yaml, resolution 256) with reconcile: off and on.
# Opposite views: front, back, right and top renders where the back has its topmost part
# erased (a horn, an ear), with opposite: union and intersect; the front drawing's missing
# share says whether the part is in the model. MODELS: names of bench/models.txt,
# comma-separated (default all). Work files go to ${TMPDIR:-/tmp}/cm-disagree.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-disagree
seeds=${2:-1 2 3}
wanted=${3:-}
bin=$build/bin

# reconstruct MANIFEST OUT.ply EXTRA-SETS...: phase 1 of the method on a manifest.
reconstruct() {
    manifest=$1 mesh=$2
    shift 2
    (cd "$root" && "$cm" run bench/accuracy/reconstruct.yaml -q --set "views.manifest=$manifest" \
        --set hull.resolution=256 --set "write.path=$mesh" --report "${mesh%.ply}.json" "$@") 2>/dev/null
}
# score DRAWINGS MESH VIEWS: "view missing extra" lines of the model against the drawings.
score() {
    "$cm" render-views "$2" --style mask --size 1024 --views "$3" -o "${2%.ply}-r" -q
    "$bin/score_drawings" "$1" "${2%.ply}-r/views.yaml"
}

echo "| model | seed | reconcile: off, missing % (front / right / top) | reconcile: on, missing % | on, extra % | on, worst missing | off, missing + extra % | on, missing + extra % |"
echo "|---|---:|---|---|---|---:|---|---|"
echo "$list" | while read -r name file up front; do
    [ -z "$wanted" ] || case ",$wanted," in *",$name,"*) ;; *) continue ;; esac
    views=$work/$name
    [ -f "$views/views.yaml" ] ||
        "$cm" render-views "$models/$file" --style mask --size 1024 --up "$up" --front "$front" -o "$views" -q
    for s in $seeds; do
        p=$work/$name-s$s
        "$bin/perturb_views" "$views/views.yaml" "$p" --seed "$s"
        for rc in off on; do
            reconstruct "$p/views.yaml" "$p/$rc.ply" --set "views.reconcile=$rc" ||
                echo "$name seed $s reconcile $rc: the run failed" >&2
            score "$p/views.yaml" "$p/$rc.ply" front,right,top > "$p/$rc.txt"
        done
        off=$(awk '{ printf "%s%.2f", (NR > 1 ? " / " : ""), $2 }' "$p/off.txt")
        on=$(awk '{ printf "%s%.2f", (NR > 1 ? " / " : ""), $2 }' "$p/on.txt")
        extra=$(awk '{ printf "%s%.2f", (NR > 1 ? " / " : ""), $3 }' "$p/on.txt")
        worst=$(awk 'BEGIN { w = 0 } { if ($2 > w) w = $2 } END { printf "%.2f", w }' "$p/on.txt")
        # The artist's whole error per drawing: what it draws and the model lacks, plus what
        # the model adds beyond it (the bar: on no worse than off, drawing by drawing).
        xoff=$(awk '{ printf "%s%.2f", (NR > 1 ? " / " : ""), $2 + $3 }' "$p/off.txt")
        xon=$(awk '{ printf "%s%.2f", (NR > 1 ? " / " : ""), $2 + $3 }' "$p/on.txt")
        echo "| $name | $s | $off | $on | $extra | $worst | $xoff | $xon |"
    done
done

echo
echo "| model | front missing %, opposite: union | front missing %, opposite: intersect | erased part, % of the front |"
echo "|---|---:|---:|---:|"
echo "$list" | while read -r name file up front; do
    [ -z "$wanted" ] || case ",$wanted," in *",$name,"*) ;; *) continue ;; esac
    views=$work/$name-fb
    [ -f "$views/views.yaml" ] ||
        "$cm" render-views "$models/$file" --style mask --size 1024 --up "$up" --front "$front" \
            --views front,back,right,top -o "$views" -q
    p=$work/$name-fb-erased
    "$bin/perturb_views" "$views/views.yaml" "$p" --scale 0 --turn 0 --shift 0 --wobble 0 --erase back
    for mode in union intersect; do
        reconstruct "$p/views.yaml" "$p/$mode.ply" --set "views.opposite=$mode"
        score "$p/views.yaml" "$p/$mode.ply" front,back,right,top > "$p/$mode.txt"
    done
    erased=$(awk '$2 == "erased_pct" { printf "%.2f", $3 }' "$p/perturbation.txt")
    u=$(awk '$1 == "front" { printf "%.2f", $2 }' "$p/union.txt")
    i=$(awk '$1 == "front" { printf "%.2f", $2 }' "$p/intersect.txt")
    echo "| $name | $u | $i | $erased |"
done
