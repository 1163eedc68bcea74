#!/usr/bin/env python3
"""The tables of docs/results/shape.md from the rows of bench/hull/run_shape.sh.

    bench/hull/shape_table.py rows.txt [more rows...]

One table per view set and resolution: per model the silhouette error from the four unseen
views, the 3D error and the drawn views' xor_pct of each pipeline, the CPU ratio against
paper.yaml; then the means over the organic models (fandisk, the hard-surface model, apart)
and the bars of issue 45 (unseen mean <= 0.6x organic.yaml's, no model worse than paper.yaml,
3D error 30 % below paper.yaml, drawn xor within 0.1 points, time <= 1.5x).
"""
import sys
from collections import defaultdict

HARD = {"fandisk"}
rows = defaultdict(dict)  # (views, res) -> model -> pipeline -> values
order = []
for path in sys.argv[1:]:
    for line in open(path):
        f = line.split()
        if len(f) != 9:
            continue
        model, pipe, views, res = f[0], f[1], f[2], f[3]
        rows[(views, res)].setdefault(model, {})[pipe] = dict(
            err=float(f[4]), xor=float(f[5]), unseen=float(f[6]), clean=f[7], cpu=float(f[8]))
        if model not in order:
            order.append(model)

for (views, res), models in rows.items():
    pipes = [p for p in ("paper", "organic", "loft") if any(p in m for m in models.values())]
    print(f"\n### {views}, resolution {res}\n")
    head = "| model | " + " | ".join(f"unseen % {p}" for p in pipes) + " | " + \
        " | ".join(f"3D % {p}" for p in pipes) + " | " + " | ".join(f"drawn xor {p}" for p in pipes) + \
        " | clean | CPU loft / paper |"
    print(head)
    print("|---" * (head.count("|") - 1) + "|")
    sums = defaultdict(list)
    for m in order:
        if m not in models or not all(p in models[m] for p in pipes):
            continue
        r = models[m]
        cells = [f"{r[p]['unseen']:.2f}" for p in pipes] + [f"{r[p]['err']:.3f}" for p in pipes] + \
            [f"{r[p]['xor']:.3f}" for p in pipes]
        clean = "/".join(r[p]["clean"] for p in pipes)
        ratio = r["loft"]["cpu"] / r["paper"]["cpu"] if "loft" in r else float("nan")
        name = m + (" (hard-surface)" if m in HARD else "")
        print(f"| {name} | " + " | ".join(cells) + f" | {clean} | {ratio:.2f} |")
        if m not in HARD:
            for p in pipes:
                for k in ("unseen", "err", "xor"):
                    sums[(p, k)].append(r[p][k])
            sums["ratio"].append(ratio)
    if not sums:
        continue
    mean = lambda v: sum(v) / len(v)
    cells = [f"**{mean(sums[(p, 'unseen')]):.2f}**" for p in pipes] + \
        [f"**{mean(sums[(p, 'err')]):.3f}**" for p in pipes] + [f"{mean(sums[(p, 'xor')]):.3f}" for p in pipes]
    print("| **organic mean** | " + " | ".join(cells) + f" | | {mean(sums['ratio']):.2f} |")
    if "loft" in pipes and "organic" in pipes:
        u = mean(sums[("loft", "unseen")]) / mean(sums[("organic", "unseen")])
        e = mean(sums[("loft", "err")]) / mean(sums[("paper", "err")]) - 1
        worse = [m for m in order if m in models and "loft" in models[m]
                 and models[m]["loft"]["unseen"] > models[m]["paper"]["unseen"]]
        dx = max(models[m]["loft"]["xor"] - models[m]["paper"]["xor"] for m in models if "loft" in models[m])
        print(f"\nBars (organic models): unseen mean loft / organic {u:.2f} (bar 0.60); "
              f"3D error loft vs paper {100 * e:+.1f} % (bar -30 %); models worse than paper unseen: "
              f"{', '.join(worse) or 'none'}; largest drawn xor loft - paper {dx:+.3f} pp (bar +0.1); "
              f"CPU loft / paper {mean(sums['ratio']):.2f} (bar 1.5).")
