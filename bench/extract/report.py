#!/usr/bin/env python3
"""Tables (markdown, on stdout) and the plot (PNG, drawn with oiiotool) of
docs/results/extract.md, from the raw table bench/extract/compare.sh prints.

    report.py RAW_TSV [PLOT_PNG]
"""
import csv
import os
import subprocess
import sys

rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
plot = sys.argv[2] if len(sys.argv) > 2 else os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "../../docs/results/extract.png")
configs = []
for r in rows:
    if r["config"] not in configs:
        configs.append(r["config"])
label = {"mc": "Marching Cubes", "dmc0": "DMC, max_error 0", "dmc": "DMC adaptive (defaults)",
         "vdb": "OpenVDB, adaptivity 0", "vdb_a": "OpenVDB, adaptivity 0.5"}


def mean(xs):
    return sum(xs) / len(xs) if xs else float("nan")


for res in sorted({int(r["res"]) for r in rows}):
    for reduced in ("no", "yes"):
        sel = [r for r in rows if int(r["res"]) == res and r["reduced"] == reduced]
        if not sel:
            continue
        models = sorted({r["model"] for r in sel})
        mc = {r["model"]: float(r["faces"]) for r in rows
              if int(r["res"]) == res and r["config"] == "mc" and r["reduced"] == "no"}
        print("### Resolution %d, %s\n" % (res, "reduced to 5 % of the Marching Cubes faces (mesh.reduce)"
                                             if reduced == "yes" else "straight out of the extractor"))
        print("| extractor | mean faces (% of MC) | mean xor_pct | mean seconds | peak MB | "
              "closed, manifold, outward | self-intersections |")
        print("|---|---:|---:|---:|---:|---:|---:|")
        for c in configs:
            cs = [r for r in sel if r["config"] == c]
            if not cs:
                continue
            pct = mean([100 * float(r["faces"]) / mc[r["model"]] for r in cs if r["model"] in mc])
            ok = sum(r["closed_manifold"] == "yes" for r in cs)
            si = sum(int(r["self_intersections"]) for r in cs)
            print("| %s | %d (%.1f %%) | %.3f | %.2f | %.0f | %d / %d | %d |" % (
                label.get(c, c), mean([float(r["faces"]) for r in cs]), pct,
                mean([float(r["xor_pct"]) for r in cs]), mean([float(r["seconds"]) for r in cs]),
                max(float(r["peak_mb"]) for r in cs), ok, len(cs), si))
        print()
        print("| model | " + " | ".join(label.get(c, c) for c in configs) + " |")
        print("|---|" + "---:|" * len(configs))
        for m in models:
            cells = []
            for c in configs:
                r = [x for x in sel if x["model"] == m and x["config"] == c]
                cells.append("%s / %.3f" % (r[0]["faces"], float(r[0]["xor_pct"])) if r else "")
            print("| %s | %s |" % (m, " | ".join(cells)))
        print("\n(faces / xor_pct)\n")

# The plot: per configuration at the first resolution, mean xor_pct against mean faces (% of MC).
res = sorted({int(r["res"]) for r in rows})
res = 256 if 256 in res else res[0]
mc = {r["model"]: float(r["faces"]) for r in rows if int(r["res"]) == res and r["config"] == "mc" and r["reduced"] == "no"}
pts = []
for reduced in ("no", "yes"):
    for c in configs:
        cs = [r for r in rows if int(r["res"]) == res and r["config"] == c and r["reduced"] == reduced and r["model"] in mc]
        if cs:
            pts.append((c, reduced, mean([100 * float(r["faces"]) / mc[r["model"]] for r in cs]),
                        mean([float(r["xor_pct"]) for r in cs])))
W, H, x0, top, pw, ph = 900, 520, 80, 50, 560, 400
font = "DejaVuSans"
xmax = 105.0
ymax = max(p[3] for p in pts) * 1.15
cmd = ["oiiotool", "--create", "%dx%d" % (W, H), "3", "--fill:color=1,1,1", "0,0,%d,%d" % (W, H)]
cmd += ["--box:color=0.2,0.2,0.2", "%d,%d,%d,%d" % (x0, top, x0 + pw, top + ph)]
cmd += ["--text:x=%d:y=%d:size=18:color=0,0,0:font=%s" % (x0, top - 15, font),
        "resolution %d: mean xor_pct against faces (%% of Marching Cubes)" % res]
for t in range(5):
    y = top + ph - int(ph * t / 4)
    x = x0 + int(pw * t / 4)
    cmd += ["--line:color=0.88,0.88,0.88", "%d,%d,%d,%d" % (x0 + 1, y, x0 + pw - 1, y)]
    cmd += ["--text:x=%d:y=%d:size=13:color=0.2,0.2,0.2:font=%s" % (x0 - 45, y + 5, font), "%.3f" % (ymax * t / 4)]
    cmd += ["--text:x=%d:y=%d:size=13:color=0.2,0.2,0.2:font=%s" % (x - 10, top + ph + 18, font), "%d" % (xmax * t / 4)]
colours = ["0.2,0.2,0.2", "0.1,0.45,0.9", "1,0.4,0.1", "0.2,0.65,0.3", "0.6,0.3,0.7"]
for i, (c, reduced, px, py) in enumerate(pts):
    col = colours[configs.index(c) % len(colours)]
    x, y = x0 + int(pw * px / xmax), top + ph - int(ph * py / ymax)
    s = 6 if reduced == "no" else 4
    cmd += ["--box:color=%s:fill=%d" % (col, 1 if reduced == "no" else 0), "%d,%d,%d,%d" % (x - s, y - s, x + s, y + s)]
for i, c in enumerate(configs):
    col = colours[i % len(colours)]
    ly = top + 20 + 22 * i
    cmd += ["--box:color=%s:fill=1" % col, "%d,%d,%d,%d" % (x0 + pw + 20, ly - 8, x0 + pw + 30, ly + 2)]
    cmd += ["--text:x=%d:y=%d:size=13:color=0,0,0:font=%s" % (x0 + pw + 36, ly + 2, font), label.get(c, c)]
ly = top + 30 + 22 * len(configs)
cmd += ["--text:x=%d:y=%d:size=13:color=0,0,0:font=%s" % (x0 + pw + 20, ly, font), "filled: extractor alone"]
cmd += ["--text:x=%d:y=%d:size=13:color=0,0,0:font=%s" % (x0 + pw + 20, ly + 20, font), "open: + mesh.reduce to 5 %"]
cmd += ["-d", "uint8", "-o", plot]
subprocess.run(cmd, check=True)
print("Plot: `%s` (means over the models)." % os.path.basename(plot))
