#!/bin/sh
# Wall time of one batch through each engine (docs/batch.md): N copies of the spot example
# (examples/spot, three 512 px drawings) at one resolution, through `--engine local` with
# 1 and 2 jobs and, when a one-node Slurm cluster can start here (tests/batch/slurm_cluster.sh,
# as root), through `--engine slurm`; each batch's peak memory estimate against the peak
# measured; and whether the engines' meshes are byte-identical.
#
#   bench/batch/engines.sh [BUILD_DIR] [N] [RESOLUTION] > table.md
#
# BUILD_DIR defaults to build/release, N to 6, RESOLUTION to 128. Work files go to
# ${TMPDIR:-/tmp}/cm-batch-bench.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-build/release}
n=${2:-6}
res=${3:-128}
case $build in /*) ;; *) build=$root/$build ;; esac
cm=$build/bin/conceptmesh
work=${TMPDIR:-/tmp}/cm-batch-bench
rm -rf "$work"
mkdir -p "$work"
{
  echo "pipeline: $root/pipelines/paper.yaml"
  echo "set: {hull.resolution: $res}"
  echo "assets:"
  i=1
  while [ $i -le "$n" ]; do
    echo "  - name: spot$i"
    echo "    views: $root/examples/spot/views.yaml"
    i=$((i + 1))
  done
} > "$work/assets.yaml"

seconds() { date +%s.%N; }
row() {   # engine jobs out-dir seconds
  peak=$(python3 -c "import json,sys; a=json.load(open('$3/batch-report.json'))['assets']; print('%.0f / %.0f' % (max(x['peak_mib'] for x in a), max(x['memory_estimate_mib'] for x in a)))")
  echo "| $1 | $2 | $n | $res | $4 | $peak |"
}
echo "| engine | jobs | assets | resolution | wall s | peak / estimate MiB |"
echo "|---|---:|---:|---:|---:|---:|"
for jobs in 1 2; do
  t0=$(seconds)
  "$cm" batch "$work/assets.yaml" --jobs $jobs -q -o "$work/local$jobs" > /dev/null
  row local $jobs "$work/local$jobs" "$(echo "$(seconds) - $t0" | bc | xargs printf '%.1f')"
done
if "$root/tests/batch/slurm_cluster.sh" start "$work/cluster" > "$work/cluster.txt" 2>&1; then
  export SLURM_CONF="$work/cluster/slurm.conf"
  t0=$(seconds)
  "$cm" batch "$work/assets.yaml" --engine slurm --jobs 2 -q -o "$work/slurm" > /dev/null || true
  row slurm 2 "$work/slurm" "$(echo "$(seconds) - $t0" | bc | xargs printf '%.1f')"
  "$root/tests/batch/slurm_cluster.sh" stop "$work/cluster"
  same=yes
  i=1
  while [ $i -le "$n" ]; do
    cmp -s "$work/slurm/spot$i/spot$i.glb" "$work/local2/spot$i/spot$i.glb" || same=no
    i=$((i + 1))
  done
  echo
  echo "Slurm and local meshes byte-identical: $same"
else
  echo
  echo "No Slurm row: $(cat "$work/cluster.txt")"
fi
