#!/usr/bin/python3
"""The Python module against the command on the same pipeline, and Ctrl-C's latency.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python/module_vs_cli.py [RUNS] [PIPELINE]

Run from the checkout after `cmake --build --preset tool`. Alternates a run of the command
(`build/release/bin/conceptmesh run -q`, a process each: start-up and plugin loading included)
with a run in this process through the module (its plugins loaded by a first, untimed run), and
prints the median wall time of each; then sends SIGINT to a subprocess held inside the mesh
writer (CONCEPTMESH_TEST_HOLD_NODE) and inside hull.marching_intersections, RUNS times each, and
prints the median and largest time from the signal to the KeyboardInterrupt.
"""

import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time

import conceptmesh as cm

RUNS = int(sys.argv[1]) if len(sys.argv) > 1 else 5
PIPELINE = sys.argv[2] if len(sys.argv) > 2 else "pipelines/paper.yaml"
EXE = "build/release/bin/conceptmesh"

INTERRUPTED = """
import signal, sys, time, conceptmesh
signal.signal(signal.SIGINT, signal.default_int_handler)
out = sys.argv[1]
p = conceptmesh.Pipeline.load(sys.argv[2], set={"write.path": out + "/m.obj", "preview.path": out + "/p.png"})
try:
    p.run()
except KeyboardInterrupt:
    print(time.monotonic(), flush=True)
"""


def outputs(folder):
    return {"write.path": f"{folder}/m.obj", "preview.path": f"{folder}/p.png"}


def timed_cli(folder):
    args = [EXE, "run", "-q", PIPELINE]
    for k, v in outputs(folder).items():
        args += ["--set", f"{k}={v}"]
    t0 = time.monotonic()
    subprocess.run(args, check=True)
    return time.monotonic() - t0


def timed_module(folder):
    t0 = time.monotonic()
    cm.Pipeline.load(PIPELINE, set=outputs(folder)).run()
    return time.monotonic() - t0


def latency(hold, folder):
    env = dict(os.environ, CONCEPTMESH_TEST_HOLD_NODE=hold)
    proc = subprocess.Popen([sys.executable, "-c", INTERRUPTED, folder, PIPELINE], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    while "test hold" not in proc.stderr.readline():
        pass
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate()
    assert not os.listdir(folder), "a file was left"
    return float(out.split()[0]) - sent


def main():
    with tempfile.TemporaryDirectory() as d:
        timed_module(d)  # loads the plugins once, as a TD's session does
        cli, mod = [], []
        for _ in range(RUNS):
            cli.append(timed_cli(d))
            mod.append(timed_module(d))
    print(f"{PIPELINE}: command {statistics.median(cli):.2f} s, module {statistics.median(mod):.2f} s "
          f"(median of {RUNS}; {os.getloadavg()[0]:.1f} load)")
    for hold in ("write", "refine@30"):
        lat = []
        for _ in range(RUNS):
            with tempfile.TemporaryDirectory() as d:
                lat.append(latency(hold, d))
        print(f"Ctrl-C held in {hold}: KeyboardInterrupt after {1000 * statistics.median(lat):.0f} ms median, "
              f"{1000 * max(lat):.0f} ms at most ({RUNS} runs)")


if __name__ == "__main__":
    main()
