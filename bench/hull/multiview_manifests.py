#!/usr/bin/env python3
"""Writes views manifests for the calibrated photo sets of ../shared/data/multiview.

    bench/hull/multiview_manifests.py OUT_DIR [SHARED_DATA_DIR]

OUT_DIR/tum_bunny.yaml and OUT_DIR/dino.yaml name the images by absolute path (the
images are not copied). Same content as tests/hull/multiview.cpp writes at test time.
"""
import os
import sys


def matrix(rows):
    return "    matrix:\n" + "".join("      - [%s]\n" % ", ".join(repr(v) for v in r) for r in rows)


def tum_bunny(data):
    out = ["# TUM bunny (Kolev, Klodt, Brox, Cremers, IJCV 2009): binary silhouettes, object black on white.",
           "bounds: [-7.5, -10, -7.5, 7.5, 10, 15]", "views:"]
    for i in range(0, 36, 2):
        name = "%04d" % i
        with open(os.path.join(data, "calib", name + ".txt")) as f:
            words = f.read().split()
        p = [float(w) for w in words[1:13]]
        entry = "  v%s:\n    image: \"%s\"\n    background: white\n%s" % (
            name, os.path.abspath(os.path.join(data, "silhouettes", name + ".pgm")), matrix([p[0:4], p[4:8], p[8:12]]))
        out.append(entry.rstrip("\n"))
    return "\n".join(out) + "\n"


def dino(data):
    good = set(open(os.path.join(data, "dinoSR_good_silhouette_images.txt")).read().split())
    lines = open(os.path.join(data, "dinoSR_par.txt")).read().split("\n")
    out = ["# Middlebury dinoSparseRing (Seitz et al., CVPR 2006): white plaster on black.",
           "bounds: [-0.061897, -0.018874, -0.057845, 0.010897, 0.068227, 0.015495]", "views:"]
    for line in lines[1:1 + int(lines[0])]:
        w = line.split()
        if good and w[0] not in good:
            continue
        K = [float(x) for x in w[1:10]]
        R = [float(x) for x in w[10:19]]
        t = [float(x) for x in w[19:22]]
        rows = []
        for r in range(3):
            row = [sum(K[3 * r + k] * R[3 * k + c] for k in range(3)) for c in range(3)]
            row.append(sum(K[3 * r + k] * t[k] for k in range(3)))
            rows.append(row)
        entry = "  %s:\n    image: \"%s\"\n    background: black\n    threshold: 0.19\n%s" % (
            os.path.splitext(w[0])[0], os.path.abspath(os.path.join(data, w[0])), matrix(rows))
        out.append(entry.rstrip("\n"))
    return "\n".join(out) + "\n"


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    shared = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data")
    os.makedirs(out, exist_ok=True)
    mv = os.path.join(shared, "multiview")
    with open(os.path.join(out, "tum_bunny.yaml"), "w") as f:
        f.write(tum_bunny(os.path.join(mv, "tum_bunny")))
    with open(os.path.join(out, "dino.yaml"), "w") as f:
        f.write(dino(os.path.join(mv, "middlebury_dinoSparseRing")))


if __name__ == "__main__":
    main()
