#!/usr/bin/env bash
# Blueprint-style line art (docs/results/real-drawings.md, "Blueprint-style line art"): each
# model drawn by render-views --style blueprint (outline, creases and inner contours in one
# colour and width, no fill), then
#   - the true model's silhouette error against those views (compare --fit bbox), per view;
#   - the reconstruction (pipelines/paper.yaml, or the pipeline PIPELINE names) and its genus
#     against the model's (conceptmesh check: genus = components - euler / 2 of a closed mesh).
# Usage: bench/views/blueprint_bar.sh BUILD_DIR [SIZE] [MODELS] [WORK] [VIEWS] [COLOUR] [WIDTH] [HOLES] [STYLE]
#                                    [PAPER] [GRAIN] [RECONSTRUCT]
#   MODELS: names from bench/models.txt, comma-separated (default: all)
#   VIEWS: render-views --views (default front,right,top; six views let opposite views
#   confirm the openings of line art)
#   HOLES: rule (default): the manifest as render-views writes it, holes judged by the
#   reader's rule alone; user: the manifest a user would write, `holes: keep` on each view
#   whose drawing shows a through-opening that no other given view can confirm (the list in
#   user_keep below); keep: `holes: keep` on every view
#   STYLE: blueprint (default); mask: the true silhouettes (render-views --style mask), for
#   the genus of the visual hull itself
#   PAPER, GRAIN: render-views --paper and --grain (default white, 0; #f2ead8 and 0.03 for a
#   scan of cream paper)
#   RECONSTRUCT: yes (default) runs pipelines/$PIPELINE.yaml for the genus; no prints the
#   silhouette errors alone ("-" in the genus columns)
#   PIPELINE (environment variable): the pipeline of the reconstruction, pipelines/$PIPELINE.yaml
#   (default paper; loft for pipelines/loft.yaml)
#   SET (environment variable): parameters of the reconstruction's nodes, space-separated
#   NODE.PARAM=VALUE, each given to the run as --set (plausible.handles=cut)
set -euo pipefail
build=${1:?usage: blueprint_bar.sh BUILD_DIR [SIZE] [MODELS] [WORK] [VIEWS] [COLOUR] [WIDTH] [HOLES] [STYLE] [PAPER] [GRAIN] [RECONSTRUCT]}
size=${2:-1024}
wanted=${3:-all}
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
models=$(cd "$repo/../shared/data/models" && pwd)
exe="$build/bin/conceptmesh"
work=${4:-$(mktemp -d)}
views=${5:-front,right,top}
colour=${6:-#1f3f8f}
width=${7:-1.5}
holes=${8:-rule}
style=${9:-blueprint}
paper=${10:-white}
grain=${11:-0}
reconstruct=${12:-yes}
pipeline="$repo/pipelines/${PIPELINE:-paper}.yaml"
sets=()
for kv in ${SET:-}; do sets+=(--set "$kv"); done
[[ "$holes" == rule || "$holes" == user || "$holes" == keep ]] || {
    echo "blueprint_bar.sh: HOLES must be rule, user or keep, not '$holes'" >&2
    exit 2
}
mkdir -p "$work"

# The views whose drawing shows a through-opening, as view:opposite, decided from the
# front, right and top drawings as a user reading them would (not from the model's masks).
# A user writes `holes: keep` on such a view only when its opposite view is not drawn: the
# opposite view shows the same opening and confirms it (docs/views.md, `holes`).
user_keep() {
    case "$1" in
    # the ring's hole, seen from above (front and side show a solid band)
    bob) echo "top:bottom" ;;
    # the loops of the arms and the arch under them from the front; the ring of the head
    # and the openings beside the neck from the side
    fertility) echo "front:back right:left" ;;
    # daylight between the arms and the body, closed where the hands come to the hips
    man) echo "front:back" ;;
    # daylight between the legs above the crossed knees
    camel) echo "front:back" ;;
    # spot, bunny, armadillo, fandisk: every closed line is detail (eyes, nostrils, creases,
    # the fur's and the panels' lines); spot's space between its legs shows the hind legs
    *) echo "" ;;
    esac
}

# Writes `holes: keep` into the manifest $1 on the views named (one per argument).
keep_holes() {
    local manifest=$1 v
    shift
    for v in "$@"; do sed -i "s/^  $v: {/  $v: {holes: keep, /" "$manifest"; done
}

genus() {
    "$exe" check "$1" --json 2>/dev/null |
        python3 -c 'import json,sys; d=json.load(sys.stdin); print("%g" % (d["components"] - d["euler"] / 2))'
}

echo "| model | xor % per view ($views) | worst | genus of the model | genus of the reconstruction | holes: keep on |"
echo "|---|---|---:|---:|---:|---|"
grep -v '^#' "$here/../models.txt" | tr -s ' ' | while read -r name file up front; do
    [[ "$wanted" == all || ",$wanted," == *",$name,"* ]] || continue
    d="$work/$name"
    "$exe" render-views "$models/$file" -o "$d" --style "$style" --line-colour "$colour" --line-width "$width" \
        --paper "$paper" --grain "$grain" --size "$size" --views "$views" --up "$up" --front "$front" -q
    kept=()
    if [[ "$holes" == keep ]]; then
        IFS=, read -r -a kept <<<"$views"
    elif [[ "$holes" == user ]]; then
        for pair in $(user_keep "$name"); do
            [[ ",$views," == *",${pair%%:*},"* && ",$views," != *",${pair##*:},"* ]] && kept+=("${pair%%:*}")
        done
    fi
    keep_holes "$d/views.yaml" "${kept[@]}"
    xor=$("$exe" compare "$models/$file" "$d/views.yaml" --fit bbox --up "$up" --front "$front" --json 2>/dev/null |
        python3 -c 'import json,sys; d=json.load(sys.stdin); print(" ".join("%.2f" % v["xor_pct"] for v in d["views"]))')
    worst=$(echo "$xor" | tr ' ' '\n' | sort -g | tail -1)
    if [[ "$reconstruct" == no ]]; then
        echo "| $name | ${xor// / \/ } | $worst | - | - | ${kept[*]:--} |"
        continue
    fi
    "$exe" run "$pipeline" -q --set views.manifest="$d/views.yaml" --set write.path="$d/mesh.obj" \
        --set preview.path="$d/preview.png" "${sets[@]}" >/dev/null 2>&1 ||
        "$exe" run "$pipeline" -q --set views.manifest="$d/views.yaml" --set write.path="$d/mesh.obj" "${sets[@]}"
    echo "| $name | ${xor// / \/ } | $worst | $(genus "$models/$file") | $(genus "$d/mesh.obj") | ${kept[*]:--} |"
done
