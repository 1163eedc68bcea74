#!/usr/bin/env bash
# The drawings of ../shared/data/drawings (docs/results/real-drawings.md, "Drawings by
# people"): no manifest comes with them, so this script writes one per drawing set into WORK
# (which image is which view, decided by looking at them), runs pipelines/paper.yaml with a
# preview sheet, and prints per set the holes views.load took, the faces written, the written
# mesh's genus and components, and each view's silhouette error (xor %).
# Usage: bench/views/shared_drawings.sh BUILD_DIR WORK
set -euo pipefail
build=${1:?usage: shared_drawings.sh BUILD_DIR WORK}
work=${2:?usage: shared_drawings.sh BUILD_DIR WORK}
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
src=$(cd "$repo/../shared/data/drawings" && pwd)
exe="$build/bin/conceptmesh"
mkdir -p "$work"

# A manifest WORK/NAME.yaml from VIEW=FILE pairs (FILE under ../shared/data/drawings).
manifest() {
    local name=$1
    shift
    { echo "views:"; for kv in "$@"; do echo "  ${kv%%=*}: $src/${kv#*=}"; done; } > "$work/$name.yaml"
}
# The shrimp: front.png and back.png are the two profiles (length along x, so front and
# back), side.png is face-on (right), top.png from above with the length along x.
manifest shrimp front=sketchrec_shrimp/front.png back=sketchrec_shrimp/back.png \
    right=sketchrec_shrimp/side.png top=sketchrec_shrimp/top.png
manifest abstract front=sketchrec_abstract/front.png right=sketchrec_abstract/side.png \
    top=sketchrec_abstract/top.png bottom=sketchrec_abstract/bottom.png
manifest gopher front=gopher/front.png right=gopher/side.png
manifest gopher_lineart front=gopher/front.png right=gopher/side_lineart.png
manifest morevna front=morevna_saha_body/front.png right=morevna_saha_body/side.png

for set in shrimp abstract gopher gopher_lineart morevna; do
    echo "## $set"
    "$exe" run "$repo/pipelines/paper.yaml" -v --set views.manifest="$work/$set.yaml" \
        --set write.path="$work/$set.obj" --set preview.path="$work/$set.preview.png" \
        --report "$work/$set.json" 2>&1 | grep -E "\[views\] (view|views)" | sed 's/^conceptmesh: //' || true
    python3 -c 'import json,sys
d = json.load(open(sys.argv[1]))
for n in d["nodes"]:
    m = n.get("metrics", {})
    if n["id"] in ("surface", "reduce"):
        print("%s: %s faces" % (n["id"], m.get("faces", m.get("faces_out", "?"))))
    if n["id"] == "write":
        print("written: genus %s, %s component(s)" % (m.get("genus", "?"), m.get("components", "?")))
    if n["id"] == "score":
        xs = sorted((k[len("xor_pct."):], v) for k, v in m.items() if k.startswith("xor_pct."))
        print("xor %%: %s" % ", ".join("%s %.2f" % kv for kv in xs))' "$work/$set.json"
done
