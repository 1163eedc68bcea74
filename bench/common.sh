# Shared by the bench scripts that run over the models of ../shared/data/models; sourced
# after `root` (the checkout) is set:
#   bench_setup BUILD_DIR WORK_NAME
# sets build (made absolute), cm (the executable), models (the models folder), work
# (${TMPDIR:-/tmp}/WORK_NAME, created) and list (name, file, --up, --front of each model,
# from bench/models.txt).
bench_setup() {
    build=$1
    case $build in /*) ;; *) build=$root/$build ;; esac
    cm=$build/bin/conceptmesh
    models=$root/../shared/data/models
    work=${TMPDIR:-/tmp}/$2
    mkdir -p "$work"
    list=$(grep -v '^#' "$root/bench/models.txt" | tr -s ' ')
}
