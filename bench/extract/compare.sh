#!/bin/sh
# The extractor comparison of docs/results/extract.md: each model of ../shared/data/models
# rendered at 1024 px from front, right and top (binary masks), carved and refined at each
# resolution, then meshed by each extractor configuration; optionally each mesh reduced by
# the paper's importance reduction (mesh.reduce) to one face budget. Per run: faces,
# xor_pct (conceptmesh compare), the extractor's (and reduction's) wall and CPU seconds and
# peak memory (run report), closed / manifold / self-intersections / coincident vertices
# (conceptmesh check).
#
#   bench/extract/compare.sh [BUILD_DIR] [RESOLUTIONS] [CONFIGS] [BUDGET_PCT] > raw.tsv
#
# CONFIGS: space-separated NAME=STAGE[,param=value...] (default: mc, dmc0, dmc, vdb, vdb_a);
# BUDGET_PCT > 0 adds, per model and resolution, every configuration reduced to that
# percentage of the Marching Cubes faces (mesh.reduce, max_angle_deg 40, target_faces).
# MODELS="spot|bob" restricts the models. Work files go to ${TMPDIR:-/tmp}/cm-extract; bench/extract/report.py makes the tables.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
. "$root/bench/common.sh"
bench_setup "${1:-build/release}" cm-extract
# MODELS="spot|bob" keeps those models only.
[ -n "${MODELS:-}" ] && list=$(echo "$list" | grep -E "^($MODELS) ")
resolutions=${2:-128 256 512}
configs=${3:-"mc=extract.marching_cubes dmc0=extract.dual_marching_cubes,max_error=0 dmc=extract.dual_marching_cubes vdb=extract.vdb_volume_to_mesh vdb_a=extract.vdb_volume_to_mesh,adaptivity=0.5"}
budget=${4:-0}

printf 'model\tres\tconfig\treduced\tfaces\txor_pct\tseconds\tcpu_s\tpeak_mb\tclosed_manifold\tself_intersections\tcoincident\n'
echo "$list" | while read -r name file up front; do
    views=$work/$name
    [ -f "$views/views.yaml" ] ||
        "$cm" render-views "$models/$file" --style mask --size 1024 --up "$up" --front "$front" -o "$views" -q
    for r in $resolutions; do
        mc_faces=0
        for c in $configs; do
            cname=${c%%=*}
            spec=${c#*=}
            stage=${spec%%,*}
            sets="--set views.manifest=$views/views.yaml --set hull.resolution=$r"
            rest=$(echo "$spec" | sed -n 's/^[^,]*,//p' | tr ',' ' ')
            for kv in $rest; do sets="$sets --set surface.$kv"; done
            for reduced in no yes; do
                [ $reduced = yes ] && [ "$budget" = 0 ] && continue
                p=$work/p-$cname-$reduced.yaml
                if [ $reduced = no ]; then
                    sed "s/extract.marching_cubes/$stage/" "$root/bench/extract/extract.yaml" > "$p"
                else
                    target=$((mc_faces * budget / 100))
                    sed "s/extract.marching_cubes/$stage/; s/inputs: { mesh: surface }/inputs: { mesh: reduce }/" \
                        "$root/bench/extract/extract.yaml" > "$p"
                    printf '  - id: reduce\n    stage: mesh.reduce\n    inputs: { mesh: surface }\n    params: { max_angle_deg: 40, target_faces: %s }\n' \
                        "$target" >> "$p"
                fi
                mesh=$work/$name-$r-$cname-$reduced.ply
                rep=$work/$name-$r-$cname-$reduced.json
                # shellcheck disable=SC2086
                (cd "$root" && "$cm" run "$p" -q $sets --set "write.path=$mesh" --report "$rep") >&2
                x=$("$cm" compare "$mesh" "$views/views.yaml" --json -q |
                    python3 -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["xor_pct"])')
                chk=$("$cm" check "$mesh" --json 2>/dev/null || true)
                line=$(python3 - "$rep" "$chk" "$reduced" <<'P'
import json, sys
rep = json.load(open(sys.argv[1]))
nodes = {n["id"]: n for n in rep["nodes"]}
node = nodes["reduce"] if sys.argv[3] == "yes" else nodes["surface"]
s = nodes["surface"]
c = json.loads(sys.argv[2])
closed = (c.get("boundary_edges", 1) == 0 and c.get("nonmanifold_edges", 1) == 0 and
          c.get("nonmanifold_vertices", 1) == 0 and c.get("inconsistent_edges", 1) == 0)
secs = s["seconds"] + (node["seconds"] if node is not s else 0)
cpu = s["cpu_seconds"] + (node["cpu_seconds"] if node is not s else 0)
peak = max(s["peak_rss_bytes"], node["peak_rss_bytes"])
closed = closed and c.get("volume", 0) > 0
print("%d\t%.3f\t%.3f\t%.1f\t%s\t%d\t%d" % (node["metrics"]["faces"], secs, cpu, peak / 2**20,
                                  "yes" if closed else "no", c.get("self_intersections", -1),
                                  c.get("coincident_vertices", -1)))
P
)
                faces=$(echo "$line" | cut -f1)
                [ "$cname" = mc ] && [ $reduced = no ] && mc_faces=$faces
                printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$r" "$cname" "$reduced" "$faces" "$x" \
                    "$(echo "$line" | cut -f2-7)"
            done
        done
    done
done
