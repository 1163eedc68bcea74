"""Ctrl-C: KeyboardInterrupt within half a second, no partial file; the GIL is free meanwhile."""

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

from conftest import SOURCE_DIR

SCRIPT = textwrap.dedent("""
    import signal, sys, time, conceptmesh
    # Python leaves SIGINT alone when it starts with it ignored (a background job of a shell
    # without job control, as ctest may be): take it as an interactive session does.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    out = sys.argv[1]
    p = conceptmesh.Pipeline.load("pipelines/paper.yaml", set={
        "hull.resolution": 384, "write.path": out + "/spot.obj", "preview.path": out + "/spot.png"})
    try:
        p.run(report=out + "/report.json")
    except KeyboardInterrupt as e:
        print("interrupted at", time.monotonic(), "message:", e, flush=True)
        sys.exit(3)
    print("finished", flush=True)
""")


def run_and_interrupt(cm, tmp_path, hold):
    env = dict(os.environ, CONCEPTMESH_TEST_HOLD_NODE=hold)
    proc = subprocess.Popen([sys.executable, "-c", SCRIPT, str(tmp_path)], cwd=SOURCE_DIR, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # The hold says when the node is running; the signal comes then.
    line = ""
    while "test hold" not in line:
        line = proc.stderr.readline()
        assert line, "the run ended before the node was held"
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 3, out + err
    caught = float(out.split("interrupted at ")[1].split()[0])
    # The KeyboardInterrupt says where the run stopped, as the command does.
    assert "stopped" in out or "cancelled by the user" in out, out
    return caught - sent


def test_ctrl_c_raises_keyboard_interrupt_and_leaves_no_file(cm, tmp_path):
    # Held while writing the mesh (its file is staged under a temporary name) ...
    latency = run_and_interrupt(cm, tmp_path, "write")
    assert latency < 0.5, f"KeyboardInterrupt came {latency:.3f} s after Ctrl-C"
    assert list(tmp_path.iterdir()) == [], "no partial or temporary file is left"


def test_ctrl_c_in_a_long_stage(cm, tmp_path):
    # ... and in the middle of the grid work, past a third of it.
    latency = run_and_interrupt(cm, tmp_path, "refine@30")
    assert latency < 0.5, f"KeyboardInterrupt came {latency:.3f} s after Ctrl-C"
    assert list(tmp_path.iterdir()) == []


def test_gil_is_released_while_stages_run(cm, tmp_path):
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    t = threading.Thread(target=count)
    sets = {"write.path": str(tmp_path / "x.obj"), "preview.path": str(tmp_path / "x.png")}
    p = cm.Pipeline.load("pipelines/paper.yaml", set=sets)
    t.start()
    t0 = time.monotonic()
    p.run()
    elapsed = time.monotonic() - t0
    stop.set()
    t.join()
    # A thread that takes the GIL every millisecond kept running through the run: far more
    # often than the 20 times a second the waiting thread wakes up.
    assert len(ticks) > 100 * elapsed, (len(ticks), elapsed)
