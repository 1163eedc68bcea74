#!/bin/sh
# Bar 2 of docs/results/extract.md: pipelines/paper.yaml against pipelines/dmc.yaml (the
# same pipeline with Dual Marching Cubes as the extractor) end to end, on each model of
# ../shared/data/models rendered at 1024 px (binary masks) from front, right and top. Per run:
# faces written, xor_pct of the written mesh (conceptmesh compare), the process's CPU
# seconds (run report), closed / manifold / self-intersections (conceptmesh check).
#
#   bench/extract/pipelines.sh [BUILD_DIR] [RESOLUTION] > raw.tsv
#
# MODELS="spot|bob" restricts the models. Work files go to ${TMPDIR:-/tmp}/cm-extract (the
# views are shared with compare.sh).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-extract
[ -n "${MODELS:-}" ] && list=$(echo "$list" | grep -E "^($MODELS) ")
res=${2:-256}
printf 'model\tres\tpipeline\tfaces\txor_pct\tcpu_s\tclosed_manifold\tself_intersections\n'
echo "$list" | while read -r name file up front; do
    views=$work/$name
    [ -f "$views/views.yaml" ] ||
        "$cm" render-views "$models/$file" --style mask --size 1024 --up "$up" --front "$front" -o "$views" -q
    for p in paper dmc; do
        mesh=$work/$name-$res-$p.obj
        rep=$work/$name-$res-$p.json
        (cd "$root" && "$cm" run "pipelines/$p.yaml" -q --set "views.manifest=$views/views.yaml" \
            --set "hull.resolution=$res" --set "write.path=$mesh" --set "preview.path=$work/$name-$p.png" \
            --report "$rep") >&2
        x=$("$cm" compare "$mesh" "$views/views.yaml" --json -q |
            python3 -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["xor_pct"])')
        chk=$("$cm" check "$mesh" --json 2>/dev/null || true)
        python3 - "$rep" "$chk" "$name" "$res" "$p" "$x" <<'P'
import json, sys
rep = json.load(open(sys.argv[1]))
nodes = {n["id"]: n for n in rep["nodes"]}
c = json.loads(sys.argv[2])
ok = all(c.get(k, 1) == 0 for k in ("boundary_edges", "nonmanifold_edges", "nonmanifold_vertices",
                                     "inconsistent_edges")) and c.get("volume", 0) > 0
print("%s\t%s\t%s\t%d\t%s\t%.2f\t%s\t%d" % (sys.argv[3], sys.argv[4], sys.argv[5], nodes["reduce"]["metrics"]["faces"],
                                        sys.argv[6], rep["cpu_seconds"], "yes" if ok else "no",
                                        c.get("self_intersections", -1)))
P
    done
done
