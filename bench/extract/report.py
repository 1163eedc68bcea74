#!/usr/bin/env python3
"""Tables (markdown, on stdout) and the plot (PNG, drawn with oiiotool) of
docs/results/extract.md, from the raw table bench/extract/compare.sh prints.

    report.py RAW_TSV [PLOT_PNG]
    report.py --pipelines RAW_TSV...  (bench/extract/pipelines.sh outputs: bar 2)
    report.py --speed RAW_TSV         (bench/extract/speed.sh outputs concatenated: bar 3)

RAW_TSV may hold several resolutions (compare.sh's outputs concatenated, one header).
Plots: PLOT_PNG (means at 256, straight and reduced), PLOT_PNG with -models-RES (one panel
per model at each resolution) and with -res (the error against the resolution).
"""
import csv
import math
import os
import subprocess
import sys

def mean(xs):
    return sum(xs) / len(xs) if xs else float("nan")


if len(sys.argv) > 2 and sys.argv[1] == "--pipelines":
    # bench/extract/pipelines.sh: paper.yaml against dmc.yaml, per model, as shipped (target
    # 0) and, when it ran them, both stopped at matched face counts (target > 0).
    # Several TSVs (runs with different factors) are merged; a run repeated keeps its first.
    rows, seen = [], set()
    for path in sys.argv[2:]:
        for r in csv.DictReader(open(path), delimiter="\t"):
            r.setdefault("target", "0")
            key = (r["model"], r["pipeline"], r["target"])
            if key not in seen:
                seen.add(key)
                rows.append(r)
    models = list(dict.fromkeys(r["model"] for r in rows))

    def pick(m, p, t):
        sel = [r for r in rows if r["model"] == m and r["pipeline"] == p and r["target"] == t]
        return sel[0] if sel else None

    print("| model | paper.yaml faces / xor_pct | dmc.yaml faces / xor_pct | faces dmc / paper | "
          "xor_pct dmc - paper | CPU s paper / dmc | all clean |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    pairs = []
    for m in models:
        p, d = pick(m, "paper", "0"), pick(m, "dmc", "0")
        if not p or not d:
            continue
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
    # Matched face counts: per factor of paper.yaml's shipped count, both stopped there.
    def factor(r):
        p0 = pick(r["model"], "paper", "0")
        return round(float(r["target"]) / float(p0["faces"]), 2) if p0 and r["target"] != "0" else None

    factors = sorted({factor(r) for r in rows} - {None})
    if factors:
        cell = {}
        for m in models:
            for f in factors:
                sel = [r for r in rows if r["model"] == m and factor(r) == f]
                p = [r for r in sel if r["pipeline"] == "paper"]
                d = [r for r in sel if r["pipeline"] == "dmc"]
                if p and d:
                    cell[m, f] = (p[0], d[0], float(d[0]["xor_pct"]) - float(p[0]["xor_pct"]),
                                  int(d[0]["faces"]) <= int(p[0]["faces"]) and float(d[0]["xor_pct"]) < float(p[0]["xor_pct"]))
        print("\nBoth stopped by `mesh.reduce`'s `target_faces` at a factor of the faces paper.yaml writes "
              "as shipped (a pipeline whose own end comes first stops there): dmc.yaml's `xor_pct` minus "
              "paper.yaml's; `<=` marks dmc.yaml with no more faces and a lower `xor_pct`.\n")
        print("| model | " + " | ".join("%.2fx" % f for f in factors) + " |")
        print("|---|" + "---:|" * len(factors))
        for m in models:
            print("| %s | %s |" % (m, " | ".join("%+.3f%s" % (cell[m, f][2], " <=" if cell[m, f][3] else "")
                                               if (m, f) in cell else "" for f in factors)))
        ds = {f: [cell[m, f] for m in models if (m, f) in cell] for f in factors}
        print("| mean, dmc.yaml <= | %s |" % " | ".join(
            "%+.3f, %d / %d" % (mean([c[2] for c in ds[f]]), sum(c[3] for c in ds[f]), len(ds[f])) for f in factors))
        print("\n<details><summary>faces and xor_pct of each run</summary>\n")
        print("| model | factor | paper.yaml faces / xor_pct | dmc.yaml faces / xor_pct | dmc - paper |")
        print("|---|---:|---:|---:|---:|")
        for m in models:
            for f in factors:
                if (m, f) in cell:
                    p, d, dx, dom = cell[m, f]
                    print("| %s | %.2fx | %s / %.3f | %s / %.3f | %+.3f%s |" % (
                        m, f, p["faces"], float(p["xor_pct"]), d["faces"], float(d["xor_pct"]), dx, " <=" if dom else ""))
        print("\n</details>")
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
        print("### Resolution %d, %s\n" % (res, "each followed by mesh.reduce to at most 5 % of the Marching Cubes "
                                             "faces (40 degrees)" if reduced == "yes" else "straight out of the extractor"))
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
                if not r:
                    cells.append("")
                    continue
                r = r[0]
                flags = [] if r["closed_manifold"] == "yes" else ["not closed"]
                if int(r["self_intersections"]):
                    flags.append("%s crossing pairs" % r["self_intersections"])
                if int(r.get("coincident", "0") or 0):
                    flags.append("%s coincident" % r["coincident"])
                cells.append("%s / %.3f%s" % (r["faces"], float(r["xor_pct"]),
                                               " (%s)" % ", ".join(flags) if flags else ""))
            print("| %s | %s |" % (m, " | ".join(cells)))
        print("\n(faces / xor_pct; a mesh that is not clean says what it has)\n")

# Drawing with oiiotool: a plot is a list of oiiotool arguments on one white canvas.
FONT = "DejaVuSans"
COLOURS = ["0.2,0.2,0.2", "0.1,0.45,0.9", "1,0.4,0.1", "0.2,0.65,0.3", "0.6,0.3,0.7"]


def text(x, y, s, size=13, colour="0,0,0"):
    return ["--text:x=%d:y=%d:size=%d:color=%s:font=%s" % (x, y, size, colour, FONT), s]


def canvas(w, h):
    return ["oiiotool", "--create", "%dx%d" % (w, h), "3", "--fill:color=1,1,1", "0,0,%d,%d" % (w, h)]


def nice_max(v):
    """The smallest of 1, 2, 2.5, 5 times a power of ten at or above v."""
    p = 10 ** math.floor(math.log10(v)) if v > 0 else 1
    for m in (1, 2, 2.5, 5, 10):
        if m * p >= v:
            return m * p
    return 10 * p


def scatter(x0, top, pw, ph, pts, ymax, xlog, title, ticks=True):
    """One panel: pts are (x, y, colour, filled); x is the faces in % of Marching Cubes
    (log axis from 2 to 150 % when xlog), y the xor_pct from 0 to ymax."""
    cmd = ["--box:color=0.2,0.2,0.2", "%d,%d,%d,%d" % (x0, top, x0 + pw, top + ph)]
    cmd += text(x0, top - 8, title, 15 if not ticks else 18)
    lo, hi = math.log(2), math.log(150)
    xpos = (lambda v: x0 + int(pw * (math.log(max(v, 2)) - lo) / (hi - lo))) if xlog else (
        lambda v: x0 + int(pw * v / 100.0))
    for t in range(5):
        y = top + ph - int(ph * t / 4)
        cmd += ["--line:color=0.88,0.88,0.88", "%d,%d,%d,%d" % (x0 + 1, y, x0 + pw - 1, y)]
        cmd += text(x0 - 42, y + 5, ("%.3f" if ymax < 1 else "%.2f") % (ymax * t / 4), 12, "0.2,0.2,0.2")
    for v in ((2, 5, 10, 20, 50, 100) if xlog else (0, 25, 50, 75, 100)):
        x = xpos(v)
        cmd += ["--line:color=0.88,0.88,0.88", "%d,%d,%d,%d" % (x, top + 1, x, top + ph - 1)]
        cmd += text(x - 8, top + ph + 16, "%d" % v, 12, "0.2,0.2,0.2")
    for px, py, col, filled in pts:
        x, y = xpos(px), top + ph - int(ph * min(py, ymax) / ymax)
        s = 6 if filled else 5
        cmd += ["--box:color=%s:fill=%d" % (col, 1 if filled else 0), "%d,%d,%d,%d" % (x - s, y - s, x + s, y + s)]
    return cmd


def legend(x, y, reduced_note=True):
    cmd = []
    for i, c in enumerate(configs):
        ly = y + 22 * i
        cmd += ["--box:color=%s:fill=1" % COLOURS[i % len(COLOURS)], "%d,%d,%d,%d" % (x, ly - 8, x + 10, ly + 2)]
        cmd += text(x + 16, ly + 2, label.get(c, c))
    if reduced_note:
        ly = y + 10 + 22 * len(configs)
        cmd += text(x, ly, "filled: extractor alone")
        cmd += text(x, ly + 20, "open: + mesh.reduce (5 % budget)")
    return cmd


def faces_pct(r, mc):
    return 100 * float(r["faces"]) / mc[r["model"]]


def mc_faces(res):
    return {r["model"]: float(r["faces"]) for r in rows
            if int(r["res"]) == res and r["config"] == "mc" and r["reduced"] == "no"}


# The plot of the means: per configuration at resolution 256 (or the first), mean xor_pct
# against mean faces (% of Marching Cubes), straight and reduced.
allres = sorted({int(r["res"]) for r in rows})
res = 256 if 256 in allres else allres[0]
mc = mc_faces(res)
pts = []
for reduced in ("no", "yes"):
    for i, c in enumerate(configs):
        cs = [r for r in rows if int(r["res"]) == res and r["config"] == c and r["reduced"] == reduced and r["model"] in mc]
        if cs:
            pts.append((mean([faces_pct(r, mc) for r in cs]), mean([float(r["xor_pct"]) for r in cs]),
                        COLOURS[i % len(COLOURS)], reduced == "no"))
W, H, x0, top, pw, ph = 900, 520, 80, 50, 560, 400
cmd = canvas(W, H) + scatter(x0, top, pw, ph, pts, nice_max(max(p[1] for p in pts) * 1.05), True,
                             "resolution %d: mean xor_pct against faces (%% of Marching Cubes, log)" % res)
cmd += legend(x0 + pw + 20, top + 20) + ["-d", "uint8", "-o", plot]
subprocess.run(cmd, check=True)
print("Plot: `%s` (means over the models)." % os.path.basename(plot))

# Per model: one panel each, at every resolution that has all the models of the first.
for q in allres:
    mcq = mc_faces(q)
    models = sorted(mcq)
    if len(models) < 2:
        continue
    cols = 4
    nrow = (len(models) + cols - 1) // cols
    PW, PH, LM, TM = 250, 190, 60, 70
    W2 = LM + cols * (PW + LM) + 230
    H2 = TM + nrow * (PH + TM)
    cmd = canvas(W2, H2) + text(LM, 28, "resolution %d, per model: xor_pct against faces (%% of Marching Cubes, log)" % q, 18)
    for k, m in enumerate(models):
        sel = [r for r in rows if int(r["res"]) == q and r["model"] == m]
        pts = [(faces_pct(r, mcq), float(r["xor_pct"]), COLOURS[configs.index(r["config"]) % len(COLOURS)],
                r["reduced"] == "no") for r in sel]
        x = LM + (k % cols) * (PW + LM)
        y = TM + (k // cols) * (PH + TM)
        cmd += scatter(x, y, PW, PH, pts, nice_max(max(p[1] for p in pts) * 1.05), True, m, ticks=False)
    cmd += legend(LM + cols * (PW + LM), TM + 20) + ["-d", "uint8", "-o", plot.replace(".png", "-models-%d.png" % q)]
    subprocess.run(cmd, check=True)
    print("Plot: `%s` (per model)." % os.path.basename(plot.replace(".png", "-models-%d.png" % q)))

# Mean xor_pct straight out of each extractor against the resolution.
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
    ymax = nice_max(max(y for ys in series.values() for y in ys if y is not None) * 1.05)
    cmd = canvas(W, H) + ["--box:color=0.2,0.2,0.2", "%d,%d,%d,%d" % (x0, top, x0 + pw, top + ph)]
    cmd += text(x0, top - 15, "mean xor_pct straight out of the extractor, against the resolution (%d models)" % len(common), 18)
    xs = [x0 + int(pw * (0.1 + 0.8 * i / (len(allres) - 1))) for i in range(len(allres))]
    for t in range(5):
        y = top + ph - int(ph * t / 4)
        cmd += ["--line:color=0.88,0.88,0.88", "%d,%d,%d,%d" % (x0 + 1, y, x0 + pw - 1, y)]
        cmd += text(x0 - 45, y + 5, "%.3f" % (ymax * t / 4), 13, "0.2,0.2,0.2")
    for x, q in zip(xs, allres):
        cmd += text(x - 12, top + ph + 18, "%d" % q, 13, "0.2,0.2,0.2")
    for i, c in enumerate(configs):
        col = COLOURS[i % len(COLOURS)]
        pts2 = [(x, top + ph - int(ph * y / ymax)) for x, y in zip(xs, series[c]) if y is not None]
        for (xa, ya), (xb, yb) in zip(pts2, pts2[1:]):
            cmd += ["--line:color=%s" % col, "%d,%d,%d,%d" % (xa, ya, xb, yb)]
        for x, y in pts2:
            cmd += ["--box:color=%s:fill=1" % col, "%d,%d,%d,%d" % (x - 5, y - 5, x + 5, y + 5)]
    cmd += legend(x0 + pw + 20, top + 20, reduced_note=False) + ["-d", "uint8", "-o", plot2]
    subprocess.run(cmd, check=True)
    print("Plot: `%s` (means over the models run at every resolution)." % os.path.basename(plot2))
