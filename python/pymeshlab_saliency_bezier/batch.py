"""One mesh file through the smoothing filter: the task that the batch command runs in its worker
processes, local (-j N) or on Dask workers (--scheduler / --local-cluster).

smooth_file(job) loads job["input"] with PyMeshLab, applies the filter with job["params"] and writes
job["output"] atomically: the mesh is saved into a temporary folder beside the output (same file
system), then renamed into place, sidecar files first (an OBJ's .mtl), the mesh last. A refused,
unreadable or crashed mesh leaves no file under the output name.

Progress: a verbose MeshSet prints a filter's progress and log to the process's stderr (file
descriptor 2: "LOG: 2 Moving vertices    [ 45% ]") and its parameters to stdout. smooth_file reads
both from pipes put on descriptors 1 and 2 for the duration of the call and passes progress events
to `emit`, which the caller sets (a queue to the command's process, or a Dask event topic).
"""
import ctypes
import os
import re
import shutil
import socket
import sys
import tempfile
import threading
import time

PROGRESS_TOPIC = "saliency-bezier-smooth-progress"
_PERCENT = re.compile(r"\[\s*(\d+)%\s*\]\s*$")
_LOG = re.compile(r"^LOG: \d+ (.*?)(?:\s*\[\s*\d+%\s*\])?\s*$")
# The filter's log starts with one summary line (vcg_ext: MethodRun::summary).
_SUMMARY = re.compile(r"^(Automatic|Feature-preserving|Organic|Paper's method)\b")
# The filter returns the row of its Method choice that ran (-1: none, the mesh measured clean).
_METHOD_ROWS = ["ring barycentre", "patch point", "paper (Newton)", "feature-preserving",
                "organic", "automatic"]
# One filter call at a time per process: PyMeshLab keeps process-wide state (its logger) and the
# capture below owns descriptors 1 and 2.
_PROCESS_LOCK = threading.Lock()
_libc = ctypes.CDLL(None)


class _DescriptorLines:
    """Puts a pipe on file descriptor `fd` (1 or 2) and hands every line written to it, by C, C++
    or Python, to on_line(line, original_fd) from a reader thread. PyMeshLab's filters release the
    GIL, so lines arrive while the filter runs."""

    def __init__(self, fd, on_line):
        self.fd, self.on_line = fd, on_line

    def __enter__(self):
        sys.stdout.flush()
        sys.stderr.flush()
        self.saved = os.dup(self.fd)
        read_end, write_end = os.pipe()
        os.dup2(write_end, self.fd)
        os.close(write_end)
        self.reader = threading.Thread(target=self._read, args=(read_end,), daemon=True)
        self.reader.start()
        return self

    def _read(self, read_end):
        with os.fdopen(read_end, "rb") as pipe:
            for raw in pipe:
                try:
                    self.on_line(raw.decode("utf-8", "replace").rstrip("\n"), self.saved)
                except Exception:  # a display problem must never stop the filter
                    pass

    def __exit__(self, *exc):
        sys.stdout.flush()
        sys.stderr.flush()
        _libc.fflush(None)
        os.dup2(self.saved, self.fd)  # closes the pipe's last write end: the reader sees its end
        self.reader.join(timeout=10)
        os.close(self.saved)


class _Progress:
    """Turns the stages and PyMeshLab's percentages into events for one file: percent of the whole
    job (load 0-5, filter 5-95, save 95-100). An event goes out at each new stage, at every 10
    points of progress and otherwise at most ~10 times a second: the sequence a mesh produces
    depends on what the filter reports, not on how fast the machine runs it (only the extra timed
    events do)."""

    STEP = 10  # percent of the whole job between events that are sent whatever the clock says

    def __init__(self, job, emit):
        self.job, self.emit = job, emit
        self.last_sent = 0.0
        self.last_percent = None
        self.stage = None
        self.log = []

    def send(self, stage, percent, force=False):
        now = time.monotonic()
        stepped = self.last_percent is not None and percent >= self.last_percent + self.STEP
        if force or stage != self.stage or stepped or now - self.last_sent >= 0.1:
            self.stage, self.last_sent, self.last_percent = stage, now, percent
            self.emit({"index": self.job["index"], "stage": stage, "percent": percent})

    def stderr_line(self, text, original):
        """A line that PyMeshLab wrote to stderr while the filter ran: its log ("LOG: <level>
        <text>", with "[ NN% ]" for progress). Anything else is passed on to the real stderr."""
        log = _LOG.match(text)
        if not log:
            os.write(original, (text + "\n").encode())
            return
        match = _PERCENT.search(text)
        if match:
            self.send("smoothing", 5 + 0.9 * min(100, int(match.group(1))))
        else:
            self.log.append(log.group(1))


def _emit_nothing(event):
    pass


def _reset_pymeshlab(pymeshlab):
    """After a filter throws, pymeshlab 2025.7.post1 keeps a pointer to that MeshSet's log, and the
    next progress callback after the MeshSet is freed can crash; one successful filter resets it."""
    import numpy

    reset = pymeshlab.MeshSet()
    reset.add_mesh(pymeshlab.Mesh(vertex_matrix=numpy.eye(3), face_matrix=numpy.array([[0, 1, 2]])))
    reset.apply_filter("set_selection_none")


def _details(error):
    """The filter's own message out of PyMeshLab's 'Failed to apply filter: X\\nDetails: msg'."""
    text = str(error).strip()
    return text.split("Details:", 1)[1].strip() if "Details:" in text else text


def method_that_ran(result, log, requested):
    """The method that ran: the row the filter returns as "method" (the automatic one's choice;
    -1 when the mesh measured as clean and was left as it was), else the method asked for."""
    row = result.get("method") if isinstance(result, dict) else None
    if isinstance(row, int) and -1 <= row < len(_METHOD_ROWS):
        return "none (measured clean: left as it is)" if row < 0 else _METHOD_ROWS[row]
    return requested if requested != "automatic" else "?"


def summary_of(result, log):
    """One line about what the filter did: the summary line the filter logs first."""
    return next((line for line in log if _SUMMARY.match(line)), "")


def _save_atomically(ms, output):
    """Saves into a new temporary folder beside output, then renames the files into place."""
    folder = os.path.dirname(output) or "."
    os.makedirs(folder, exist_ok=True)
    staging = tempfile.mkdtemp(prefix=".saliency-bezier-tmp-", dir=folder)
    try:
        name = os.path.basename(output)
        ms.save_current_mesh(os.path.join(staging, name))
        if not os.path.isfile(os.path.join(staging, name)):
            raise RuntimeError("PyMeshLab wrote no file")
        for extra in sorted(os.listdir(staging)):  # sidecars (an OBJ's .mtl) before the mesh
            if extra != name:
                os.replace(os.path.join(staging, extra), os.path.join(folder, extra))
        os.replace(os.path.join(staging, name), output)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def smooth_file(job, emit=_emit_nothing):
    """Smooths one mesh file. job: {"index", "input", "output", "params" (filter keyword
    arguments), "method" (the name asked for)}. Returns a dict with "status" ("ok", "refused": the
    filter refused the mesh, "failed": unreadable or unwritable) and "message", or the figures of
    the run: "vertices", "faces", "method", "summary", "seconds" per stage."""
    with _PROCESS_LOCK:
        return _smooth_file(job, emit)


def _smooth_file(job, emit):
    import pymeshlab

    from . import SMOOTH

    progress = _Progress(job, emit)
    where = f"{socket.gethostname()}:{os.getpid()}"
    result = {"index": job["index"], "input": job["input"], "output": job["output"],
              "worker": where, "seconds": {}}
    start = time.monotonic()

    def failed(status, message):
        result.update(status=status, message=message)
        result["seconds"]["total"] = time.monotonic() - start
        return result

    if not os.path.isfile(job["input"]):
        return failed("failed", f"input not found on {socket.gethostname()} (on a cluster: is the "
                                "storage shared, at the same path, by every worker?)")
    progress.send("loading", 0, force=True)
    ms = pymeshlab.MeshSet()
    try:
        ms.load_new_mesh(job["input"])
    except pymeshlab.PyMeshLabException as error:
        _reset_pymeshlab(pymeshlab)
        return failed("failed", f"cannot read the mesh: {_details(error)}")
    if ms.mesh_number() != 1:
        return failed("failed", f"the file holds {ms.mesh_number()} meshes; the batch command "
                                "smooths files of one mesh")
    mesh = ms.current_mesh()
    result.update(vertices=mesh.vertex_number(), faces=mesh.face_number())
    result["seconds"]["load"] = time.monotonic() - start

    progress.send("smoothing", 5, force=True)
    started = time.monotonic()
    ms.set_verbosity(True)
    try:
        # Verbose PyMeshLab prints the parameters to stdout (dropped) and the log to stderr.
        with _DescriptorLines(1, lambda text, original: None), \
                _DescriptorLines(2, progress.stderr_line):
            returned = ms.apply_filter(SMOOTH, **job["params"])
    except Exception as error:  # PyMeshLabException: the filter refused the mesh (its message)
        ms.set_verbosity(False)
        _reset_pymeshlab(pymeshlab)
        refused = isinstance(error, pymeshlab.PyMeshLabException)
        return failed("refused" if refused else "failed", _details(error))
    ms.set_verbosity(False)
    result["seconds"]["filter"] = time.monotonic() - started
    result.update(method=method_that_ran(returned, progress.log, job.get("method", "?")),
                  summary=summary_of(returned, progress.log), log=progress.log,
                  moved={key: returned[key] for key in
                         ("vertices_moved", "mean_displacement", "roughness")}
                  if isinstance(returned, dict) and "vertices_moved" in returned else None)

    progress.send("saving", 95, force=True)
    started = time.monotonic()
    try:
        _save_atomically(ms, job["output"])
    except (pymeshlab.PyMeshLabException, OSError, RuntimeError) as error:
        _reset_pymeshlab(pymeshlab)
        return failed("failed", f"cannot write {job['output']}: {_details(error)}")
    result["seconds"]["save"] = time.monotonic() - started
    result["seconds"]["total"] = time.monotonic() - start
    result["status"] = "ok"
    progress.send("done", 100, force=True)
    return result


# ---- the two ways the command runs smooth_file ---------------------------------------------------

_queue = None


def init_local_worker(queue):
    """ProcessPoolExecutor initializer: progress goes to the command's queue."""
    global _queue
    _queue = queue


def local_task(job):
    return smooth_file(job, _queue.put if _queue is not None else _emit_nothing)


def dask_task(job):
    """The task submitted to Dask: progress goes to the scheduler's event topic, which the command
    subscribes to."""
    from distributed import get_worker

    worker = get_worker()
    return smooth_file(job, lambda event: worker.log_event(PROGRESS_TOPIC, event))


def installed_versions():
    """(our version, pymeshlab's version) in this process: the command compares its workers'."""
    from importlib.metadata import version

    return version("pymeshlab-saliency-bezier"), version("pymeshlab")
