"""The benchmark: our Saliency Bezier Smooth against MeshLab 2020.09's own smoothing filters, in
quality (the denoising literature's scores) and speed. Started by bench/run.sh, which installs the
dependencies and builds the tools; see bench/README.md.

Quality: every case is a clean/noisy pair with the same connectivity; each method smooths the noisy
mesh and tools/mesh_compare scores the result against the clean one. MeshLab's filters run at
their defaults and over a small sweep whose best setting (lowest theta) is the fair strongest
baseline. Speed: the same run times our filter (in-process and inside meshlabserver) and MeshLab's
filters (inside meshlabserver, with a load+save-only run as the overhead baseline) on ~10k, ~100k
and ~1M vertex meshes, interleaved, median of N runs.
"""
import argparse
import datetime
import json
import math
import os
import pathlib
import platform
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tarfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import meshio  # noqa: E402
import sd_filter  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[1]
SHARED = pathlib.Path(os.environ.get("SBS_SHARED_DIR", REPO.parent / "shared"))
CGAL_DATA = pathlib.Path("/usr/share/doc/libcgal-demo/data.tar.gz")
MESHLAB_LIB = "/usr/lib/x86_64-linux-gnu/meshlab"
NOISE_SEED = 20090601  # fixed: every run makes the same noisy meshes

# Debian libcgal-demo meshes used as extra cases (all manifold, consistently oriented triangles).
CGAL_CASES = ["armadillo", "lion-head", "elephant-with-holes", "three_peaks"]
CGAL_NOISE = [0.1, 0.2, 0.3]
# Timing meshes: (label, libcgal-demo mesh, midpoint subdivisions) -> ~10k, ~100k, ~1M vertices.
# Issue 7's sizes are 104k and 1.66M; the armadillo at every subdivision level gives the log-log
# growth from 26k to 1.66M on one shape.
TIMING_MESHES = [("10k", "camel", 0), ("26k", "armadillo", 0), ("104k", "armadillo", 1),
                 ("416k", "armadillo", 2), ("1.66M", "armadillo", 3)]
# Issue 7's targets: whole meshlabserver process vs Taubin x10 and TwoStep in the same run; peak
# memory vs a load+save-only run.
TARGET_TAUBIN_RATIO, TARGET_TWOSTEP_RATIO, TARGET_RSS_RATIO = 2.0, 0.2, 1.5

# MeshLab 2020.09 filter_unsharp: every parameter of each filter (meshlabserver asserts on a
# missing one), names and defaults from src/meshlabplugins/filter_unsharp/filter_unsharp.cpp.
PEERS = ["Laplacian", "HC Laplacian", "Taubin", "TwoStep"]
PEER_DEFAULT = {"Laplacian": {"steps": 3}, "HC Laplacian": {"repeat": 1},
                "Taubin": {"steps": 10}, "TwoStep": {"steps": 3, "thr": 60}}
PEER_SWEEP = {
    "Laplacian": [{"steps": s} for s in (1, 3, 5, 10)],
    "HC Laplacian": [{"repeat": r} for r in (1, 2, 3, 5, 10)],
    "Taubin": [{"steps": s} for s in (5, 10, 20, 40, 80)],
    "TwoStep": [{"steps": s, "thr": t} for s in (1, 3, 6) for t in (45, 60, 75)],
}
# Timing settings (issue 4): Laplacian x5 (the paper's comparison), the others at defaults.
PEER_TIMING = {"Laplacian": {"steps": 5}, "HC Laplacian": {"repeat": 1},
               "Taubin": {"steps": 10}, "TwoStep": {"steps": 3, "thr": 60}}
OURS = {  # label -> smooth_mesh overrides (placement: 0 ring barycentre, 1 patch point, 2 Newton,
    # 3 feature-preserving face patches, 4 organic band shrinkage, 5 automatic: 3 or 4, the default)
    "ours automatic (default)": [],
    "ours ring barycentre": ["placement=0"],
    "ours feature-preserving": ["placement=3"],
    "ours organic": ["placement=4"],
    "ours patch point": ["placement=1"],
    "ours paper (safeguard)": ["placement=2"],
    "ours paper (as printed)": ["placement=2", "newton_step_limit=0"],
}
OURS_ITERATIONS = [1, 2, 3, 4, 6, 8, 12, 16, 20]
TAUBIN_ITERATIONS = [1, 2, 5, 10, 20, 40, 80, 160]
# The SD filter (Debian's meshsdfilter-tools, bench/sd_filter.py): at its defaults and at the best
# of sd_filter.SWEEP (quick mode: the defaults only, to keep CI short). Timed like MeshLab's filters
# (whole process) on the timing meshes up to SD_TIMING_MAX_VERTICES: beyond, one run takes many
# minutes and gigabytes.
SD = "SD filter"
SD_TIMING_MAX_VERTICES = 110_000
SD_TIMING_LABEL = "SD filter (defaults; its own I/O)"
LAPLACIAN_ITERATIONS = [1, 2, 3, 5, 10, 20]


def peer_setting_text(peer, s):
    if peer == "Laplacian" or peer == "Taubin":
        return f"x{s['steps']}"
    if peer == "HC Laplacian":
        return f"x{s['repeat']}"
    return f"x{s['steps']}, {s['thr']}deg"


def peer_mlx(peer, s, times=1):
    """A meshlabserver script applying the filter with setting `s`, `times` times in a row."""
    def param(name, kind, value):
        return f'  <Param name="{name}" type="{kind}" value="{value}"/>\n'
    blocks = []
    if peer == "Laplacian":
        blocks.append(("Laplacian Smooth", param("stepSmoothNum", "RichInt", s["steps"]) +
                       param("Boundary", "RichBool", "true") +
                       param("cotangentWeight", "RichBool", "true") +
                       param("Selected", "RichBool", "false")))
    elif peer == "HC Laplacian":  # no parameters: one step per application
        blocks += [("HC Laplacian Smooth", "")] * s["repeat"]
    elif peer == "Taubin":
        blocks.append(("Taubin Smooth", param("lambda", "RichFloat", 0.5) +
                       param("mu", "RichFloat", -0.53) +
                       param("stepSmoothNum", "RichInt", s["steps"]) +
                       param("Selected", "RichBool", "false")))
    elif peer == "TwoStep":
        blocks.append(("TwoStep Smooth", param("stepSmoothNum", "RichInt", s["steps"]) +
                       param("normalThr", "RichFloat", s["thr"]) +
                       param("stepNormalNum", "RichInt", 20) +
                       param("stepFitNum", "RichInt", 20) +
                       param("Selected", "RichBool", "false")))
    body = "".join(f' <filter name="{n}">\n{p} </filter>\n' for n, p in blocks * times)
    return f"<!DOCTYPE FilterScript>\n<FilterScript>\n{body}</FilterScript>\n"


def log(*a):
    print("[bench]", *a, file=sys.stderr, flush=True)


class BenchError(RuntimeError):
    pass


class Runner:
    """Runs the tools and meshlabserver, memoising quality runs within one benchmark run."""

    def __init__(self, build, work):
        self.build = build
        self.work = work
        self.tools = build / "tools"
        self.meshlabserver = build / "meshlab" / "meshlabserver"
        self.env = dict(os.environ)
        self.env["LD_LIBRARY_PATH"] = MESHLAB_LIB + ":" + self.env.get("LD_LIBRARY_PATH", "")
        self.xvfb = None
        self.memo = {}
        self.quality_threads = None  # OMP_NUM_THREADS of untimed runs (set when run in parallel)
        self.lock = threading.Lock()
        self.mlx_dir = work / "mlx"
        self.mlx_dir.mkdir(parents=True, exist_ok=True)

    # --- X server for meshlabserver: one for the whole run, so that timings exclude its start-up
    def start_xvfb(self):
        read_fd, write_fd = os.pipe()
        self.xvfb = subprocess.Popen(
            ["Xvfb", "-displayfd", str(write_fd), "-nolisten", "tcp", "-screen", "0",
             "640x480x24"], pass_fds=(write_fd,), stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL)
        os.close(write_fd)
        with os.fdopen(read_fd) as f:
            display = f.readline().strip()
        if not display:
            raise BenchError("Xvfb did not start")
        self.env["DISPLAY"] = ":" + display
        log(f"Xvfb on display :{display} (pid {self.xvfb.pid})")

    def stop_xvfb(self):
        if self.xvfb is not None:
            self.xvfb.terminate()
            try:
                self.xvfb.wait(10)
            except subprocess.TimeoutExpired:
                self.xvfb.kill()
            self.xvfb = None

    def run(self, cmd, timed=False, env=None, timeout=3600):
        """Runs cmd; returns (CompletedProcess, wall seconds, peak RSS in MB or None)."""
        cmd = [str(c) for c in cmd]
        rss_file = None
        if timed:
            rss_file = self.work / "time.txt"
            cmd = ["/usr/bin/time", "-v", "-o", str(rss_file)] + cmd
        start = time.perf_counter()
        proc = subprocess.run(cmd, env=env or self.env, capture_output=True, text=True,
                              timeout=timeout)
        wall = time.perf_counter() - start
        rss = None
        if rss_file is not None and rss_file.exists():
            m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", rss_file.read_text())
            rss = int(m.group(1)) / 1024.0 if m else None
        return proc, wall, rss

    def tool(self, name, *args):
        proc, _, _ = self.run([self.tools / name, *args])
        if proc.returncode != 0:
            raise BenchError(f"{name} {' '.join(map(str, args))} failed:\n{proc.stderr[-2000:]}")
        return proc.stdout

    def compare(self, result, clean):
        return json.loads(self.tool("mesh_compare", result, clean))

    def ours_mlx(self, overrides):
        path = self.mlx_dir / ("ours_" + "_".join(o.replace("=", "-") for o in overrides) + ".mlx")
        if not path.exists():
            path.write_text(self.tool("write_mlx", "smooth", *overrides))
        return path

    def peer_mlx_path(self, peer, s, times=1):
        name = peer.replace(" ", "") + "_" + "_".join(f"{k}{v}" for k, v in sorted(s.items()))
        path = self.mlx_dir / (name + (f"_times{times}" if times > 1 else "") + ".mlx")
        if not path.exists():
            path.write_text(peer_mlx(peer, s, times))
        return path

    def smooth_inprocess(self, src, out, overrides, timed=False, threads=None):
        env = None
        if threads is not None:
            env = dict(self.env)
            env["OMP_NUM_THREADS"] = str(threads)
        proc, wall, rss = self.run([self.tools / "smooth_mesh", src, out, *overrides],
                                   timed=timed, env=env)
        if proc.returncode != 0:
            raise BenchError(f"smooth_mesh {src} {overrides}: {proc.stderr[-1500:]}")
        info = json.loads(proc.stdout.strip().splitlines()[-1])
        stages = parse_stages(proc.stderr)
        return {"wall": wall, "rss": rss, "filter": info["seconds"], "stages": stages,
                "log": proc.stderr}

    def meshlab(self, src, out, mlx, timed=False, extra_env=None):
        """extra_env: variables added to the run's environment (e.g. OMP_WAIT_POLICY)."""
        args = [self.meshlabserver, "-i", src, "-o", out]
        if mlx is not None:
            args += ["-s", mlx]
        env = dict(self.env, **extra_env) if extra_env else None
        for attempt in range(3):
            if pathlib.Path(out).exists():
                pathlib.Path(out).unlink()
            proc, wall, rss = self.run(args, timed=timed, env=env)
            if proc.returncode == 0 and pathlib.Path(out).exists():
                return {"wall": wall, "rss": rss, "log": proc.stdout + proc.stderr}
            text = proc.stdout + proc.stderr
            # now and then a start-up cannot reach the X server: try again (not counted)
            if "Qt platform plugin" not in text:
                break
            log(f"meshlabserver could not start (attempt {attempt + 1}), retrying")
        raise BenchError(f"meshlabserver {src} {mlx} failed (rc {proc.returncode}):\n"
                         f"{text[-2000:]}")

    # --- memoised quality runs: (case, method, setting) -> scores
    @staticmethod
    def memo_key(case, method, setting):
        if method == SD:  # {} and the sweep's centre are the same run
            setting = sd_filter.full(setting)
        return (case["name"], method, json.dumps(setting, sort_keys=True))

    def quality(self, case, method, setting):
        key = self.memo_key(case, method, setting)
        if key in self.memo:
            return self.memo[key]
        tag = re.sub(r"[^A-Za-z0-9]+", "_", f"{method}_{json.dumps(setting, sort_keys=True)}")
        out = case["dir"] / f"{tag}.ply"
        start = time.perf_counter()
        try:
            if method == "ours":
                self.smooth_inprocess(case["noisy"], out, setting, threads=self.quality_threads)
            elif method == "ours meshlabserver":
                self.meshlab(case["noisy"], out, self.ours_mlx(setting))
            elif method == SD:
                sd_filter.run(case["noisy"], out, setting, options_dir=self.mlx_dir,
                              threads=self.quality_threads)
            else:
                self.meshlab(case["noisy"], out, self.peer_mlx_path(method, setting))
            wall = time.perf_counter() - start  # whole process(es), untimed conditions
            scores = self.compare(out, case["clean"])
            scores["path"] = str(out)
            scores["wall"] = wall
        except (BenchError, sd_filter.SDError, subprocess.TimeoutExpired) as e:
            log(f"FAILED {case['name']} {method} {setting}: {str(e)[:400]}")
            scores = {"error": str(e)[:400]}
        with self.lock:
            self.memo[key] = scores
        return scores

    def prefetch(self, tasks, jobs):
        """Runs the (case, method, setting) quality tasks, `jobs` at a time (untimed, so they may
        share the cores; each in-process run then gets one OpenMP thread)."""
        seen, todo = set(), []
        for case, method, setting in tasks:
            key = self.memo_key(case, method, setting)
            if key not in seen and key not in self.memo:
                seen.add(key)
                todo.append((case, method, setting))
        self.quality_threads = 1 if jobs > 1 else None
        done = [0]

        def one(task):
            self.quality(*task)
            with self.lock:
                done[0] += 1
                if done[0] % 50 == 0 or done[0] == len(todo):
                    log(f"quality runs: {done[0]}/{len(todo)}")
        with ThreadPoolExecutor(max_workers=jobs) as pool:
            list(pool.map(one, todo))
        self.quality_threads = None


def parse_stages(text):
    m = re.search(r"Time: topology ([\d.]+) s, curvature ([\d.]+) s, saliency ([\d.]+) s, "
                  r"patch fit \+ placement ([\d.]+) s", text)
    if not m:
        return None
    return dict(zip(["topology", "curvature", "saliency", "fit+placement"],
                    map(float, m.groups())))


# --------------------------------------------------------------------------------------------
# Cases

def cgal_meshes(work):
    """Extracts the libcgal-demo meshes the benchmark uses; returns their folder."""
    dest = work / "cgal"
    wanted = set(CGAL_CASES) | {m for _, m, _ in TIMING_MESHES}
    if all((dest / f"{m}.off").exists() for m in wanted):
        return dest
    if not CGAL_DATA.exists():
        raise BenchError(f"{CGAL_DATA} missing: apt-get install libcgal-demo")
    dest.mkdir(parents=True, exist_ok=True)
    with tarfile.open(CGAL_DATA) as tar:
        for member in tar.getmembers():
            name = pathlib.Path(member.name)
            if name.parent.name == "meshes" and name.suffix == ".off" and name.stem in wanted:
                member.name = name.name
                tar.extract(member, dest)
    return dest


def off_to_ply(off, ply):
    if not ply.exists():
        points, faces = meshio.read_off(off)
        ok, why = meshio.check_manifold(faces, len(points))
        if not ok:
            raise BenchError(f"{off}: {why}")
        meshio.write_ply(ply, points, faces)
    return ply


def make_cases(runner, work, quick):
    """[{name, group, noisy, clean, dir, closed}] in table order."""
    cases = []

    def add(name, group, noisy, clean, note):
        d = work / "cases" / re.sub(r"[^A-Za-z0-9.]+", "_", name)
        d.mkdir(parents=True, exist_ok=True)
        info = json.loads(runner.tool("mesh_compare", "--volume", clean))
        cases.append({"name": name, "group": group, "noisy": noisy, "clean": clean, "dir": d,
                      "closed": info["closed"], "vertices": info["vertices"],
                      "faces": info["faces"], "note": note})

    bench = SHARED / "data" / "benchmark"
    for name in ["Fandisk0.3", "Block0.4", "SharpSphere0.3", "Twelve0.5Impulsive", "Bunny0.2"]:
        add(name, "literature", bench / name / "noisy.ply", bench / name / "clean.ply",
            "Zhang et al. 2015 release")
    paper = SHARED / "data" / "paper"
    made = work / "made"
    made.mkdir(parents=True, exist_ok=True)
    fandisk = made / "paper_fandisk_n0.3.ply"
    runner.tool("add_noise", paper / "fandisk.ply", fandisk, 0.3, "normal", NOISE_SEED)
    add("paper fandisk n0.3", "paper", fandisk, paper / "fandisk.ply",
        "paper's fandisk, noise 0.3 x mean edge along normals")
    cow = made / "paper_cow_n0.2.ply"
    runner.tool("add_noise", paper / "cow.ply", cow, 0.2, "normal", NOISE_SEED)
    add("paper cow n0.2", "paper", cow, paper / "cow.ply",
        "paper's cow, noise 0.2 x mean edge along normals")
    add("paper mountain n0.2", "paper", paper / "mountain_noisy0.2.ply",
        paper / "mountain_clean.ply", "50x50 height field, open")
    if quick:
        return cases
    src = cgal_meshes(work)
    for mesh in CGAL_CASES:
        clean = off_to_ply(src / f"{mesh}.off", made / f"{mesh}_clean.ply")
        for direction, letter in (("normal", "n"), ("random", "r")):
            for k in CGAL_NOISE:
                noisy = made / f"{mesh}_{letter}{k}.ply"
                runner.tool("add_noise", clean, noisy, k, direction, NOISE_SEED)
                add(f"{mesh} {letter}{k}", "cgal", noisy, clean,
                    f"libcgal-demo {mesh}, noise {k} x mean edge "
                    f"{'along normals' if direction == 'normal' else 'in random directions'}")
    return cases


def noisy_subdivided(runner, src, made, name, levels):
    """libcgal-demo's `name` subdivided `levels` times at edge midpoints, with normal noise 0.2 x
    mean edge; made once into `made`."""
    noisy = made / f"{name}_x{levels}_n0.2.ply"
    if not noisy.exists():
        points, faces = meshio.read_off(src / f"{name}.off")
        for _ in range(levels):
            points, faces = meshio.midpoint_subdivide(points, faces)
        base = made / f"{name}_x{levels}.ply"
        meshio.write_ply(base, points, faces)
        runner.tool("add_noise", base, noisy, 0.2, "normal", NOISE_SEED)
        base.unlink()
    return noisy


def make_timing_meshes(runner, work, quick):
    src = cgal_meshes(work)
    made = work / "timing"
    made.mkdir(parents=True, exist_ok=True)
    meshes = []
    for label, name, levels in TIMING_MESHES[:1] if quick else TIMING_MESHES:
        noisy = noisy_subdivided(runner, src, made, name, levels)
        info = json.loads(runner.tool("mesh_compare", "--volume", noisy))
        meshes.append({"label": label, "name": f"{name}" + (f" (midpoint x{levels})" if levels
                                                            else ""),
                       "path": noisy, "vertices": info["vertices"], "faces": info["faces"]})
    return meshes


# --------------------------------------------------------------------------------------------
# Runs

def sd_sweep(quick):
    return [{}] if quick else sd_filter.SWEEP


def quality_tasks(cases, quick):
    tasks = []
    for i, case in enumerate(cases):
        tasks += [(case, "ours", o) for o in OURS.values()]
        for peer in PEERS:
            tasks.append((case, peer, PEER_DEFAULT[peer]))
            tasks += [(case, peer, s) for s in PEER_SWEEP[peer]]
        tasks += [(case, SD, s) for s in [{}] + sd_sweep(quick)]
        if case["group"] == "cgal":
            continue
        tasks.append((case, "ours meshlabserver", ["placement=0"]))
        if quick and i > 0:
            continue  # quick mode: the theta-vs-iterations curves of the first case only
        tasks += [(case, "ours", ["placement=0", f"iterations={n}"])
                  for n in OURS_ITERATIONS]
        tasks += [(case, "Taubin", {"steps": n}) for n in TAUBIN_ITERATIONS]
        tasks += [(case, "Laplacian", {"steps": n}) for n in LAPLACIAN_ITERATIONS]
    return tasks


def best_of(runner, case, method, sweep, text):
    """(scores of the sweep setting with the lowest theta, with its `setting` text; every
    setting's scores by text): a peer's oracle best on one case."""
    best, best_setting, scores = None, None, {}
    for s in sweep:
        sc = runner.quality(case, method, s)
        scores[text(s)] = sc
        if finite(sc.get("theta_deg")) and (best is None or sc["theta_deg"] < best["theta_deg"]):
            best, best_setting = sc, s
    return dict(best or {"error": "all failed"},
                setting=text(best_setting) if best_setting is not None else "-"), scores


def run_quality(runner, cases, quick):
    results = {}
    for case in cases:
        r = {"noisy": runner.compare(case["noisy"], case["clean"])}
        for label, overrides in OURS.items():
            r[label] = runner.quality(case, "ours", overrides)
        if case["group"] != "cgal":
            r["ours via meshlabserver"] = runner.quality(case, "ours meshlabserver", ["placement=0"])
        for peer in PEERS:
            r[peer + " default"] = runner.quality(case, peer, PEER_DEFAULT[peer])
            r[peer + " best"], r[peer + " sweep"] = best_of(
                runner, case, peer, PEER_SWEEP[peer], lambda s, p=peer: peer_setting_text(p, s))
        r[SD + " default"] = runner.quality(case, SD, {})
        r[SD + " best"], r[SD + " sweep"] = best_of(runner, case, SD, sd_sweep(quick),
                                                    sd_filter.setting_text)
        results[case["name"]] = r
    return results


def run_iterations(runner, cases, quality, quick):
    """theta vs iterations for ours ring barycentre, Taubin and Laplacian on the literature + paper cases
    (quick mode: the first case only)."""
    curves = {}
    for case in cases[:1] if quick else cases:
        if case["group"] == "cgal":
            continue
        c = {}
        noisy = quality[case["name"]]["noisy"]["theta_deg"]
        c["ours ring barycentre"] = [(0, noisy)] + [
            (n, runner.quality(case, "ours", ["placement=0", f"iterations={n}"]).get("theta_deg"))
            for n in OURS_ITERATIONS]
        c["Taubin"] = [(0, noisy)] + [
            (n, runner.quality(case, "Taubin", {"steps": n}).get("theta_deg"))
            for n in TAUBIN_ITERATIONS]
        c["Laplacian"] = [(0, noisy)] + [
            (n, runner.quality(case, "Laplacian", {"steps": n}).get("theta_deg"))
            for n in LAPLACIAN_ITERATIONS]
        curves[case["name"]] = c
    return curves


def run_agreement(runner, cases, quality):
    """Our filter in-process vs inside meshlabserver (float build): same scores, same vertices."""
    rows = []
    for case in cases:
        r = quality[case["name"]]
        a, b = r.get("ours ring barycentre", {}), r.get("ours via meshlabserver", {})
        if "path" not in a or "path" not in b:
            continue
        pa, _, _ = meshio.read_mesh(a["path"])
        pb, _, _ = meshio.read_mesh(b["path"])
        diag = np.linalg.norm(pa.max(0) - pa.min(0))
        rows.append({"case": case["name"], "theta_in": a["theta_deg"], "theta_ml": b["theta_deg"],
                     "ev_in": a["ev_1e3"], "ev_ml": b["ev_1e3"],
                     "max_diff": float(np.abs(pa - pb).max() / diag)})
    return rows


SLOW_RUN_SECONDS = 120  # a method whose first run takes longer is not repeated


def peer_applications(vertices):
    """How often a MeshLab filter is applied in one timed script: on small meshes one application
    takes less than the noise of meshlabserver's start-up, so the script repeats it and the time
    is divided by the count."""
    return int(min(10, max(1, round(50_000 / vertices))))


def run_timing(runner, meshes, runs):
    """Interleaved: every method once per round, `runs` rounds, medians. A method slower than
    SLOW_RUN_SECONDS in round 1 is run once only (the table says how many runs)."""
    # "ours": the ring barycentre (the smoothing issue's default, the time reference of issue 8);
    # the automatic mode (the default now) on one thread beside it.
    methods = [("ours in-process", None), ("ours in-process, 1 thread", None),
               ("ours automatic in-process, 1 thread", None),
               ("ours in meshlabserver", None), ("load+save only", None)]
    methods += [(f"{p} {peer_setting_text(p, PEER_TIMING[p])}", p) for p in PEERS]
    table = {}
    for mesh in meshes:
        log(f"timing: {mesh['label']} {mesh['name']} ({mesh['vertices']} vertices), {runs} runs")
        mesh_methods = methods + ([(SD_TIMING_LABEL, SD)] if sd_filter.available() and
                                  mesh["vertices"] <= SD_TIMING_MAX_VERTICES else [])
        samples = {m: [] for m, _ in mesh_methods}
        out = runner.work / "timing" / "out.ply"
        times = peer_applications(mesh["vertices"])
        for rnd in range(runs):
            for label, peer in mesh_methods:
                if rnd > 0 and samples[label][0]["wall"] > SLOW_RUN_SECONDS:
                    continue
                if label == "ours in-process":
                    r = runner.smooth_inprocess(mesh["path"], out, ["placement=0"], timed=True)
                elif label == "ours in-process, 1 thread":
                    r = runner.smooth_inprocess(mesh["path"], out, ["placement=0"], timed=True,
                                                threads=1)
                elif label == "ours automatic in-process, 1 thread":
                    r = runner.smooth_inprocess(mesh["path"], out, [], timed=True, threads=1)
                elif label == "ours in meshlabserver":
                    r = runner.meshlab(mesh["path"], out, runner.ours_mlx(["placement=0"]),
                                       timed=True)
                    r["stages"] = parse_stages(r["log"])
                elif label == "load+save only":
                    r = runner.meshlab(mesh["path"], out, None, timed=True)
                elif peer == SD:
                    r = sd_filter.run(mesh["path"], out, {}, options_dir=runner.mlx_dir,
                                      timed=True)
                else:
                    r = runner.meshlab(mesh["path"], out,
                                       runner.peer_mlx_path(peer, PEER_TIMING[peer], times),
                                       timed=True)
                samples[label].append(r)
                log(f"  round {rnd + 1} {label}: {r['wall']:.2f} s, {r['rss'] or 0:.0f} MB")
        med = {}
        base = statistics.median(s["wall"] for s in samples["load+save only"])
        for label, peer in mesh_methods:
            s = samples[label]
            m = {"wall": statistics.median(x["wall"] for x in s),
                 "rss": statistics.median(x["rss"] for x in s if x["rss"] is not None),
                 "walls": [x["wall"] for x in s], "runs": len(s)}
            if peer == SD:  # the denoising time it logs (its load and save are its own)
                m["filter"] = statistics.median(x["filter"] for x in s)
            elif "in-process" in label:
                m["filter"] = statistics.median(x["filter"] for x in s)
            elif label != "load+save only":
                applications = 1 if label.startswith("ours") else times
                m["applications"] = applications
                # below the run-to-run noise of start-up + load + save: no figure
                m["filter"] = (m["wall"] - base) / applications if m["wall"] - base > 0.05 \
                    else None
            stages = [x["stages"] for x in s if x.get("stages")]
            if stages:
                m["stages"] = {k: statistics.median(st[k] for st in stages) for k in stages[0]}
            med[label] = m
        table[mesh["label"]] = {"mesh": mesh, "methods": med, "base": base,
                                "peer_applications": times}
    return table


# --------------------------------------------------------------------------------------------
# Report

def finite(x):
    return isinstance(x, (int, float)) and math.isfinite(x)


def fmt(x, digits=2):
    return f"{x:.{digits}f}" if finite(x) else "–"


def machine_info():
    cpu = "unknown"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    version = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "meshlab"],
                             capture_output=True, text=True).stdout.strip() or "unknown"
    mem = ""
    try:
        kb = int(re.search(r"MemTotal:\s+(\d+)", open("/proc/meminfo").read()).group(1))
        mem = f"{kb / 1024 / 1024:.0f} GB"
    except (OSError, AttributeError):
        pass
    commit = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    # rstrip, not strip: a line reads " M path", and the paths start at its fourth character.
    dirty = subprocess.run(["git", "-C", str(REPO), "status", "--porcelain", "--untracked-files=no",
                            "--", "vcg_ext", "filter_saliency_bezier_smooth", "tools"],
                           capture_output=True, text=True).stdout.rstrip()
    if commit and dirty:
        commit += " + uncommitted changes to " + ", ".join(
            sorted({l[3:].split("/")[0] for l in dirty.splitlines()}))
    return {"nproc": os.cpu_count(), "cpu": cpu, "meshlab": version, "memory": mem,
            "date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
            "kernel": platform.release(), "commit": commit or "unknown",
            "load": f"{os.getloadavg()[0]:.2f}"}


SUMMARY_COLUMNS = (["noisy", "ours automatic (default)", "ours ring barycentre",
                    "ours feature-preserving", "ours organic"] +
                   [f"{p} {w}" for p in PEERS + [SD] for w in ("default", "best")])


def summary_table(cases, quality, key, digits, title_note=""):
    head = "| case | " + " | ".join(SUMMARY_COLUMNS) + " |"
    lines = [head, "|" + "---|" * (len(SUMMARY_COLUMNS) + 1)]
    for case in cases:
        r = quality[case["name"]]
        cells = []
        best_peer = min((r[f"{p} {w}"].get(key) for p in PEERS + [SD]
                         for w in ("default", "best") if finite(r[f"{p} {w}"].get(key))),
                        default=None)
        for col in SUMMARY_COLUMNS:
            v = r[col].get(key)
            text = fmt(v, digits)
            if col.startswith("ours") and finite(v) and finite(best_peer) and v <= best_peer:
                text = f"**{text}**"
            cells.append(text)
        lines.append(f"| {case['name']} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def best_meshlab(r, key="theta_deg"):
    """(label, scores) of the MeshLab filter and setting with the lowest `key` on a case."""
    best = None
    for p in PEERS:
        for w in ("default", "best"):
            sc = r[f"{p} {w}"]
            if finite(sc.get(key)) and (best is None or sc[key] < best[1][key]):
                setting = sc.get("setting") if w == "best" else \
                    peer_setting_text(p, PEER_DEFAULT[p])
                best = (f"{p} {setting}", sc)
    return best or ("–", {})


def best_sd(r, key="theta_deg"):
    """(label, scores) of the SD filter's default or best sweep setting, whichever has the lower
    `key` on a case."""
    options = [(f"{SD} defaults", r.get(f"{SD} default", {})),
               (f"{SD} {r.get(f'{SD} best', {}).get('setting', '-')}", r.get(f"{SD} best", {}))]
    options = [o for o in options if finite(o[1].get(key))]
    return min(options, key=lambda o: o[1][key]) if options else ("–", {})


# shared/data/README.md: guided normal filtering (Zhang et al. 2015, authors' code, default
# parameters) and bilateral normal filtering (Zheng et al. 2011): theta / Ev x 1e-3.
GNF = {"Fandisk0.3": (2.93, 0.93), "Block0.4": (4.09, 1.30), "SharpSphere0.3": (8.17, 1.46),
       "Twelve0.5Impulsive": (3.84, 1.39)}
BILATERAL = {"Fandisk0.3": (3.49, 1.02), "Block0.4": (7.06, 1.58), "SharpSphere0.3": (8.29, 1.29),
             "Twelve0.5Impulsive": (6.92, 1.90)}


def normal_filtering_section(cases, quality):
    """The automatic mode (the default) against the published normal-filtering figures (issue 8)."""
    L = ["| case | noisy θ / Ev | ours automatic (default) θ / Ev | θ sharp noisy → ours | "
         "guided normal filtering | bilateral normal filtering | best MeshLab θ / Ev | "
         "SD filter best θ / Ev | beats guided on θ and Ev |", "|---|---|---|---|---|---|---|---|---|"]
    wins = rows = 0
    for case in cases:
        if case["name"] not in GNF:
            continue
        r = quality[case["name"]]
        ours, noisy = r["ours automatic (default)"], r["noisy"]
        g, b = GNF[case["name"]], BILATERAL[case["name"]]
        _, peer = best_meshlab(r)
        _, sd = best_sd(r)
        win = finite(ours.get("theta_deg")) and ours["theta_deg"] < g[0] and \
            ours["ev_1e3"] < g[1]
        wins += win
        rows += 1
        L.append(f"| {case['name']} | {fmt(noisy.get('theta_deg'))} / {fmt(noisy.get('ev_1e3'))} "
                 f"| {fmt(ours.get('theta_deg'))} / {fmt(ours.get('ev_1e3'))} | "
                 f"{fmt(noisy.get('theta_sharp_deg'))} → {fmt(ours.get('theta_sharp_deg'))} | "
                 f"{g[0]:.2f} / {g[1]:.2f} | {b[0]:.2f} / {b[1]:.2f} | "
                 f"{fmt(peer.get('theta_deg'))} / {fmt(peer.get('ev_1e3'))} | "
                 f"{fmt(sd.get('theta_deg'))} / {fmt(sd.get('ev_1e3'))} | "
                 f"{'yes' if win else 'no'} |")
    L.append("")
    L.append(f"The automatic mode (which runs the feature-preserving mode on these four) beats "
             f"guided normal filtering on both θ and Ev on {wins} of {rows} cases.")
    return "\n".join(L)


def whole_process(t, method):
    """A method's whole meshlabserver run on the mesh: load+save plus one application."""
    m = t["methods"][method]
    return t["base"] + (m.get("filter") or 0.0)


def targets_section(timing):
    """Issue 7's targets, read off the timing run."""
    L = ["| mesh | vertices | ours, whole meshlabserver run (s) | Taubin x10 (s) | ours ÷ Taubin "
         f"(target ≤ {TARGET_TAUBIN_RATIO:g}) | TwoStep x3 (s) | ours ÷ TwoStep (target ≤ "
         f"{TARGET_TWOSTEP_RATIO:g}) | peak RSS ours / load+save (MB) | ratio (target ≤ "
         f"{TARGET_RSS_RATIO:g}) | Taubin x10's own RSS ratio | vertex-iterations/s: iterations "
         "only (fit + placement stage) / whole filter (3 iterations + topology + final "
         "analysis), in-process |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
    for label, t in timing.items():
        m = t["methods"]
        taubin = next(k for k in m if k.startswith("Taubin"))
        twostep = next(k for k in m if k.startswith("TwoStep"))
        ours, ta, ts = (whole_process(t, k) for k in ("ours in meshlabserver", taubin, twostep))
        rss, rss0 = m["ours in meshlabserver"]["rss"], m["load+save only"]["rss"]
        inproc = m["ours in-process"].get("filter")
        vips = 3 * t["mesh"]["vertices"] / inproc if inproc else None
        fit = (m["ours in-process"].get("stages") or {}).get("fit+placement")
        iteration_vips = 3 * t["mesh"]["vertices"] / fit if fit else None
        taubin_rss = m[taubin]["rss"]
        rss_text = f"{fmt(rss, 0)} / {fmt(rss0, 0)}" if rss and rss0 else "–"
        rss_ratio = f"{rss / rss0:.2f}" if rss and rss0 else "–"
        L.append(f"| {label} {t['mesh']['name']} | {t['mesh']['vertices']:,} | {ours:.2f} | "
                 f"{ta:.2f} | {ours / ta:.2f} | {ts:.2f} | {ours / ts:.3f} | {rss_text} | "
                 f"{rss_ratio} | {taubin_rss / rss0:.2f} | "
                 f"{f'{iteration_vips:,.0f}' if iteration_vips else '–'} / "
                 f"{f'{vips:,.0f}' if vips else '–'} |" if taubin_rss and rss0 else
                 f"{rss_ratio} | – | – / {f'{vips:,.0f}' if vips else '–'} |")
    armadillo = sorted((t["mesh"]["vertices"], t["methods"][k].get("filter"), k)
                       for t in timing.values() if t["mesh"]["name"].startswith("armadillo")
                       for k in ("ours in-process", "ours in-process, 1 thread"))
    L.append("")
    for k in ("ours in-process", "ours in-process, 1 thread"):
        pts = [(n, f) for n, f, kk in armadillo if kk == k and f]
        if len(pts) > 1:
            (n0, f0), (n1, f1) = pts[0], pts[-1]
            L.append(f"- Growth, {k} on the armadillo: time ∝ n^{math.log(f1 / f0) / math.log(n1 / n0):.2f} "
                     f"from {n0:,} to {n1:,} vertices ({f0:.2f} s → {f1:.2f} s).")
    over = [label for label, t in timing.items()
            if (t["methods"]["ours in meshlabserver"]["rss"] or 0) >
            TARGET_RSS_RATIO * (t["methods"]["load+save only"]["rss"] or math.inf)]
    if over:
        L.append(f"- Peak memory is above its target at {', '.join(over)}: our core works on a flat "
                 "double copy of the mesh with CSR 1- and 2-rings and Jacobi position buffers, "
                 "which on large meshes alone exceed 0.5 × a load+save run (compare MeshLab's own Taubin "
                 "in the column before last). The per-array budget, the profile of every "
                 "stage and what would close each gap are in [docs/studies/performance.md](../docs/studies/performance.md).")
    return "\n".join(L)


def summary_section(cases, quality, timing):
    modes = ("ours automatic (default)", "ours ring barycentre", "ours feature-preserving",
             "ours organic")
    L = ["| case | noisy θ / Ev | ours automatic (default) θ / Ev | ours ring barycentre θ / Ev | "
         "ours feature-preserving θ / Ev | ours organic θ / Ev | best MeshLab (by θ) | its θ / Ev "
         "| best MeshLab Ev | SD filter best (by θ) | its θ / Ev |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
    wins = {m: [0, 0] for m in modes}  # theta, Ev
    sd_wins = {m: [0, 0] for m in modes}
    for case in cases:
        r = quality[case["name"]]
        label, peer = best_meshlab(r)
        _, peer_ev = best_meshlab(r, "ev_1e3")
        sd_label, sd = best_sd(r)
        _, sd_ev = best_sd(r, "ev_1e3")
        cells = []
        for mode in modes:
            ours = r[mode]
            for counts, by_theta, by_ev in ((wins, peer, peer_ev), (sd_wins, sd, sd_ev)):
                counts[mode][0] += finite(ours.get("theta_deg")) and \
                    ours["theta_deg"] <= by_theta.get("theta_deg", math.inf)
                counts[mode][1] += finite(ours.get("ev_1e3")) and \
                    ours["ev_1e3"] <= by_ev.get("ev_1e3", math.inf)
            cells.append(f"{fmt(ours.get('theta_deg'))} / {fmt(ours.get('ev_1e3'))}")
        L.append(f"| {case['name']} | {fmt(r['noisy'].get('theta_deg'))} / "
                 f"{fmt(r['noisy'].get('ev_1e3'))} | {' | '.join(cells)} | {label} | "
                 f"{fmt(peer.get('theta_deg'))} / {fmt(peer.get('ev_1e3'))} | "
                 f"{fmt(peer_ev.get('ev_1e3'))} | {sd_label.replace(SD + ' ', '')} | "
                 f"{fmt(sd.get('theta_deg'))} / {fmt(sd.get('ev_1e3'))} |")
    L.append("")
    for mode in modes:
        L.append(f"- {mode}: θ at least as low as every MeshLab filter (at its default and at its "
                 f"per-case best sweep setting) on {wins[mode][0]} of {len(cases)} cases, Ev on "
                 f"{wins[mode][1]} of {len(cases)}; as low as the SD filter's (default or best "
                 f"of its sweep) θ on {sd_wins[mode][0]}, Ev on {sd_wins[mode][1]}.")
    if timing:
        L.append("")
        parts = []
        for label, t in timing.items():
            m = t["methods"]
            ours = m["ours in meshlabserver"]["filter"]
            ours1 = m["ours in-process, 1 thread"]["filter"]
            peers = ", ".join(f"{name} {fmt(m[name]['filter'], 3)} s" for name in m
                              if not name.startswith("ours") and name != "load+save only")
            parts.append(f"- {label} ({t['mesh']['vertices']:,} vertices): ours "
                         f"{fmt(ours)} s inside meshlabserver, {fmt(ours1)} s in-process on one "
                         f"thread; MeshLab {peers}")
        L.append("Filter times (medians; details under Speed):\n")
        L.extend(parts)
    return "\n".join(L)


def detail_table(case, r):
    lines = ["| method | setting | θ (°) | θ sharp (°) | Ev ×1e-3 | volume ratio | "
             "boundary turning (°) | boundary drift (edges) | flipped faces |",
             "|---|---|---|---|---|---|---|---|---|"]
    rows = [("noisy input", "", r["noisy"])]
    rows += [(label, "", r[label]) for label in OURS]
    if "ours via meshlabserver" in r:
        rows.append(("ours ring barycentre via meshlabserver", "", r["ours via meshlabserver"]))
    for p in PEERS:
        rows.append((p, "default " + peer_setting_text(p, PEER_DEFAULT[p]), r[p + " default"]))
        rows.append((p, "best: " + r[p + " best"].get("setting", "-"), r[p + " best"]))
    rows.append((SD, "defaults", r[SD + " default"]))
    rows.append((SD, "best: " + r[SD + " best"].get("setting", "-"), r[SD + " best"]))
    for name, setting, s in rows:
        if "error" in s:
            lines.append(f"| {name} | {setting} | failed: {s['error'][:80].splitlines()[0]} "
                         "| | | | | | |")
            continue
        turning = (f"{fmt(s.get('boundary_turning_deg_result'))} "
                   f"(clean {fmt(s.get('boundary_turning_deg_reference'))})"
                   if finite(s.get("boundary_turning_deg_result")) else "–")
        lines.append(f"| {name} | {setting} | {fmt(s.get('theta_deg'))} | "
                     f"{fmt(s.get('theta_sharp_deg'))} | {fmt(s.get('ev_1e3'))} | "
                     f"{fmt(s.get('volume_ratio'), 4)} | {turning} | "
                     f"{fmt(s.get('boundary_drift_edges'), 3)} | {s.get('flipped_faces', '–')} |")
    return "\n".join(lines)


def timing_tables(timing):
    out = []
    lines = ["| size | mesh | vertices | method | wall (s) | filter (s) | vertices/s | "
             "peak RSS (MB) | filter ÷ ours in meshlabserver | filter ÷ ours 1 thread | runs |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for label, t in timing.items():
        ours_ml = t["methods"]["ours in meshlabserver"]["filter"]
        ours_1 = t["methods"]["ours in-process, 1 thread"]["filter"]
        for method, m in t["methods"].items():
            f = m.get("filter")
            vps = t["mesh"]["vertices"] / f if f else None
            r1 = f"{f / ours_ml:.3f}" if f and ours_ml else "–"
            r2 = f"{f / ours_1:.3f}" if f and ours_1 else "–"
            if m.get("applications", 1) > 1:
                method = f"{method} (applied {m['applications']}× per script)"
            lines.append(f"| {label} | {t['mesh']['name']} | {t['mesh']['vertices']} | {method} | "
                         f"{m['wall']:.3f} | {fmt(f, 3) if f else '–'} | "
                         f"{f'{vps:,.0f}' if vps else '–'} | {fmt(m['rss'], 0)} | {r1} | {r2} | "
                         f"{m.get('runs', '–')} |")
    out.append("\n".join(lines))
    lines = ["| size | vertices | run | topology (s) | curvature (s) | saliency (s) | "
             "patch fit + placement (s) | sum of stages (s) |",
             "|---|---|---|---|---|---|---|---|"]
    for label, t in timing.items():
        for method, run in (("ours in-process", f"in-process, {os.cpu_count()} threads"),
                            ("ours in-process, 1 thread", "in-process, 1 thread"),
                            ("ours in meshlabserver", f"meshlabserver, {os.cpu_count()} threads")):
            st = t["methods"][method].get("stages")
            if not st:
                continue
            lines.append(f"| {label} | {t['mesh']['vertices']} | {run} | {st['topology']:.3f} | "
                         f"{st['curvature']:.3f} | {st['saliency']:.3f} | "
                         f"{st['fit+placement']:.3f} | {sum(st.values()):.3f} |")
    out.append("\n".join(lines))
    return out


def write_results(path, img_rel, args, machine, cases, quality, agreement, timing, pictures,
                  runs, elapsed):
    lit = [c for c in cases if c["group"] != "cgal"]
    cg = [c for c in cases if c["group"] == "cgal"]
    cmd = "bash bench/run.sh" + (" --quick" if args.quick else "") + \
          (f" --out {args.out}" if args.out else "") + (f" --runs {args.runs}" if args.runs else "")
    L = []
    L.append("# Benchmark: Saliency Bezier Smooth vs MeshLab's smoothing filters\n")
    L.append(f"Produced by `{cmd}` ({'quick mode' if args.quick else 'full run'}) "
             f"on {machine['date']}, commit {machine['commit']}, in {elapsed / 60:.1f} min. "
             "Do not edit by hand: rerun the command.\n")
    L.append(f"Machine: {machine['nproc']} CPUs ({machine['cpu']}), {machine['memory']} RAM, "
             f"Linux {machine['kernel']}; MeshLab {machine['meshlab']} (Debian, float build) "
             "through its meshlabserver. Load average (1 min) when the run started "
             f"{machine.get('load', '?')}, after the timing runs {machine.get('load_after_timing', '?')}: "
             "other jobs on the machine make absolute times noisy; "
             f"all methods were timed in the same run, interleaved, "
             f"median of {runs} run(s) (a method whose first run took over {SLOW_RUN_SECONDS} s "
             "ran once), so the ratios are the figures to read.\n")
    L.append("## Summary\n")
    L.append(summary_section(lit + cg, quality, timing) + "\n")
    if any(c["name"] in GNF for c in lit):
        L.append("## Automatic (default) mode vs published normal filtering\n")
        L.append(normal_filtering_section(lit, quality) + "\n")
    if timing and not args.quick:
        L.append("## Speed targets\n")
        L.append("Whole meshlabserver runs (load, filter, save; for MeshLab's filters applied "
                 "several times per script on small meshes: load+save plus one application), "
                 "medians of the same interleaved run as the Speed section below.\n")
        L.append(targets_section(timing) + "\n")
    L.append("## How it is measured\n")
    L.append("- Each case is a clean/noisy pair with the same connectivity; each method smooths "
             "the "
             "noisy mesh and `tools/mesh_compare` scores the result against the clean mesh: "
             "**θ** mean angle between result and clean face normals (degrees); **θ sharp** the "
             "same on faces next to a clean dihedral > 30°; **Ev** area-weighted RMS distance of "
             "the result's vertices to the clean surface / bbox diagonal (×1e-3, Sun et al. "
             "2007); **volume ratio** result/clean (closed meshes); **boundary turning** mean "
             "turning angle along open boundaries (clean value in brackets) and **boundary drift** "
             "mean inward move of boundary vertices in mean edge lengths (open meshes); "
             "**flipped faces** faces whose normal is more than 90° from the clean one.")
    L.append("- Ours: `tools/smooth_mesh` (the plugin's core, in-process, double precision) at the "
             "filter's default (the automatic mode, `placement=5`: the feature-preserving or the "
             "organic mode, chosen from the mesh), in its ring-barycentre placement (`placement=0`, "
             "3 iterations: the paper's patch, the first default), its feature-preserving "
             "mode (`placement=3`, face patches on guided-filtered normals) and its organic mode "
             "(`placement=4`, Taubin band shrinkage); variants: patch point "
             "placement, the paper's Newton placement with the step safeguard (1 mean edge) and "
             "as printed (`newton_step_limit=0`). Ours through the real meshlabserver (float "
             "build) is checked against in-process below.")
    L.append("- MeshLab 2020.09 filters through meshlabserver, every parameter in the .mlx: "
             "Laplacian Smooth (cotangent weights, 1D boundary smoothing; default 3 steps; sweep "
             "1, 3, 5, 10), HC Laplacian Smooth (no parameters, one step per application; sweep "
             "1, 2, 3, 5, 10 applications), Taubin Smooth (λ 0.5, μ −0.53; default 10 steps; "
             "sweep 5, 10, 20, 40, 80), TwoStep Smooth (20 normal and 20 fit steps; default 3 "
             "steps at 60°; sweep 1/3/6 steps × 45/60/75°). **best** = the sweep setting with "
             "the "
             "lowest θ on that case (an oracle choice per case: the strongest fair baseline).")
    sweep = "the defaults only (quick mode)" if args.quick else "; ".join(
        sd_filter.setting_text(s) for s in sd_filter.SWEEP)
    L.append("- The SD filter (Zhang, Deng et al., *Static/Dynamic Filtering for Mesh Geometry*, "
             "TVCG 2019; Debian's `meshsdfilter-tools`, `MeshDenoiser OPTIONS IN OUT`, OpenMP on "
             "every core, one thread in the parallel quality runs) at the defaults of its "
             f"`DenoisingOptions.txt` ({sd_filter.defaults_text()}) and at the best (lowest θ) "
             f"of the sweep {sweep} (bench/sd_filter.py).")
    L.append(f"- Noise made here: Gaussian, std k × mean edge length, along vertex normals (n) or "
             f"in random 3-D directions (r), seed {NOISE_SEED} (`tools/add_noise`).\n")

    L.append("## θ (degrees, lower is better) — literature and paper cases\n")
    L.append("Bold: our mode is at least as good as every MeshLab and SD filter setting "
             "tried.\n")
    L.append(summary_table(lit, quality, "theta_deg", 2) + "\n")
    L.append("## Ev (×1e-3, lower is better) — literature and paper cases\n")
    L.append(summary_table(lit, quality, "ev_1e3", 3) + "\n")
    L.append("## θ sharp (degrees, faces next to dihedral > 30°) — literature and paper "
             "cases\n")
    L.append(summary_table(lit, quality, "theta_sharp_deg", 2) + "\n")
    L.append("## Flipped faces — literature and paper cases\n")
    L.append(summary_table(lit, quality, "flipped_faces", 0) + "\n")
    if cg:
        L.append("## θ (degrees) — libcgal-demo meshes with added noise\n")
        L.append(summary_table(cg, quality, "theta_deg", 2) + "\n")
        L.append("## Ev (×1e-3) — libcgal-demo meshes with added noise\n")
        L.append(summary_table(cg, quality, "ev_1e3", 3) + "\n")
        L.append("## Flipped faces — libcgal-demo meshes with added noise\n")
        L.append(summary_table(cg, quality, "flipped_faces", 0) + "\n")
    if agreement:
        L.append("## Ours in-process vs inside meshlabserver\n")
        L.append("| case | θ in-process | θ meshlabserver | Ev in-process | Ev meshlabserver | "
                 "max vertex difference / bbox diagonal |\n|---|---|---|---|---|---|")
        for a in agreement:
            L.append(f"| {a['case']} | {a['theta_in']:.3f} | {a['theta_ml']:.3f} | "
                     f"{a['ev_in']:.4f} | {a['ev_ml']:.4f} | {a['max_diff']:.1e} |")
        L.append("")
    L.append("## Speed\n")
    L.append("Noisy meshes (0.2 × mean edge along normals) from libcgal-demo, subdivided at edge "
             "midpoints to reach the larger sizes. *wall*: the whole process (load, filter, save); "
             "*filter*: ours in-process = the filter's own clock; inside meshlabserver = wall "
             "minus the median load+save-only run of the same mesh (on small meshes MeshLab's "
             "filters are applied several times in one script and this is divided by the count; "
             "– = within the start-up noise). MeshLab's filters are single-threaded; ours uses "
             "OpenMP on all cores (the 1-thread row is the "
             "like-for-like figure). The ratio columns divide a method's filter time by ours "
             "(> 1: slower than ours). Peak RSS from `/usr/bin/time -v` (whole process). "
             "The SD filter (`MeshDenoiser`, OpenMP on all cores): *wall* its whole process "
             "(OpenMesh load, denoising, ASCII save), *filter* the denoising time it logs; run "
             f"on meshes up to {SD_TIMING_MAX_VERTICES:,} vertices (beyond, one run takes "
             "many minutes).\n")
    t1, t2 = timing_tables(timing)
    L.append(t1 + "\n")
    L.append("Our filter's stages (its own log, medians):\n")
    L.append(t2 + "\n")
    if pictures:
        L.append("## Pictures\n")
        for title, name in pictures:
            L.append(f"**{title}**\n\n![{title}]({img_rel}/{name})\n")
    L.append("## Every case in detail\n")
    for case in cases:
        r = quality[case["name"]]
        L.append(f"### {case['name']}\n")
        L.append(f"{case['note']}; {case['vertices']} vertices, {case['faces']} faces, "
                 f"{'closed' if case['closed'] else 'open'}.\n")
        L.append(detail_table(case, r) + "\n")
    path.write_text("\n".join(L))


def validate(path, cases, timing):
    """The tables must exist with finite numbers for every case in the run (quick-mode check)."""
    text = path.read_text()
    problems = []
    theta_sections = [s for s in text.split("\n## ") if s.startswith("θ (degrees")]
    for case in cases:
        rows = [l for sec in theta_sections for l in sec.splitlines()
                if l.startswith(f"| {case['name']} |")]
        if len(rows) != 1:
            problems.append(f"{case['name']}: θ row missing")
            continue
        cells = [c.strip().strip("*") for c in rows[0].strip("|").split("|")[1:]]
        if len(cells) != len(SUMMARY_COLUMNS) or not all(finite_text(c) for c in cells):
            problems.append(f"{case['name']}: θ row has missing numbers: {rows[0]}")
    for label in timing:
        if not any(l.startswith(f"| {label} |") for l in text.splitlines()):
            problems.append(f"timing row {label} missing")
    return problems


def write_between_markers(path, begin, end, lines):
    """Replaces the text between the `begin` and `end` marker lines of a hand-written report with
    `lines` (appends the block, markers included, when the file has none)."""
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    block = begin + "\n" + "\n".join(lines) + "\n" + end
    text = path.read_text() if path.exists() else ""
    start, stop = text.find(begin), text.find(end)
    if start >= 0 and stop > start:
        text = text[:start] + block + text[stop + len(end):]
    else:
        text = text + ("\n" if text else "") + block + "\n"
    path.write_text(text)


def finite_text(s):
    try:
        return math.isfinite(float(s))
    except ValueError:
        return False


# --------------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true",
                    help="small public cases only, one run, ~10k timing size only")
    ap.add_argument("--out", help="write RESULTS.md and img/ here instead of bench/RESULTS.md "
                                  "and docs/img/ (default for --quick: bench/out/quick)")
    ap.add_argument("--runs", type=int, help="timing runs per method (default 3, quick 1)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="parallel quality runs (timing always runs alone); default: all cores")
    ap.add_argument("--report-only", action="store_true",
                    help="rewrite RESULTS.md and the pictures from the last run's raw.json")
    ap.add_argument("--build", default=os.environ.get("SBS_BUILD_DIR", str(REPO / "build")))
    args = ap.parse_args()
    started = time.time()
    runs = args.runs or (1 if args.quick else 3)
    if args.out:
        out = pathlib.Path(args.out).resolve()
        results_path, img_dir, img_rel = out / "RESULTS.md", out / "img", "img"
        work = out / "work"
    elif args.quick:
        out = REPO / "bench" / "out" / "quick"
        results_path, img_dir, img_rel = out / "RESULTS.md", out / "img", "img"
        work = out / "work"
    else:
        results_path, img_dir, img_rel = REPO / "bench" / "RESULTS.md", REPO / "docs" / "img", \
            "../docs/img"
        work = REPO / "bench" / "out" / "full"
    if (work / "cases").exists() and not args.report_only:
        shutil.rmtree(work / "cases")  # results of an older run must not be scored again
    for d in (work, img_dir, results_path.parent):
        d.mkdir(parents=True, exist_ok=True)

    runner = Runner(pathlib.Path(args.build).resolve(), work)
    raw_path = work / "raw.json"
    if args.report_only:  # tables and pictures again from the last run's raw.json
        raw = json.loads(raw_path.read_text())
        cases = make_cases(runner, work, args.quick)
        quality, curves, timing = raw["quality"], raw["curves"], raw["timing"]
        agreement, machine, elapsed = raw["agreement"], raw["machine"], raw["elapsed"]
        runs = raw.get("runs", runs)
        import figures
        pictures = figures.make_all(runner, cases, quality, curves, timing, img_dir, args.quick)
    else:
        signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # so that Xvfb is stopped
        runner.start_xvfb()
        try:
            machine = machine_info()
            cases = make_cases(runner, work, args.quick)
            timing_meshes = make_timing_meshes(runner, work, args.quick)
            timing = run_timing(runner, timing_meshes, runs)  # first: the machine is quietest
            machine["load_after_timing"] = f"{os.getloadavg()[0]:.2f}"
            runner.prefetch(quality_tasks(cases, args.quick), args.jobs)
            quality = run_quality(runner, cases, args.quick)
            curves = run_iterations(runner, cases, quality, args.quick)
            agreement = run_agreement(runner, cases, quality)
        finally:
            runner.stop_xvfb()
        elapsed = time.time() - started
        raw_path.write_text(json.dumps(
            {"quality": quality, "curves": curves, "timing": timing, "agreement": agreement,
             "machine": machine, "elapsed": elapsed, "runs": runs}, default=str, indent=1))
        import figures
        pictures = figures.make_all(runner, cases, quality, curves, timing, img_dir, args.quick)
    write_results(results_path, img_rel, args, machine, cases, quality, agreement, timing,
                  pictures, runs, elapsed)
    problems = validate(results_path, cases, timing)
    log(f"wrote {results_path} and {len(pictures)} pictures in {img_dir} "
        f"({(time.time() - started) / 60:.1f} min)")
    if problems:
        for p in problems:
            log("PROBLEM: " + p)
        sys.exit(1)


if __name__ == "__main__":
    main()
