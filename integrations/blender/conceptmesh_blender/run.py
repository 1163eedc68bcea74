"""Runs the conceptmesh command and reads its progress stream (`--progress json`,
docs/pipelines.md). Nothing here touches bpy: the reader threads only queue lines."""

import json
import os
import queue
import shutil
import signal
import subprocess
import sys
import threading

BUNDLED = ("loft", "paper", "organic", "dmc", "quadric", "textured")


def addon_dir():
    return os.path.dirname(os.path.abspath(__file__))


def bundled_pipeline(name):
    """A bundled pipeline: in the add-on's zip, or in the checkout when run from it."""
    for folder in (os.path.join(addon_dir(), "pipelines"), os.path.join(addon_dir(), "..", "..", "..", "pipelines")):
        path = os.path.normpath(os.path.join(folder, name + ".yaml"))
        if os.path.isfile(path):
            return path
    raise RunError('the bundled pipeline "%s" is not in the add-on (%s)' % (name, addon_dir()))


def find_executable(preference=""):
    """The conceptmesh command: the path given (operator or preferences), else
    $CONCEPTMESH_EXECUTABLE, else one beside the add-on, else the first on PATH."""
    exe = "conceptmesh.exe" if sys.platform == "win32" else "conceptmesh"
    for candidate in (preference, os.environ.get("CONCEPTMESH_EXECUTABLE", "")):
        if candidate:
            candidate = os.path.abspath(os.path.expanduser(candidate))
            if os.path.isfile(candidate) and os.access(candidate, os.X_OK):
                return candidate
            raise RunError('the conceptmesh command "%s" does not exist or cannot be run' % candidate)
    for beside in (os.path.join(addon_dir(), exe), os.path.join(addon_dir(), "bin", exe)):
        if os.path.isfile(beside) and os.access(beside, os.X_OK):
            return beside
    found = shutil.which(exe)
    if found:
        return found
    raise RunError(
        "the conceptmesh command was not found: put it on PATH or beside the add-on, or set its path in "
        "the add-on's preferences"
    )


class RunError(Exception):
    pass


def command(exe, pipeline, manifest, mesh_path, sets):
    """The command line: the pipeline on the manifest, its mesh written as `mesh_path` in the
    views' units (no rescaling: write.height 0, unit_scale 1), plus the artist's --set."""
    cmd = [exe, "run", pipeline, "--progress", "json"]
    base = [
        "views.manifest=" + manifest,
        "write.path=" + mesh_path,
        "write.height=0",
        "write.unit_scale=1",
    ]
    for s in base + list(sets):
        cmd += ["--set", s]
    return cmd


class Run:
    """One conceptmesh process, its events read on threads into a queue."""

    def __init__(self, cmd, cwd):
        self.cmd = cmd
        self.events = queue.Queue()
        self.stderr_lines = []
        self.end = None  # the stream's "end" event
        flags = {}
        if sys.platform != "win32":
            flags["start_new_session"] = True  # Ctrl-C in Blender's terminal stays Blender's
        self.proc = subprocess.Popen(
            cmd,
            cwd=cwd,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            encoding="utf-8",
            errors="replace",
            bufsize=1,
            **flags,
        )
        self._threads = [
            threading.Thread(target=self._read_stdout, daemon=True),
            threading.Thread(target=self._read_stderr, daemon=True),
        ]
        for t in self._threads:
            t.start()

    def _read_stdout(self):
        for line in self.proc.stdout:
            line = line.strip()
            if not line:
                continue
            try:
                ev = json.loads(line)
            except ValueError:
                ev = {"event": "message", "level": "info", "node": "", "stage": "", "message": line}
            self.events.put(ev)
        self.events.put({"event": "_eof"})

    def _read_stderr(self):
        for line in self.proc.stderr:
            self.stderr_lines.append(line.rstrip("\n"))

    def poll(self):
        """Events that arrived since the last call."""
        out = []
        while True:
            try:
                ev = self.events.get_nowait()
            except queue.Empty:
                return out
            if ev.get("event") == "end":
                self.end = ev
            out.append(ev)

    def finished(self):
        return self.proc.poll() is not None and not any(t.is_alive() for t in self._threads)

    def wait(self, on_event=None):
        """Runs to the end (scripts, background mode), handing each event to `on_event`."""
        while True:
            ev = self.events.get()
            if ev.get("event") == "end":
                self.end = ev
            if ev.get("event") == "_eof":
                break
            if on_event:
                on_event(ev)
        self.proc.wait()
        for t in self._threads:
            t.join()
        return self.proc.returncode

    def cancel(self, grace=5.0):
        """Asks the command to stop (it removes what it staged) and waits; kills it if it does not."""
        if self.proc.poll() is None:
            try:
                if sys.platform == "win32":
                    self.proc.terminate()
                else:
                    self.proc.send_signal(signal.SIGTERM)
                self.proc.wait(timeout=grace)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        for t in self._threads:
            t.join(timeout=2.0)

    def error_line(self):
        """The one-line cause of a failed run: from the stream's end line, else stderr."""
        e = self.end or {}
        if e.get("status") == "cancelled":
            return "cancelled"
        if e.get("cause"):
            where = ' node "%s" (%s)' % (e["node"], e["stage"]) if e.get("node") else ""
            return "conceptmesh%s: %s" % (where, e["cause"])
        for line in reversed(self.stderr_lines):
            if line.strip():
                return line.strip()
        return "conceptmesh stopped with exit status %s" % self.proc.returncode
