#!/usr/bin/env python3
"""Tables (markdown, on stdout) and the reduction plot (PNG, drawn with oiiotool) of
docs/results/phase2.md, from the files bench/mesh/phase2.sh leaves in its work folder.

    phase2_report.py WORK_DIR [BUILD_DIR] [PLOT_PNG]
"""
import glob
import json
import os
import subprocess
import sys

work = sys.argv[1]
plot = sys.argv[3] if len(sys.argv) > 3 else os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "../../docs/results/phase2_reduction.png")
order = ["spot", "bob", "bunny", "armadillo", "fertility", "fandisk", "camel", "man"]
names = [n for n in order if os.path.exists(os.path.join(work, n + "-eval.json"))]
evals = {n: json.load(open(os.path.join(work, n + "-eval.json"))) for n in names}
pipes = {}
for n in names:
    p = os.path.join(work, n + "-pipeline.json")
    if os.path.exists(p):
        rep = json.load(open(p))
        pipes[n] = {node["id"]: node for node in rep["nodes"]}
        pipes[n]["_seconds"] = rep.get("seconds", 0)


def mean(xs):
    return sum(xs) / len(xs) if xs else float("nan")


# 1. The full paper pipeline.
print("### Full paper pipeline (views -> hull 256 -> refine -> Marching Cubes -> "
      "hull-constrained Laplacian, 10 iterations -> mesh.reduce)\n")
print("| model | MC faces | final faces | % of MC | xor_pct MC | xor_pct final | closed, 2-manifold, no degenerate face | "
      "self-intersections | run s |")
print("|---|---:|---:|---:|---:|---:|---|---:|---:|")
angle = None
rows = []
for n in names:
    if n not in pipes:
        continue
    p = pipes[n]
    angle = p["reduce"]["params"]["max_angle_deg"]
    mc_faces = p["surface"]["metrics"]["faces"]
    faces = p["reduce"]["metrics"]["faces"]
    xor = p["score"]["metrics"]["xor_pct"]
    e = evals[n]
    # The same chain evaluated by phase2_eval at this angle (checks it adds).
    row = next((s for s in e["sweep"] if abs(s["max_angle_deg"] - angle) < 1e-9), None)
    ok = row["reduce"]["closed_manifold"] and row["reduce"]["outward"] if row else None
    si = row["reduce"]["self_intersections"] if row else None
    # mesh.write checks what it writes (boundary, manifold, degenerate, crossings, volume).
    w = p.get("write", {}).get("metrics", {})
    if "self_intersections" in w:
        si = int(w["self_intersections"])
        ok = (w["boundary_edges"] == 0 and w["nonmanifold_edges"] == 0 and w["degenerate_faces"] == 0
              and w["volume"] > 0)
    rows.append((mc_faces, faces, xor, e["mc"]["xor_pct"]))
    print("| %s | %d | %d | %.1f %% | %.3f | %.3f | %s | %s | %.1f |" % (
        n, mc_faces, faces, 100.0 * faces / mc_faces, e["mc"]["xor_pct"], xor,
        "yes" if ok else "NO", si, p["_seconds"]))
if rows:
    print("| **mean** | | | **%.1f %%** | **%.3f** | **%.3f** | | | |" % (
        mean([100.0 * r[1] / r[0] for r in rows]), mean([r[3] for r in rows]), mean([r[2] for r in rows])))
print("\nmax_angle_deg = %s. xor_pct as in docs/conventions.md (all three views pooled).\n" % angle)

# 2. Smoothing.
print("### Smoothing, 10 iterations, from the Marching Cubes mesh\n")
variants = [("laplacian", "Laplacian"), ("taubin", "Taubin 0.63/-0.67"),
            ("laplacian_hull", "Laplacian + hull 0.5 px"), ("taubin_hull", "Taubin + hull 0.5 px")]
print("| model | " + " | ".join("%s: volume %% / xor_pct" % v[1] for v in variants) + " |")
print("|---|" + "---:|" * len(variants))
for n in names:
    s = evals[n]["smooth"]
    print("| %s | " % n + " | ".join("%+.3f / %.3f" % (s[k]["volume_change_pct"], s[k]["xor_pct"])
                                     for k, _ in variants) + " |")
print("| **mean** | " + " | ".join("**%+.3f / %.3f**" % (
    mean([evals[n]["smooth"][k]["volume_change_pct"] for n in names]),
    mean([evals[n]["smooth"][k]["xor_pct"] for n in names])) for k, _ in variants) + " |")
print()

# 3. Reduction sweep.
angles = [s["max_angle_deg"] for s in evals[names[0]]["sweep"]] if names else []
print("### Reduction sweep (paper Figure 6): mesh.reduce by max_angle_deg, and mesh.quadric_decimate "
      "to the same face counts, from the hull-constrained Laplacian mesh\n")
print("| max_angle_deg | faces, % of MC (mean) | xor_pct reduce (mean) | xor_pct quadric (mean) | "
      "all closed, 2-manifold, no degenerate face | self-intersections (reduce / quadric) |")
print("|---:|---:|---:|---:|---|---:|")
curves = {"pct": [], "xr": [], "xq": []}
for i, a in enumerate(angles):
    rs = [evals[n]["sweep"][i]["reduce"] for n in names]
    qs = [evals[n]["sweep"][i]["quadric"] for n in names]
    pct, xr, xq = mean([r["face_pct_of_mc"] for r in rs]), mean([r["xor_pct"] for r in rs]), mean(
        [q["xor_pct"] for q in qs])
    curves["pct"].append(pct)
    curves["xr"].append(xr)
    curves["xq"].append(xq)
    ok = all(r["closed_manifold"] and r["outward"] for r in rs + qs)
    print("| %g | %.2f %% | %.3f | %.3f | %s | %d / %d |" % (
        a, pct, xr, xq, "yes" if ok else "NO", sum(r["self_intersections"] for r in rs),
        sum(q["self_intersections"] for q in qs)))
print()
print("Per model, faces / xor_pct of mesh.reduce (quadric xor_pct in brackets):\n")
print("| model | " + " | ".join("%g deg" % a for a in angles) + " |")
print("|---|" + "---:|" * len(angles))
for n in names:
    print("| %s | " % n + " | ".join("%d / %.2f (%.2f)" % (s["reduce"]["faces"], s["reduce"]["xor_pct"],
                                                         s["quadric"]["xor_pct"]) for s in evals[n]["sweep"]) + " |")
print()

# 4. The plot: two panels over max_angle_deg, drawn with oiiotool (no plotting package needed).
if angles:
    W, H = 1000, 420
    panels = [(60, "faces, % of Marching Cubes", [("pct", "1,0.4,0.1", "mesh.reduce")]),
              (560, "xor_pct (%)", [("xr", "1,0.4,0.1", "mesh.reduce"), ("xq", "0.1,0.45,0.9", "quadric, same faces")])]
    cmd = ["oiiotool", "--create", "%dx%d" % (W, H), "3", "--fill:color=1,1,1", "0,0,%d,%d" % (W, H)]
    font = "DejaVuSans"
    pw, ph, top = 380, 300, 50
    for x0, title, series in panels:
        ymax = max(max(curves[k]) for k, _, _ in series) * 1.15
        cmd += ["--box:color=0.2,0.2,0.2", "%d,%d,%d,%d" % (x0, top, x0 + pw, top + ph)]
        cmd += ["--text:x=%d:y=%d:size=18:color=0,0,0:font=%s" % (x0, top - 15, font), title]
        for t in range(5):
            v = ymax * t / 4
            y = top + ph - int(ph * t / 4)
            cmd += ["--line:color=0.85,0.85,0.85", "%d,%d,%d,%d" % (x0 + 1, y, x0 + pw - 1, y)]
            cmd += ["--text:x=%d:y=%d:size=13:color=0.2,0.2,0.2:font=%s" % (x0 - 45, y + 5, font), "%.2f" % v]
        amin, amax = min(angles), max(angles)
        for a in angles:
            x = x0 + int(pw * (a - amin) / (amax - amin))
            cmd += ["--text:x=%d:y=%d:size=13:color=0.2,0.2,0.2:font=%s" % (x - 6, top + ph + 18, font), "%g" % a]
        cmd += ["--text:x=%d:y=%d:size=14:color=0,0,0:font=%s" % (x0 + pw // 2 - 50, top + ph + 40, font),
                "max_angle_deg"]
        for si, (k, col, label) in enumerate(series):
            pts = []
            for a, v in zip(angles, curves[k]):
                pts += [x0 + int(pw * (a - amin) / (amax - amin)), top + ph - int(ph * v / ymax)]
            cmd += ["--line:color=%s" % col, ",".join(str(p) for p in pts)]
            for j in range(0, len(pts), 2):
                cmd += ["--box:color=%s:fill=1" % col, "%d,%d,%d,%d" % (pts[j] - 3, pts[j + 1] - 3, pts[j] + 3, pts[j + 1] + 3)]
            ly = top + 20 + 20 * si
            cmd += ["--box:color=%s:fill=1" % col, "%d,%d,%d,%d" % (x0 + pw - 170, ly - 8, x0 + pw - 160, ly + 2)]
            cmd += ["--text:x=%d:y=%d:size=13:color=0,0,0:font=%s" % (x0 + pw - 155, ly + 2, font), label]
    cmd += ["-d", "uint8", "-o", plot]
    subprocess.run(cmd, check=True)
    print("Plot: `%s` (means over %d models)." % (os.path.basename(plot), len(names)))
