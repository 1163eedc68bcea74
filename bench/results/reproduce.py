#!/usr/bin/python3
"""bench/reproduce: regenerates docs/results/README.md, its tables and plots, in one run.

    bench/reproduce [--quick] [--build BUILD_DIR] [--out DIR] [--runs N]

Sections: error against grid resolution (the paper's Figure 7b), the 3D error against the
true model (three views, and three plus one oblique view), time and memory per stage against
resolution (Figure 7a), reduction against angle (Figure 6, with pictures), the peers on the
same views (a dense numpy / scikit-image / Open3D script, Open3D's carve_silhouette, OpenVDB's
volumeToMesh), and each model's preview sheet. --quick runs fewer models and resolutions.

Whole processes are timed from outside with /usr/bin/time -v (wall seconds, user + system
CPU seconds, peak resident memory); stages from the run report (--report). The peers need
Debian's python3-skimage, python3-open3d, python3-openvdb, python3-matplotlib and
python3-scipy: this script installs them with apt-get when it runs as root and they are
missing (bench only; the product never uses them). Work files go to
${TMPDIR:-/tmp}/cm-reproduce.
"""
import argparse
import json
import math
import os
import platform
import shutil
import signal
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HERE = os.path.join(ROOT, "bench", "results")
MODELS_DIR = os.path.join(ROOT, "..", "shared", "data", "models")
PAPER_XOR = {8: 20.78, 4: 3.78}  # the paper's errors at grids 8x and 4x coarser than the images
LAST_STDERR = ""  # what the last timed() run wrote to stderr
PEER_PACKAGES = ["python3-skimage", "python3-open3d", "python3-openvdb", "python3-matplotlib", "python3-scipy"]


def ensure_packages():
    probe = "import skimage, open3d, pyopenvdb, matplotlib, scipy"
    if subprocess.run([sys.executable, "-c", probe], capture_output=True).returncode == 0:
        return
    if os.geteuid() != 0:
        sys.exit("bench/reproduce needs " + " ".join(PEER_PACKAGES) + " (apt-get install -y ...)")
    print("installing the peers' packages:", " ".join(PEER_PACKAGES), file=sys.stderr)
    subprocess.run(["apt-get", "install", "-y", "--no-install-recommends"] + PEER_PACKAGES, check=True,
                   env=dict(os.environ, DEBIAN_FRONTEND="noninteractive"), stdout=subprocess.DEVNULL)


def models_list():
    out = []
    for line in open(os.path.join(ROOT, "bench", "models.txt")):
        if line.strip() and not line.startswith("#"):
            name, file, up, front = line.split()
            out.append((name, file, up, front))
    return out


def limit_memory(mib):
    """A preexec_fn capping the child's address space at mib MiB (a peer that asks for more fails
    at once with MemoryError instead of taking the machine's memory and swap)."""
    def apply():
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (mib << 20, mib << 20))
    return apply


def timed(cmd, cwd=ROOT, check=True, limit_s=None, limit_mib=None):
    """Runs cmd under /usr/bin/time -v: (stdout, wall s, cpu s, peak MiB, exit code). With limit_s,
    a run still going after limit_s seconds is stopped and its exit code is None."""
    log = os.path.join(WORK, "time.log")
    t0 = time.monotonic()
    # A session of its own, so that a run past its time is stopped with everything it started.
    proc = subprocess.Popen(["/usr/bin/time", "-v", "-o", log] + cmd, cwd=cwd, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True,
                            preexec_fn=limit_memory(limit_mib) if limit_mib else None)
    try:
        out, err = proc.communicate(timeout=limit_s)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return "", time.monotonic() - t0, 0.0, 0.0, None
    p = subprocess.CompletedProcess(proc.args, proc.returncode, out, err)
    wall = time.monotonic() - t0
    global LAST_STDERR
    LAST_STDERR = p.stderr
    cpu, peak = 0.0, 0.0
    for line in open(log):
        k, _, v = line.strip().partition(": ")
        if k in ("User time (seconds)", "System time (seconds)"):
            cpu += float(v)
        elif k == "Maximum resident set size (kbytes)":
            peak = float(v) / 1024
    if check and p.returncode != 0:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr.strip()[-400:]))
    return p.stdout, wall, cpu, peak, p.returncode


def render(name, file, up, front, size, views="front,right,top", tag=""):
    out = os.path.join(WORK, "%s-%d%s" % (name, size, tag))
    if not os.path.exists(os.path.join(out, "views.yaml")):
        subprocess.run([CM, "render-views", os.path.join(MODELS_DIR, file), "--style", "mask", "--size", str(size),
                        "--up", up, "--front", front, "--views", views, "-o", out, "-q"], check=True)
    return os.path.join(out, "views.yaml")


def run_pipeline(pipeline, views, res, extra=()):
    report = os.path.join(WORK, "report.json")
    cmd = [CM, "run", pipeline, "-q", "--set", "views.manifest=" + views, "--set", "hull.resolution=%d" % res,
           "--report", report] + list(extra)
    _, wall, cpu, peak, _ = timed(cmd)
    r = json.load(open(report))
    nodes = {n["id"]: n for n in r["nodes"]}
    return {"wall": wall, "cpu": cpu, "peak": peak, "nodes": nodes, "report": r}


# ---------------------------------------------------------------------------------------------
# 3D error: mean two-sided surface distance, in % of the true model's bounding-box diagonal,
# from bench/hull/surface_distance (the one implementation; it turns the true model into
# the output frame as render-views frames it).

def surface_distance_pct(model_file, up, front, mesh_path, n=200000):
    out = subprocess.run([os.path.join(os.path.dirname(CM), "surface_distance"), mesh_path,
                          os.path.join(MODELS_DIR, model_file), "--up", up, "--front", front, "--samples", str(n)],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)["mean_pct"]


# ---------------------------------------------------------------------------------------------

def fmt(x, d=2):
    return "-" if x is None else ("%.*f" % (d, x))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="fewer models and resolutions (under 5 minutes)")
    ap.add_argument("--build", default="build/release")
    ap.add_argument("--out", default="docs/results")
    ap.add_argument("--runs", type=int, default=0, metavar="N",
                    help="runs per resolution in the time and memory section, the median run reported; 4096 "
                         "runs once (default 3, --quick 1)")
    ap.add_argument("--peer-limit", type=int, default=240, metavar="S",
                    help="seconds a peer may run at one resolution before it is stopped (default 240)")
    ap.add_argument("--peer-memory", type=int, default=0, metavar="MIB",
                    help="address space a peer may take (default: 70 %% of the machine's memory)")
    a = ap.parse_args()
    global CM, WORK
    build = a.build if os.path.isabs(a.build) else os.path.join(ROOT, a.build)
    CM = os.path.join(build, "bin", "conceptmesh")
    WORK = os.path.join(os.environ.get("TMPDIR", "/tmp"), "cm-reproduce")
    out_dir = a.out if os.path.isabs(a.out) else os.path.join(ROOT, a.out)
    pics = os.path.join(out_dir, "reproduce")
    os.makedirs(WORK, exist_ok=True)
    os.makedirs(pics, exist_ok=True)
    if not os.path.isdir(MODELS_DIR):
        sys.exit("bench/reproduce: ../shared/data/models is not there")
    ensure_packages()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    started = time.monotonic()
    load0 = open("/proc/loadavg").read().split()[0]
    models = models_list()
    if a.quick:
        models = [m for m in models if m[0] in ("spot", "bob", "fandisk")]
    factors = [8, 4, 2] if a.quick else [8, 4, 2, 1]
    speed_res = [256, 512] if a.quick else [256, 512, 1024, 2048, 4096]
    angles = [5, 20, 40] if a.quick else [5, 10, 15, 20, 25, 30, 35, 40]
    peer_res = [256] if a.quick else [256, 512, 1024]
    runs = a.runs or (1 if a.quick else 3)
    md = []
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT, capture_output=True,
                           text=True).stdout.strip()
    mem_gib = int(open("/proc/meminfo").readline().split()[1]) / 2**20
    cpu_name = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")

    # 1. Error against grid resolution, and the 3D error with three and four views. -----------
    print("1/5 error against grid resolution", file=sys.stderr)
    err_rows, d3_rows = [], []
    for name, file, up, front in models:
        views = render(name, file, up, front, 1024)
        for fct in factors:
            res = 1024 // fct
            mesh = os.path.join(WORK, "%s-%d.ply" % (name, res))
            r = run_pipeline(os.path.join(HERE, "eval.yaml"), views, res, ["--set", "write.path=" + mesh])
            n = r["nodes"]
            row = {"model": name, "factor": fct, "res": res, "xor_mc": n["error_mc"]["metrics"]["xor_pct"],
                   "xor": n["score"]["metrics"]["xor_pct"], "faces_mc": n["surface"]["metrics"]["faces"],
                   "faces": n["reduce"]["metrics"]["faces"], "cpu": r["cpu"]}
            if fct == 4:  # the 3D error at the paper's 4x grid, three views and three plus an oblique one
                row["d3"] = surface_distance_pct(file, up, front, mesh)
                views4 = render(name, file, up, front, 1024, "front,right,top,az45el30", "-oblique")
                mesh4 = os.path.join(WORK, "%s-%d-oblique.ply" % (name, res))
                r4 = run_pipeline(os.path.join(HERE, "eval.yaml"), views4, res, ["--set", "write.path=" + mesh4])
                d3_rows.append((name, row["d3"], surface_distance_pct(file, up, front, mesh4),
                                r4["nodes"]["score"]["metrics"]["xor_pct"]))
                sheet = os.path.join(pics, "%s_preview.png" % name)
                subprocess.run([CM, "preview", mesh, "--views", views, "-o", sheet, "-q"], check=True)
            err_rows.append(row)

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name, *_ in models:
        rs = [r for r in err_rows if r["model"] == name]
        line, = ax.plot([r["factor"] for r in rs], [r["xor"] for r in rs], "o-", label=name)
        ax.plot([r["factor"] for r in rs], [r["xor_mc"] for r in rs], "x--", color=line.get_color(), alpha=0.6)
    ax.plot(list(PAPER_XOR), list(PAPER_XOR.values()), "s", color="black", markersize=9, label="paper (SBGames 2014)")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xticks(factors)
    ax.set_xticklabels(["%dx" % f for f in factors])
    ax.invert_xaxis()
    ax.set_xlabel("grid coarser than the 1024 px images by")
    ax.set_ylabel("xor_pct (solid: full pipeline, dashed: phase 1)")
    ax.legend(fontsize=7, ncol=2)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(pics, "error_vs_grid.png"), dpi=110)
    plt.close(fig)

    # 2. Time and memory against resolution, per stage (pipelines/paper.yaml, 2048 px views). --
    print("2/5 time and memory against resolution", file=sys.stderr)
    sname, sfile, sup, sfront = next(m for m in models_list() if m[0] == "spot")
    views2k = render(sname, sfile, sup, sfront, 2048)
    stages = ["views", "hull", "refine", "surface", "smooth", "reduce", "write", "preview", "score"]
    speed_rows = []
    for res in speed_res:
        # The median run by process wall time (one machine's speed drifts from run to run);
        # 4096, the longest by far, once.
        tries = []
        try:
            for _ in range(1 if res > 2048 else runs):
                tries.append(run_pipeline(os.path.join(ROOT, "pipelines", "paper.yaml"), views2k, res,
                                          ["--set", "write.path=" + os.path.join(WORK, "speed.obj"),
                                           "--set", "preview.path=" + os.path.join(WORK, "speed.png")]))
        except RuntimeError as e:
            speed_rows.append({"res": res, "failed": str(e)})
            continue
        tries.sort(key=lambda t: t["wall"])
        r = tries[(len(tries) - 1) // 2]
        n = r["nodes"]
        speed_rows.append({"res": res, "runs": len(tries), "walls": [t["wall"] for t in tries],
                           "wall": r["wall"], "cpu": r["cpu"], "peak": r["peak"],
                           "stages": {s: n[s]["seconds"] for s in stages},
                           "stages_cpu": {s: n[s].get("cpu_seconds", 0) for s in stages},
                           "faces_mc": n["surface"]["metrics"]["faces"], "faces": n["reduce"]["metrics"]["faces"],
                           "xor": n["score"]["metrics"]["xor_pct"]})
    ok = [r for r in speed_rows if "failed" not in r]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for s in stages:
        a1.plot([r["res"] for r in ok], [max(r["stages"][s], 1e-3) for r in ok], "o-", label=s)
    a1.plot([r["res"] for r in ok], [r["wall"] for r in ok], "k^-", label="whole process")
    a1.set_xscale("log", base=2)
    a1.set_yscale("log")
    a1.set_xlabel("grid resolution (cells along the longest side)")
    a1.set_ylabel("wall seconds")
    a1.legend(fontsize=7)
    a1.grid(True, which="both", alpha=0.3)
    a2.plot([r["res"] for r in ok], [r["peak"] for r in ok], "o-")
    a2.set_xscale("log", base=2)
    a2.set_xlabel("grid resolution")
    a2.set_ylabel("peak resident memory, MiB")
    a2.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(pics, "time_memory_vs_resolution.png"), dpi=110)
    plt.close(fig)

    # 3. Reduction against angle, with pictures at three angles. -------------------------------
    print("3/5 reduction against angle", file=sys.stderr)
    views1k = render(sname, sfile, sup, sfront, 1024)
    red_rows = []
    for ang in angles:
        # The paper's Figure 6 measures its operator alone: pipelines/paper.yaml also
        # collapses along straight creases (docs/mesh.md), off here.
        extra = ["--set", "reduce.max_angle_deg=%g" % ang, "--set", "reduce.crease_straightness=0",
                 "--set", "write.path=" + os.path.join(WORK, "angle.obj"),
                 "--set", "preview.path=" + os.path.join(pics, "reduce_%02d.png" % ang)]
        r = run_pipeline(os.path.join(ROOT, "pipelines", "paper.yaml"), views1k, 256, extra)
        n = r["nodes"]
        red_rows.append((ang, n["reduce"]["metrics"]["faces_before"], n["reduce"]["metrics"]["faces"],
                         n["score"]["metrics"]["xor_pct"]))
        if ang not in (5, 20, 40):
            os.remove(os.path.join(pics, "reduce_%02d.png" % ang))
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot([r[0] for r in red_rows], [100 * r[2] / r[1] for r in red_rows], "o-", label="faces kept, %")
    ax2 = ax.twinx()
    ax2.plot([r[0] for r in red_rows], [r[3] for r in red_rows], "s--", color="tab:red", label="xor_pct")
    ax.set_xlabel("max_angle_deg")
    ax.set_ylabel("faces kept, % of Marching Cubes")
    ax2.set_ylabel("xor_pct", color="tab:red")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(pics, "reduction_vs_angle.png"), dpi=110)
    plt.close(fig)

    # 4. Peers on the same views, in the same run. ---------------------------------------------
    print("4/5 peers", file=sys.stderr)
    peers = os.path.join(HERE, "peers.py")
    peer_rows = []
    mem_total_mib = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") >> 20
    peer_mib = a.peer_memory or int(0.7 * mem_total_mib)
    for res in peer_res:
        ours = run_pipeline(os.path.join(HERE, "eval.yaml"), views1k, res,
                            ["--set", "write.path=" + os.path.join(WORK, "ours.ply")])
        target = int(ours["nodes"]["reduce"]["metrics"]["faces"])
        row = {"res": res, "ours": (ours["wall"], ours["cpu"], ours["peak"], ours["nodes"]["score"]["metrics"]["xor_pct"])}
        for peer in ("dense", "o3d", "vdb"):
            mesh = os.path.join(WORK, "peer-%s.obj" % peer)
            cmd = ["/usr/bin/python3", peers, peer, views1k, str(res)]
            if peer != "o3d":
                cmd.append(mesh)
            if peer == "dense":
                cmd.append(str(target))
            if os.path.exists(mesh):
                os.remove(mesh)
            _, wall, cpu, peak, code = timed(cmd, check=False, limit_s=a.peer_limit, limit_mib=peer_mib)
            if code is None:
                row[peer] = ("did not finish in %d s (stopped)" % a.peer_limit,)
                continue
            if code != 0:
                oom = code in (-9, 137) or "MemoryError" in LAST_STDERR or "bad_alloc" in LAST_STDERR
                row[peer] = ("failed (exit %d%s)" % (code, ", out of memory (limit %d MiB)" % peer_mib if oom else ""),)
                continue
            xor = None
            if peer != "o3d":
                j = json.loads(subprocess.run([CM, "compare", mesh, views1k, "--json", "-q"], capture_output=True,
                                              text=True, check=True).stdout)
                xor = j["xor_pct"]
            row[peer] = (wall, cpu, peak, xor)
        peer_rows.append(row)

    # 5. The page. -----------------------------------------------------------------------------
    print("5/5 writing", file=sys.stderr)
    total = time.monotonic() - started
    load1 = open("/proc/loadavg").read().split()[0]
    md.append("# Results, reproduced\n")
    md.append("Generated by `bench/reproduce%s` (do not edit by hand). Machine: %d cores (%s), %.0f GiB RAM, %s; "
              "commit `%s`%s; load average %s at the start, %s at the end; %.0f s in all.\n" %
              (" --quick" if a.quick else "", os.cpu_count(), cpu_name, mem_gib, platform.platform(), commit,
               " with local changes" if dirty else "", load0, load1, total))
    md.append("Models: %s, from `../shared/data/models` (each with its own axes, `bench/models.txt`), rendered as "
              "binary silhouettes by `conceptmesh render-views`.\n" % ", ".join(m[0] for m in models))
    four = [r for r in err_rows if r["factor"] == 4]
    if four:
        md.append("**Headline figures.** At a grid 4x coarser than the 1024 px images (the paper's 3.78 %%), the "
                  "full pipeline's silhouette error is %.2f %% on average over %d models (worst %.2f %%). " %
                  (sum(r["xor"] for r in four) / len(four), len(four), max(r["xor"] for r in four)))
    big = [r for r in ok if r["res"] == max(x["res"] for x in ok)] if ok else []
    if big:
        md.append("The whole `pipelines/paper.yaml` at %d from three 2048 px views of spot takes %.1f s of wall time "
                  "and %.0f MiB at peak (on this machine under the load above).\n" % (big[0]["res"], big[0]["wall"],
                                                                                     big[0]["peak"]))
    md.append("\n## Error against grid resolution (the paper's Figure 7b)\n")
    md.append("Views 1024 px, front/right/top; grid 8x, 4x, 2x and 1x coarser than the images (resolution "
              "128 to 1024). `xor_pct` = 100 |S xor R| / |S| summed over the views (`eval.silhouette_error`), "
              "after phase 1 (Marching Cubes mesh) and after the full pipeline (`bench/results/eval.yaml`, "
              "the steps of `pipelines/paper.yaml`). The paper: 20.78 % at 8x, 3.78 % at 4x.\n")
    md.append("![error against grid](reproduce/error_vs_grid.png)\n")
    md.append("| model | grid | resolution | xor_pct phase 1 | xor_pct full | faces MC | faces out | CPU s |")
    md.append("|---|---:|---:|---:|---:|---:|---:|---:|")
    for r in err_rows:
        md.append("| %s | %dx | %d | %.3f | %.3f | %s | %s | %.1f |" % (r["model"], r["factor"], r["res"], r["xor_mc"],
                                                                      r["xor"], format(int(r["faces_mc"]), ","),
                                                                      format(int(r["faces"]), ","), r["cpu"]))
    md.append("\n## 3D error against the true model\n")
    md.append("What silhouettes alone cannot show: the mean two-sided surface distance between the result and the "
              "model it was rendered from (200,000 area-weighted samples on each, exact distance to the other's triangles; "
              "bench/hull/surface_distance), "
              "in percent of the model's bounding-box diagonal; grid 4x coarser than the 1024 px views. "
              "Three views (front, right, top) against three plus one oblique view (azimuth 45, elevation 30).\n")
    md.append("| model | 3 views: distance % of diagonal | 3 + oblique | change | xor_pct with 4 views |")
    md.append("|---|---:|---:|---:|---:|")
    for name, d3, d4, x4 in d3_rows:
        md.append("| %s | %.3f | %.3f | %+.0f %% | %.3f |" % (name, d3, d4, 100 * (d4 - d3) / d3, x4))
    md.append("\n## Time and memory against resolution (the paper's Figure 7a)\n")
    md.append("`pipelines/paper.yaml` from three 2048 px views of spot; per stage, wall seconds from the run report "
              "(`--report`; CPU seconds of the process in brackets); the whole process (start-up included) and its "
              "peak resident memory from `/usr/bin/time -v`. write, preview and error run at the same time, so their "
              "CPU seconds overlap. %s; `runs, wall s` lists every run's wall time.\n" %
              ("One run at each resolution" if runs == 1 else
               "Each row is the median of %d runs by process wall time (one at 4096)" % runs))
    md.append("![time and memory](reproduce/time_memory_vs_resolution.png)\n")
    md.append("| resolution | " + " | ".join(stages) +
              " | process wall s | process CPU s | peak MiB | faces MC -> out | xor_pct | runs, wall s |")
    md.append("|---:|" + "---:|" * (len(stages) + 6))
    for r in speed_rows:
        if "failed" in r:
            md.append("| %d | failed: %s |" % (r["res"], r["failed"][:200]))
            continue
        cells = ["%.2f (%.2f)" % (r["stages"][s], r["stages_cpu"][s]) for s in stages]
        md.append("| %d | %s | %.2f | %.2f | %.0f | %s -> %s | %.3f | %d: %s |" % (
            r["res"], " | ".join(cells), r["wall"], r["cpu"], r["peak"], format(int(r["faces_mc"]), ","),
            format(int(r["faces"]), ","), r["xor"], r["runs"], " ".join("%.2f" % w for w in r["walls"])))
    md.append("\n## Reduction against angle (the paper's Figure 6)\n")
    md.append("spot, views 1024 px, resolution 256; `mesh.reduce` `max_angle_deg` from 5 to 40.\n")
    md.append("![reduction against angle](reproduce/reduction_vs_angle.png)\n")
    md.append("| max_angle_deg | faces in | faces out | kept % | xor_pct |")
    md.append("|---:|---:|---:|---:|---:|")
    for ang, fin, fout, x in red_rows:
        md.append("| %g | %s | %s | %.1f | %.3f |" % (ang, format(int(fin), ","), format(int(fout), ","),
                                                   100 * fout / fin, x))
    md.append("\nPreview sheets at 5, 20 and 40 degrees: [5](reproduce/reduce_05.png), "
              "[20](reproduce/reduce_20.png), [40](reproduce/reduce_40.png).\n")
    md.append("![reduced at 20 degrees](reproduce/reduce_20.png)\n")
    md.append("\n## Peers, side by side on the same views\n")
    md.append("spot, views 1024 px; every figure is a whole process (`/usr/bin/time -v`), Python start-up and "
              "imports included for the peers. (a) **dense**: the script a user would write "
              "(`bench/results/peers.py dense`: numpy carve, scikit-image marching cubes, Open3D Laplacian "
              "smoothing, 10 iterations, and quadric decimation to our face count); (b) **Open3D "
              "carve_silhouette** (`VoxelGrid.carve_silhouette`, carve only, no mesh, so no xor); (c) **OpenVDB "
              "volumeToMesh** (`pyopenvdb` `convertToPolygons` on the same numpy carve). Ratios are peer / ours "
              "(above 1: we are faster, lighter or more accurate). Peer (c) is phase 1 only (carve and mesh, no smoothing or reduction, about a million faces out) against our whole pipeline, so its time ratio compares different work. "
              "Each peer run may take %d s and %d MiB of address space (`--peer-limit`, `--peer-memory`): a run "
              "past the time is stopped and reported as not finished; one past the memory fails and is reported "
              "as out of memory.\n" % (a.peer_limit, peer_mib))
    md.append("| resolution | ours: wall s / CPU s / MiB / xor_pct | peer | wall s | CPU s | MiB | xor_pct | time ratio | memory ratio | xor ratio |")
    md.append("|---:|---|---|---:|---:|---:|---:|---:|---:|---:|")
    names = {"dense": "(a) dense numpy + scikit-image + Open3D", "o3d": "(b) Open3D carve_silhouette",
             "vdb": "(c) OpenVDB volumeToMesh"}
    for row in peer_rows:
        ow, oc, op, ox = row["ours"]
        for peer in ("dense", "o3d", "vdb"):
            p = row[peer]
            if len(p) == 1:
                md.append("| %d | %.2f / %.2f / %.0f / %.3f | %s | %s | | | | | | |" % (row["res"], ow, oc, op, ox,
                                                                                  names[peer], p[0]))
                continue
            w, c, m, x = p
            md.append("| %d | %.2f / %.2f / %.0f / %.3f | %s | %.2f | %.2f | %.0f | %s | %.1fx | %.1fx | %s |" % (
                row["res"], ow, oc, op, ox, names[peer], w, c, m, fmt(x, 3), w / ow, m / op,
                "-" if x is None else "%.1fx" % (x / ox)))
    md.append("\n## Preview sheets\n")
    md.append("Each model at the 4x grid (resolution 256, views 1024 px), full pipeline: input, mesh, overlay.\n")
    for name, *_ in models:
        md.append("![%s](reproduce/%s_preview.png)\n" % (name, name))
    md.append("\n## How to reproduce\n")
    md.append("    cmake --preset release && cmake --build --preset release\n    bench/reproduce%s\n" %
              (" --quick" if a.quick else ""))
    md.append("Work files go to `${TMPDIR:-/tmp}/cm-reproduce`. Wall seconds depend on what else runs on the "
              "machine: see the load average at the top, and docs/results/speed.md for figures taken with "
              "repeated runs.\n")
    with open(os.path.join(out_dir, "README.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("wrote %s in %.0f s" % (os.path.join(out_dir, "README.md"), total), file=sys.stderr)


if __name__ == "__main__":
    main()
