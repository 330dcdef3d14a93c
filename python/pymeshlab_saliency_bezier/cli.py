"""saliency-bezier-smooth: smooth files and folders of meshes with the Saliency Bezier Smooth filter,
in parallel processes on this machine (-j N) or on a Dask cluster (--scheduler ADDRESS).

Every output is written to a temporary name in its folder and renamed into place when complete.
The exit status is 0 when every mesh was smoothed, 1 when the filter refused a mesh or a file could
not be read or written (each gets its own message), 2 for a usage error.
"""
import argparse
import concurrent.futures
import json
import multiprocessing
import os
import pathlib
import queue as queue_module
import sys
import time

from . import METHODS, SMOOTH, __version__, strength_to_iterations
from . import batch

# Formats PyMeshLab 2025.07 reads that hold triangles; a folder is searched for these. A file named
# on the command line is tried whatever its extension (point-cloud formats such as .xyz load, and
# the filter then refuses them: it needs faces).
MESH_EXTENSIONS = ("ply", "obj", "off", "stl", "3ds", "ctm", "dae", "fbx", "glb", "gltf", "qobj",
                   "tri", "vmi", "wrl", "x3d", "x3dv")
STATUS_WORDS = {"ok": "ok", "refused": "REFUSED", "failed": "FAILED"}


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="saliency-bezier-smooth",
        description="Smooth meshes with the Saliency Bezier Smooth filter (feature-preserving "
                    "mesh smoothing for PyMeshLab). Folders are searched recursively; each output "
                    "keeps the input's path below the folder given.",
        epilog="Exit status: 0 all smoothed, 1 some mesh refused or unreadable/unwritable, "
               "2 usage error. Docs: docs/INSTALL.md of the project.")
    parser.add_argument("inputs", nargs="+", metavar="IN", type=pathlib.Path,
                        help="mesh files (any format PyMeshLab reads) or folders of them")
    parser.add_argument("-o", "--output", required=True, type=pathlib.Path, metavar="OUTDIR",
                        help="folder for the smoothed meshes (created if missing)")
    parser.add_argument("--method", default="automatic",
                        choices=["automatic", "feature", "organic", "ring", "patch", "newton"],
                        help="placement method (the filter's `placement`): automatic (default: "
                             "feature-preserving on meshes with sharp features, organic "
                             "otherwise), feature, organic, ring (ring barycentre), patch (patch "
                             "point), newton (the paper's Newton placement)")
    amount = parser.add_mutually_exclusive_group()
    amount.add_argument("--strength", type=float, default=None, metavar="S",
                        help="multiplier of the default amount of smoothing: iterations = "
                             "round(3 * S), so 1 (default) = what the mesh's noise estimate asks "
                             "for, 2 = twice that, 0 = none")
    amount.add_argument("--iterations", type=int, default=None, metavar="N",
                        help="the filter's `iterations` directly (3 = strength 1)")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="any other parameter of the filter by its Python name, e.g. "
                             "--param preserve_volume=false (repeatable)")
    parser.add_argument("--format", metavar="EXT",
                        help="output format by extension, e.g. ply (default: the input's)")
    parser.add_argument("--ext", metavar="LIST", default=",".join(MESH_EXTENSIONS),
                        help="extensions searched for in folders, comma separated (default: "
                             "%(default)s)")
    parser.add_argument("--skip-existing", action="store_true",
                        help="leave meshes whose output exists (to resume a stopped run)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("-j", "--jobs", type=int, default=1, metavar="N",
                       help="meshes smoothed at once, each in its own process (default 1; the "
                            "filter itself also uses the cores through OpenMP)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on a Dask distributed cluster, e.g. tcp://host:8786 (needs the "
                            "'dask' extra; inputs and OUTDIR on storage every worker sees at the "
                            "same path)")
    where.add_argument("--local-cluster", type=int, metavar="N",
                       help="run on a Dask LocalCluster of N one-thread worker processes on this "
                            "machine (to try the cluster mode)")
    parser.add_argument("--report", type=pathlib.Path, metavar="FILE",
                        help="also write every mesh's result as JSON to FILE")
    progress = parser.add_mutually_exclusive_group()
    progress.add_argument("--progress", dest="progress", action="store_const", const=True,
                          help="progress bars even when stderr is not a terminal")
    progress.add_argument("--no-progress", dest="progress", action="store_const", const=False,
                          help="no progress bars (the per-mesh lines stay)")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error("-j must be at least 1")
    if args.local_cluster is not None and args.local_cluster < 1:
        parser.error("--local-cluster must be at least 1")
    if args.strength is not None and not args.strength >= 0:
        parser.error("--strength must be >= 0")
    if args.iterations is not None and args.iterations < 0:
        parser.error("--iterations must be >= 0")
    return parser, args


# ---- what to run ----------------------------------------------------------------------------------

def filter_parameters(parser, args):
    """The filter's keyword arguments: method, strength, and --param values checked against the
    filter's own parameter list (names and types) before any mesh is touched."""
    import numpy
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=numpy.eye(3), face_matrix=numpy.array([[0, 1, 2]])))
    defaults = ms.filter_parameter_values(SMOOTH)
    params = {"placement": METHODS[args.method]}
    if args.iterations is not None:
        params["iterations"] = args.iterations
    else:
        params["iterations"] = strength_to_iterations(1.0 if args.strength is None else args.strength)
    for item in args.param:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or name not in defaults:
            parser.error(f"--param {item!r}: the filter's parameters are "
                         + ", ".join(f"{n}={v!r}" for n, v in defaults.items()))
        if name in ("placement", "iterations"):
            parser.error(f"--param {name}: use --method / --strength / --iterations")
        params[name] = _typed(parser, name, text.strip(), defaults[name])
    return params


def _typed(parser, name, text, default):
    try:
        if isinstance(default, bool):
            if text.lower() in ("1", "true", "yes", "on"):
                return True
            if text.lower() in ("0", "false", "no", "off"):
                return False
            raise ValueError(text)
        if isinstance(default, int):
            return int(text) if text.lstrip("-").isdigit() else text  # an enum's label passes as is
        if isinstance(default, float):
            return float(text)
    except ValueError:
        parser.error(f"--param {name}={text}: expected a value like {default!r}")
    return text


def find_meshes(parser, args):
    """[(input, output)] for every mesh file of the inputs, in a stable order."""
    out_dir = args.output.resolve()
    extensions = {"." + e.strip().lower().lstrip(".") for e in args.ext.split(",") if e.strip()}
    pairs = []
    for given in args.inputs:
        if given.is_file():
            pairs.append((given.resolve(), pathlib.Path(given.name)))
        elif given.is_dir():
            root = given.resolve()
            for folder, dirs, files in os.walk(root):
                here = pathlib.Path(folder)
                # Never descend into OUTDIR (OUTDIR inside an input folder) or hidden folders.
                dirs[:] = sorted(d for d in dirs
                                 if not d.startswith(".") and (here / d).resolve() != out_dir)
                for name in sorted(files):
                    if not name.startswith(".") and pathlib.Path(name).suffix.lower() in extensions:
                        pairs.append((here / name, (here / name).relative_to(root)))
        else:
            parser.error(f"{given}: no such file or folder")
    planned, seen = [], {}
    for source, relative in pairs:
        if args.format:
            relative = relative.with_suffix("." + args.format.lower().lstrip("."))
        target = out_dir / relative
        if target in seen:
            parser.error(f"{source} and {seen[target]} would both be written to {target}")
        if target == source:
            parser.error(f"{source} would be overwritten by its own output: choose another -o")
        seen[target] = source
        planned.append((source, target))
    return planned


# ---- progress display -----------------------------------------------------------------------------

class Display:
    """An overall bar (meshes done) and one bar per mesh being smoothed (its stage and the filter's
    own percentage), on stderr; one line per finished mesh on stdout (errors on stderr)."""

    def __init__(self, total, slots, enabled):
        from tqdm import tqdm

        self.tqdm = tqdm
        self.enabled = enabled
        self.overall = tqdm(total=total, desc="meshes", unit="mesh", position=0,
                            disable=not enabled, dynamic_ncols=True, leave=True)
        self.free = list(range(1, slots + 1))
        self.bars = {}  # mesh index -> its bar
        self.counts = {"ok": 0, "refused": 0, "failed": 0}

    def event(self, event, names):
        index = event["index"]
        if index not in self.bars:
            if not self.free:
                return
            slot = self.free.pop(0)
            self.bars[index] = (slot, self.tqdm(
                total=100, position=slot, leave=False, disable=not self.enabled,
                dynamic_ncols=True, bar_format="{desc} {percentage:3.0f}%|{bar}|"))
        bar = self.bars[index][1]
        bar.set_description_str(f"{_short(names[index])}: {event['stage']}", refresh=False)
        bar.update(max(0.0, float(event["percent"]) - bar.n))

    def finished(self, result, line):
        slot, bar = self.bars.pop(result["index"], (None, None))
        if bar is not None:
            bar.close()
            self.free = sorted(self.free + [slot])
        self.counts[result["status"]] += 1
        stream = sys.stdout if result["status"] == "ok" else sys.stderr
        self.tqdm.write(line, file=stream)
        self.overall.set_postfix_str(
            ", ".join(f"{n} {k}" for k, n in self.counts.items() if n and k != "ok"), refresh=False)
        self.overall.update(1)

    def close(self):
        for _, bar in self.bars.values():
            bar.close()
        self.overall.close()


def _short(name, width=40):
    return name if len(name) <= width else "..." + name[-(width - 3):]


def describe(result, requested):
    """The line printed for one finished mesh."""
    word = STATUS_WORDS[result["status"]]
    if result["status"] != "ok":
        return f"{word} {result['input']}: {result['message']}"
    seconds = result["seconds"]
    method = result["method"]
    if requested == "automatic":
        method = f"automatic -> {method}"
    line = (f"{word} {result['input']} -> {result['output']}: {result['vertices']} vertices, "
            f"{method}, {seconds['total']:.2f} s (filter {seconds['filter']:.2f} s)")
    moved = result.get("moved")
    if moved:
        line += (f", {moved['vertices_moved']} vertices moved by {moved['mean_displacement']:.3f}"
                 f" mean edge lengths, noise estimate {moved['roughness']:.2f}")
    return line


# ---- where to run ---------------------------------------------------------------------------------

def _threads_per_process(processes):
    """OpenMP threads of each worker process: the cores shared out (unless OMP_NUM_THREADS is set),
    so -j N does not start N times as many threads as there are cores. Results do not depend on
    it."""
    if "OMP_NUM_THREADS" not in os.environ:
        os.environ["OMP_NUM_THREADS"] = str(max(1, (os.cpu_count() or 1) // processes))


def run_local(jobs, processes, on_event, on_result):
    """Runs the jobs in `processes` spawned processes. A process that dies (a crash inside
    PyMeshLab) takes only its own mesh down: the meshes that were running are tried once more in
    a new pool, and fail if they are running again when it dies."""
    context = multiprocessing.get_context("spawn")
    _threads_per_process(processes)
    left, crashes = list(jobs), {}
    while left:
        events = context.Queue()
        running = set()
        retry = []
        with concurrent.futures.ProcessPoolExecutor(
                processes, mp_context=context, initializer=batch.init_local_worker,
                initargs=(events,)) as pool:
            futures = {pool.submit(batch.local_task, job): job for job in left}
            pending = set(futures)
            while pending:
                done, pending = concurrent.futures.wait(
                    pending, timeout=0.1, return_when=concurrent.futures.FIRST_COMPLETED)
                _drain(events, lambda e: (running.add(e["index"]), on_event(e)))
                for future in done:
                    job = futures[future]
                    try:
                        on_result(future.result())
                    except concurrent.futures.process.BrokenProcessPool:
                        retry.append(job)
                    except Exception as error:  # pickling or the like: this mesh fails alone
                        on_result(_failure(job, f"{type(error).__name__}: {error}"))
        _drain(events, lambda e: (running.add(e["index"]), on_event(e)))
        left = []
        for job in retry:
            if job["index"] in running:
                crashes[job["index"]] = crashes.get(job["index"], 0) + 1
                if crashes[job["index"]] >= 2:
                    on_result(_failure(job, "the worker process crashed on this mesh (twice)"))
                    continue
            left.append(job)


def _drain(events, handle):
    while True:
        try:
            handle(events.get_nowait())
        except queue_module.Empty:
            return
        except (EOFError, OSError):
            return


def _failure(job, message):
    return {"index": job["index"], "input": job["input"], "output": job["output"],
            "status": "failed", "message": message, "seconds": {}}


def run_dask(jobs, scheduler, local_workers, on_event, on_result):
    """Runs the jobs as Dask tasks on the cluster at `scheduler`, or on a LocalCluster of
    `local_workers` one-thread processes. Progress comes back through the scheduler's event log."""
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        sys.exit("saliency-bezier-smooth: Dask is not installed: pip install "
                 "'pymeshlab-saliency-bezier[dask]' (or dask[distributed])")
    cluster = None
    if local_workers:
        _threads_per_process(local_workers)
        cluster = LocalCluster(n_workers=local_workers, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address=None)
    events = queue_module.Queue()
    try:
        with Client(cluster if cluster is not None else scheduler) as client:
            _check_worker_versions(client)
            client.subscribe_topic(batch.PROGRESS_TOPIC, lambda item: events.put(item[1]))
            futures = {client.submit(batch.dask_task, job, pure=False,
                                     key=f"saliency-bezier-smooth-{os.getpid()}-{job['index']}"): job
                       for job in jobs}
            finished = as_completed(futures)
            while not finished.is_empty():
                batch_done = finished.next_batch(block=False)
                _drain(events, on_event)
                if not batch_done:
                    time.sleep(0.1)
                for future in batch_done:
                    job = futures[future]
                    try:
                        on_result(future.result())
                    except Exception as error:  # the worker died (KilledWorker) or the task broke
                        on_result(_failure(job, f"{type(error).__name__}: {error}"))
            _drain(events, on_event)
            client.unsubscribe_topic(batch.PROGRESS_TOPIC)
    finally:
        if cluster is not None:
            cluster.close()


def _check_worker_versions(client):
    """Every worker must run this package and pymeshlab at the command's versions."""
    mine = batch.installed_versions()
    theirs = client.run(batch.installed_versions)
    if not theirs:
        sys.exit("saliency-bezier-smooth: the Dask cluster has no workers")
    wrong = {w: v for w, v in theirs.items() if tuple(v) != mine}
    if wrong:
        sys.exit("saliency-bezier-smooth: workers with other versions of pymeshlab-saliency-bezier "
                 f"/ pymeshlab than this command's {mine}: {wrong}")


# ---- main -----------------------------------------------------------------------------------------

def main(argv=None):
    parser, args = parse_arguments(sys.argv[1:] if argv is None else argv)
    params = filter_parameters(parser, args)
    planned = find_meshes(parser, args)
    if not planned:
        parser.error("no mesh files found in the inputs (searched for: " + args.ext + ")")
    jobs, skipped = [], 0
    for source, target in planned:
        if args.skip_existing and target.exists():
            skipped += 1
            continue
        jobs.append({"index": len(jobs), "input": str(source), "output": str(target),
                     "params": params, "method": args.method})
    args.output.mkdir(parents=True, exist_ok=True)

    workers = args.local_cluster or args.jobs
    use_dask = args.scheduler is not None or args.local_cluster is not None
    enabled = sys.stderr.isatty() if args.progress is None else args.progress
    display = Display(len(jobs), min(workers, 8) if not args.scheduler else 8, enabled)
    names = {job["index"]: os.path.basename(job["input"]) for job in jobs}
    results = []

    def on_result(result):
        results.append(result)
        display.finished(result, describe(result, args.method))

    started = time.monotonic()
    try:
        if use_dask:
            run_dask(jobs, args.scheduler, args.local_cluster,
                     lambda e: display.event(e, names), on_result)
        else:
            run_local(jobs, args.jobs, lambda e: display.event(e, names), on_result)
    except KeyboardInterrupt:
        display.close()
        print("saliency-bezier-smooth: interrupted; finished outputs are complete, others were "
              "not written", file=sys.stderr)
        return 130
    display.close()

    counts = {k: sum(r["status"] == k for r in results) for k in STATUS_WORDS}
    engine = (f"Dask {args.scheduler}" if args.scheduler else
              f"Dask LocalCluster of {args.local_cluster}" if args.local_cluster else
              f"{args.jobs} process{'es' if args.jobs > 1 else ''}")
    print(f"{counts['ok']} smoothed, {counts['refused']} refused, {counts['failed']} failed"
          + (f", {skipped} skipped (output exists)" if skipped else "")
          + f" in {time.monotonic() - started:.1f} s ({engine})")
    if args.report:
        args.report.write_text(json.dumps(sorted(results, key=lambda r: r["index"]), indent=1))
    return 0 if counts["ok"] == len(jobs) else 1


if __name__ == "__main__":
    sys.exit(main())
