#!/usr/bin/python3
"""How evenly a texture shows flat_art's fills (bench/texture/flat_art ... marker): flecks of the
stroke pattern left in it, which a mean delta E hides.
  build/release/bin/fill_delta_e MESH ART_DIR/fill/views.yaml 6 MAP_DIR   # the mesh's colour per view
  bench/texture/fill_evenness.py MAP_DIR ART_DIR/fill [VIEWS]
Per view, over each fill region eroded by 4 px (from other regions and the paper): the CIE76
delta E of the mesh's colour against the region's median colour; prints per view the 99th
percentile and the share of the pixels over 10, in per cent, then per region the same.
Needs numpy and oiiotool."""
import subprocess
import sys
import tempfile

import numpy as np


def read_rgb(path):
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run(["oiiotool", path, "--ch", "R,G,B", "-d", "uint8", "-o", f"{tmp}/t.ppm"], check=True)
        out = open(f"{tmp}/t.ppm", "rb").read()
    parts = out.split(b"\n", 3)
    w, h = map(int, parts[1].split())
    return np.frombuffer(parts[3][: w * h * 3], np.uint8).reshape(h, w, 3).astype(float) / 255


def lab(rgb):
    c = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    m = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])
    xyz = c @ m.T / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > 216 / 24389, np.cbrt(xyz), (24389 / 27 * xyz + 16) / 116)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], -1)


def main():
    maps, fills = sys.argv[1], sys.argv[2]
    views = sys.argv[3].split(",") if len(sys.argv) > 3 else ["front", "right", "top"]
    for view in views:
        mesh = read_rgb(f"{maps}/{view}.png")
        fill = (read_rgb(f"{fills}/{view}.png") * 255).round().astype(int)
        key = fill[..., 0] * 65536 + fill[..., 1] * 256 + fill[..., 2]
        paper = np.bincount(key.ravel()).argmax()  # the paper: most of the sheet
        same = key != paper
        for dy in range(-4, 5):
            for dx in range(-4, 5):
                same &= np.roll(np.roll(key, dy, 0), dx, 1) == key
        same &= (mesh < 1).any(-1)  # compared by fill_delta_e (the mesh seen)
        des, rows = [], []
        for k in np.unique(key[same]):
            m = same & (key == k)
            if m.sum() < 200:
                continue
            c = lab(mesh[m])
            de = np.linalg.norm(c - np.median(c, 0), axis=-1)
            des.append(de)
            rows.append(f"  {view} fill #{k:06x}: {m.sum()} px, p99 {np.percentile(de, 99):.2f}, "
                        f"over 10 {100 * (de > 10).mean():.2f} %")
        de = np.concatenate(des)
        print(f"{view} p99 {np.percentile(de, 99):.2f} over10 {100 * (de > 10).mean():.2f} % ({de.size} px)")
        print("\n".join(rows))


main()
