#!/bin/sh
# Runs every case of bench_hull in its own process (so each reports its own peak
# memory) and prints a Markdown table for docs/results/hull.md.
#   bench/hull/run_hull_bench.sh build/release/bin/bench_hull > /tmp/hull_table.md
set -eu
bench=${1:?usage: run_hull_bench.sh path/to/bench_hull}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for model in bunny spot; do
  for res in 256 512 1024 2048; do
    "$bench" --benchmark_filter="^Chain/$model/$res/" --benchmark_format=json > "$out/$model-$res.json"
  done
done
python3 - "$out" <<'PY'
import json, os, sys
d = sys.argv[1]
print("| model | resolution | carve s (cpu s) | refine s (cpu s) | leaves | active tiles | crossings | thin | cell px | occupancy MB | crossings MB | peak RSS MB |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for model in ("bunny", "spot"):
    for res in (256, 512, 1024, 2048):
        b = json.load(open(os.path.join(d, f"{model}-{res}.json")))["benchmarks"][0]
        print(f"| {model} | {res} | {b['carve_s']:.3f} ({b['carve_cpu_s']:.3f}) | {b['refine_s']:.3f} ({b['refine_cpu_s']:.3f}) | "
              f"{b['leaves']:.0f} | {b['active_tiles']:.0f} | {b['crossings']:.0f} | {b['thin']:.0f} | {b['cell_px']:.2f} | "
              f"{b['occupancy_mb']:.1f} | {b['crossings_mb']:.1f} | {b['peak_rss_mb']:.0f} |")
PY
