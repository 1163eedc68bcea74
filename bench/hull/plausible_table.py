#!/usr/bin/python3
"""The tables of docs/results/plausible.md from the rows of run_plausible.sh.

    bench/hull/plausible_table.py ROWS_3V [ROWS_4V]
    bench/hull/plausible_table.py --time ROWS_3V_256 ROWS_3V_512

ROWS_*: the output of bench/hull/run_plausible.sh (3 views) and of OBLIQUE=1
run_plausible.sh (4 views). The CPU seconds of each whole run, and with --time those of
the hull.plausible node, come from the run reports it left in ${TMPDIR:-/tmp}/cm-plausible.
fandisk (hard-surface) is shown but kept out of the organic averages.
"""
import json
import os
import sys

HARD = {"fandisk"}
WORK = os.path.join(os.environ.get("TMPDIR", "/tmp"), "cm-plausible")


def load(path):
    rows = {}
    for line in open(path):
        f = line.split()
        if len(f) != 8:
            continue
        name, pipe, tag, res, err, xor, clean, secs = f
        rep = os.path.join(WORK, "%s-%s-%s-%s.json" % (name, tag, res, pipe))
        cpu = stage = float("nan")
        if os.path.exists(rep):
            report = json.load(open(rep))
            cpu = report["cpu_seconds"]
            stage = sum(n["cpu_seconds"] for n in report["nodes"] if n["stage"] == "hull.plausible")
        rows.setdefault(name, {})[pipe] = {"err": float(err), "xor": float(xor), "clean": clean, "cpu": cpu,
                                           "stage": stage}
    return rows


def table(rows, title):
    print("\n%s\n" % title)
    print("| model | paper 3D error % | organic 3D error % | change | paper xor_pct | organic xor_pct "
          "| xor change (pp) | clean (paper / organic) | CPU s paper / organic | CPU ratio organic / paper |")
    print("|---|---:|---:|---:|---:|---:|---:|---|---:|---:|")
    changes, ratios = [], []
    for name, r in rows.items():
        if "paper" not in r or "organic" not in r:
            continue
        p, o = r["paper"], r["organic"]
        ch = 100.0 * (o["err"] - p["err"]) / p["err"]
        ratio = o["cpu"] / p["cpu"]
        label = name + (" (hard-surface)" if name in HARD else "")
        print("| %s | %.3f | %.3f | %+.1f %% | %.3f | %.3f | %+.3f | %s / %s | %.2f / %.2f | %.2f |" % (
            label, p["err"], o["err"], ch, p["xor"], o["xor"], o["xor"] - p["xor"], p["clean"], o["clean"],
            p["cpu"], o["cpu"], ratio))
        if name not in HARD:
            changes.append(ch)
            ratios.append(ratio)
    if changes:
        print("| **organic mean** | | | **%+.1f %%** (least gain %+.1f %%) | | | | | | %.2f |" % (
            sum(changes) / len(changes), max(changes), sum(ratios) / len(ratios)))
    return rows


def time_table(lo, hi):
    """CPU seconds at two resolutions, with the hull.plausible node's share."""
    print("| model | paper CPU s, 256 | organic CPU s, 256 | of which hull.plausible | ratio at 256 "
          "| paper CPU s, 512 | organic CPU s, 512 | of which hull.plausible | ratio at 512 |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    r_lo, r_hi = [], []
    for name in lo:
        if name not in hi or not all(k in lo[name] and k in hi[name] for k in ("paper", "organic")):
            continue
        cells = []
        for r, acc in ((lo[name], r_lo), (hi[name], r_hi)):
            p, o = r["paper"], r["organic"]
            ratio = o["cpu"] / p["cpu"]
            cells.append("%.2f | %.2f | %.2f | %.2f" % (p["cpu"], o["cpu"], o["stage"], ratio))
            if name not in HARD:
                acc.append(ratio)
        label = name + (" (hard-surface)" if name in HARD else "")
        print("| %s | %s | %s |" % (label, cells[0], cells[1]))
    if r_lo:
        print("| **organic mean** | | | | %.2f | | | | %.2f |" % (sum(r_lo) / len(r_lo), sum(r_hi) / len(r_hi)))


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    if sys.argv[1] == "--time":
        if len(sys.argv) != 4:
            sys.exit(__doc__)
        time_table(load(sys.argv[2]), load(sys.argv[3]))
        return
    r3 = table(load(sys.argv[1]), "Three views (front, right, top):")
    if len(sys.argv) > 2:
        r4 = table(load(sys.argv[2]), "Four views (front, right, top and azimuth 45, elevation 30):")
        print("\nWhat the oblique view adds (3D error %, organic models):\n")
        print("| model | paper 3 views | paper 4 views | organic 3 views | organic 4 views |")
        print("|---|---:|---:|---:|---:|")
        for name in r3:
            if name in r4 and name not in HARD and all(k in r3[name] and k in r4[name] for k in ("paper", "organic")):
                print("| %s | %.3f | %.3f | %.3f | %.3f |" % (name, r3[name]["paper"]["err"], r4[name]["paper"]["err"],
                                                             r3[name]["organic"]["err"], r4[name]["organic"]["err"]))


main()
