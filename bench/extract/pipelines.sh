#!/bin/sh
# Bar 2 of docs/results/extract.md: pipelines/paper.yaml against pipelines/dmc.yaml (the
# same pipeline with Dual Marching Cubes as the extractor) end to end, on each model of
# ../shared/data/models rendered at 1024 px (binary masks) from front, right and top. Per run:
# faces written, xor_pct of the written mesh (conceptmesh compare), the process's CPU
# seconds (run report), closed / manifold / self-intersections (conceptmesh check).
#
#   bench/extract/pipelines.sh [BUILD_DIR] [RESOLUTION] [FACTORS] > raw.tsv
#
# FACTORS (e.g. "0.98 1 1.25"): both pipelines run again with mesh.reduce stopped at that
# factor times the faces paper.yaml writes as shipped (target_faces; a pipeline whose own
# end comes first stops there), so the two are compared at matched face counts. Column
# `target`: 0 for the pipelines as shipped.
#
# MODELS="spot|bob" restricts the models. Work files go to ${TMPDIR:-/tmp}/cm-extract (the
# views are shared with compare.sh).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-extract
[ -n "${MODELS:-}" ] && list=$(echo "$list" | grep -E "^($MODELS) ")
res=${2:-256}
factors=${3:-}
printf 'model\tres\tpipeline\ttarget\tfaces\txor_pct\tcpu_s\tclosed_manifold\tself_intersections\n'
echo "$list" | while read -r name file up front; do
    views=$work/$name
    [ -f "$views/views.yaml" ] ||
        "$cm" render-views "$models/$file" --style mask --size 1024 --up "$up" --front "$front" -o "$views" -q
    paper_faces=0
    for run in $(echo "paper:0 dmc:0"; for f in $factors; do echo "paper:$f dmc:$f"; done); do
        p=${run%%:*}
        f=${run#*:}
        target=0
        [ "$f" = 0 ] || target=$(python3 -c "print(int($paper_faces * $f))")
        mesh=$work/$name-$res-$p-$f.obj
        rep=$work/$name-$res-$p-$f.json
        (cd "$root" && "$cm" run "pipelines/$p.yaml" -q --set "views.manifest=$views/views.yaml" \
            --set "hull.resolution=$res" --set "write.path=$mesh" --set "preview.path=$work/$name-$p.png" \
            --set "reduce.target_faces=$target" --report "$rep") >&2
        x=$("$cm" compare "$mesh" "$views/views.yaml" --json -q |
            python3 -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["xor_pct"])')
        chk=$("$cm" check "$mesh" --json 2>/dev/null || true)
        line=$(python3 - "$rep" "$chk" "$name" "$res" "$p" "$target" "$x" <<'P'
import json, sys
rep = json.load(open(sys.argv[1]))
nodes = {n["id"]: n for n in rep["nodes"]}
c = json.loads(sys.argv[2])
ok = all(c.get(k, 1) == 0 for k in ("boundary_edges", "nonmanifold_edges", "nonmanifold_vertices",
                                     "inconsistent_edges")) and c.get("volume", 0) > 0
print("%s\t%s\t%s\t%s\t%d\t%s\t%.2f\t%s\t%d" % (sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6],
                                            nodes["reduce"]["metrics"]["faces"], sys.argv[7], rep["cpu_seconds"],
                                            "yes" if ok else "no", c.get("self_intersections", -1)))
P
)
        echo "$line"
        [ "$p" = paper ] && [ "$f" = 0 ] && paper_faces=$(echo "$line" | cut -f5)
    done
done
