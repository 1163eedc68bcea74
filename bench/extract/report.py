#!/usr/bin/env python3
"""Tables (markdown, on stdout) and the plot (PNG, drawn with oiiotool) of
docs/results/extract.md, from the raw table bench/extract/compare.sh prints.

    report.py RAW_TSV [PLOT_PNG]
    report.py --pipelines RAW_TSV     (bench/extract/pipelines.sh: bar 2)
    report.py --speed RAW_TSV         (bench/extract/speed.sh outputs concatenated: bar 3)

RAW_TSV may hold several resolutions (compare.sh's outputs concatenated, one header);
the second plot (PLOT_PNG with -res) shows the error against the resolution.
"""
import csv
import os
import subprocess
import sys

def mean(xs):
    return sum(xs) / len(xs) if xs else float("nan")


if len(sys.argv) > 2 and sys.argv[1] == "--pipelines":
    # bench/extract/pipelines.sh: paper.yaml against dmc.yaml, per model.
    rows = list(csv.DictReader(open(sys.argv[2]), delimiter="\t"))
    print("| model | paper.yaml faces / xor_pct | dmc.yaml faces / xor_pct | faces dmc / paper | "
          "xor_pct dmc - paper | CPU s paper / dmc | all clean |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    pairs = []
    for m in dict.fromkeys(r["model"] for r in rows):
        p = [r for r in rows if r["model"] == m and r["pipeline"] == "paper"]
        d = [r for r in rows if r["model"] == m and r["pipeline"] == "dmc"]
        if not p or not d:
            continue
        p, d = p[0], d[0]
        pairs.append((p, d))
        clean = all(r["closed_manifold"] == "yes" and r["self_intersections"] == "0" for r in (p, d))
        print("| %s | %s / %.3f | %s / %.3f | %.2f | %+.3f | %s / %s | %s |" % (
            m, p["faces"], float(p["xor_pct"]), d["faces"], float(d["xor_pct"]),
            float(d["faces"]) / float(p["faces"]), float(d["xor_pct"]) - float(p["xor_pct"]),
            p["cpu_s"], d["cpu_s"], "yes" if clean else "no"))
    print("| mean | %.0f / %.3f | %.0f / %.3f | %.2f | %+.3f | %.2f / %.2f | |" % (
        mean([float(p["faces"]) for p, _ in pairs]), mean([float(p["xor_pct"]) for p, _ in pairs]),
        mean([float(d["faces"]) for _, d in pairs]), mean([float(d["xor_pct"]) for _, d in pairs]),
        mean([float(d["faces"]) / float(p["faces"]) for p, d in pairs]),
        mean([float(d["xor_pct"]) - float(p["xor_pct"]) for p, d in pairs]),
        mean([float(p["cpu_s"]) for p, _ in pairs]), mean([float(d["cpu_s"]) for _, d in pairs])))
    sys.exit(0)

if len(sys.argv) > 2 and sys.argv[1] == "--speed":
    # bench/extract/speed.sh outputs (concatenated): per model and method, the runs' CPU seconds.
    rows = [r for r in csv.DictReader(open(sys.argv[2]), delimiter="\t") if r["model"] != "model"]
    print("| model | resolution | runs | faces (MC -> out) | MC CPU s | MC + mesh.reduce CPU s | "
          "adaptive DMC CPU s | DMC / (MC + reduce) | load (1 min) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for key in dict.fromkeys((r["model"], r["res"]) for r in rows):
        sel = [r for r in rows if (r["model"], r["res"]) == key]
        cpu = {m: [float(r["cpu_s"]) for r in sel if r["method"] == m] for m in ("mc", "mc+reduce", "dmc")}
        n = min(len(v) for v in cpu.values())
        fmt = lambda v: "%.2f (%.2f-%.2f)" % (mean(v), min(v), max(v))
        mcf = [r["faces"] for r in sel if r["method"] == "mc"][0]
        out = [r["faces"] for r in sel if r["method"] == "dmc"][0]
        loads = [float(r["load1"]) for r in sel]
        print("| %s | %s | %d | %s -> %s | %s | %s | %s | %.2f | %.0f-%.0f |" % (
            key[0], key[1], n, mcf, out, fmt(cpu["mc"]), fmt(cpu["mc+reduce"]), fmt(cpu["dmc"]),
            mean(cpu["dmc"]) / mean(cpu["mc+reduce"]), min(loads), max(loads)))
    sys.exit(0)

rows = [r for r in csv.DictReader(open(sys.argv[1]), delimiter="\t") if r["model"] != "model"]
plot = sys.argv[2] if len(sys.argv) > 2 else os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "../../docs/results/extract.png")
configs = []
for r in rows:
    if r["config"] not in configs:
        configs.append(r["config"])
label = {"mc": "Marching Cubes", "dmc0": "DMC, max_error 0", "dmc": "DMC adaptive (defaults)",
         "vdb": "OpenVDB, adaptivity 0", "vdb_a": "OpenVDB, adaptivity 0.5"}


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
        cpu = "cpu_s" in sel[0]
        print("| extractor | mean faces (%% of MC) | mean xor_pct | mean %s | peak MB | "
              "closed, manifold, outward | self-intersections |%s" % (
                  "CPU s" if cpu else "seconds", " coincident vertices |" if cpu else ""))
        print("|---|---:|---:|---:|---:|---:|---:|" + ("---:|" if cpu else ""))
        for c in configs:
            cs = [r for r in sel if r["config"] == c]
            if not cs:
                continue
            pct = mean([100 * float(r["faces"]) / mc[r["model"]] for r in cs if r["model"] in mc])
            ok = sum(r["closed_manifold"] == "yes" for r in cs)
            si = sum(int(r["self_intersections"]) for r in cs)
            line = "| %s | %d (%.1f %%) | %.3f | %.2f | %.0f | %d / %d | %d |" % (
                label.get(c, c), mean([float(r["faces"]) for r in cs]), pct,
                mean([float(r["xor_pct"]) for r in cs]), mean([float(r["cpu_s" if cpu else "seconds"]) for r in cs]),
                max(float(r["peak_mb"]) for r in cs), ok, len(cs), si)
            if cpu:
                line += " %d |" % sum(int(r["coincident"]) for r in cs)
            print(line)
        print()
        if reduced == "no" and {"mc", "dmc"} <= set(configs):
            m = {c: [r for r in sel if r["config"] == c] for c in ("mc", "dmc")}
            if len(m["mc"]) == len(m["dmc"]):
                d = mean([float(r["xor_pct"]) for r in m["dmc"]]) - mean([float(r["xor_pct"]) for r in m["mc"]])
                f = 100 * sum(float(r["faces"]) for r in m["dmc"]) / sum(float(r["faces"]) for r in m["mc"])
                print("Adaptive DMC against Marching Cubes: mean xor_pct %+.3f percentage points, %.1f %% of "
                      "the faces (all models summed), %d / %d clean.\n" % (
                          d, f, sum(r["closed_manifold"] == "yes" and r["self_intersections"] == "0" and
                                    r.get("coincident", "0") == "0" for r in m["dmc"]), len(m["dmc"])))
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

# The second plot: mean xor_pct straight out of each extractor against the resolution.
allres = sorted({int(r["res"]) for r in rows})
if len(allres) > 1:
    plot2 = plot.replace(".png", "-res.png")
    models_all = [set(r["model"] for r in rows if int(r["res"]) == q and r["reduced"] == "no") for q in allres]
    common = set.intersection(*models_all)
    series = {}
    for c in configs:
        ys = []
        for q in allres:
            cs = [float(r["xor_pct"]) for r in rows
                  if int(r["res"]) == q and r["config"] == c and r["reduced"] == "no" and r["model"] in common]
            ys.append(mean(cs) if cs else None)
        series[c] = ys
    ymax = max(y for ys in series.values() for y in ys if y is not None) * 1.15
    cmd = ["oiiotool", "--create", "%dx%d" % (W, H), "3", "--fill:color=1,1,1", "0,0,%d,%d" % (W, H)]
    cmd += ["--box:color=0.2,0.2,0.2", "%d,%d,%d,%d" % (x0, top, x0 + pw, top + ph)]
    cmd += ["--text:x=%d:y=%d:size=18:color=0,0,0:font=%s" % (x0, top - 15, font),
            "mean xor_pct straight out of the extractor, against the resolution (%d models)" % len(common)]
    xs = [x0 + int(pw * (0.1 + 0.8 * i / (len(allres) - 1))) for i in range(len(allres))]
    for t in range(5):
        y = top + ph - int(ph * t / 4)
        cmd += ["--line:color=0.88,0.88,0.88", "%d,%d,%d,%d" % (x0 + 1, y, x0 + pw - 1, y)]
        cmd += ["--text:x=%d:y=%d:size=13:color=0.2,0.2,0.2:font=%s" % (x0 - 45, y + 5, font), "%.3f" % (ymax * t / 4)]
    for x, q in zip(xs, allres):
        cmd += ["--text:x=%d:y=%d:size=13:color=0.2,0.2,0.2:font=%s" % (x - 12, top + ph + 18, font), "%d" % q]
    for i, c in enumerate(configs):
        col = colours[i % len(colours)]
        pts2 = [(x, top + ph - int(ph * y / ymax)) for x, y in zip(xs, series[c]) if y is not None]
        for (xa, ya), (xb, yb) in zip(pts2, pts2[1:]):
            cmd += ["--line:color=%s" % col, "%d,%d,%d,%d" % (xa, ya, xb, yb)]
        for x, y in pts2:
            cmd += ["--box:color=%s:fill=1" % col, "%d,%d,%d,%d" % (x - 5, y - 5, x + 5, y + 5)]
        ly = top + 20 + 22 * i
        cmd += ["--box:color=%s:fill=1" % col, "%d,%d,%d,%d" % (x0 + pw + 20, ly - 8, x0 + pw + 30, ly + 2)]
        cmd += ["--text:x=%d:y=%d:size=13:color=0,0,0:font=%s" % (x0 + pw + 36, ly + 2, font), label.get(c, c)]
    cmd += ["-d", "uint8", "-o", plot2]
    subprocess.run(cmd, check=True)
    print("Plot: `%s` (means over the models run at every resolution)." % os.path.basename(plot2))
