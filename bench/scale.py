#!/usr/bin/env python3
"""Scale benchmark: whole meshlabserver runs of our filter at its defaults (the automatic mode),
MeshLab's Taubin x10 (lambda 0.5, mu -0.53) and a load+save-only run, from about 10k to 10M
vertices, side by side: wall time and peak memory (maximum resident set, /usr/bin/time), medians of
interleaved rounds, their ratios, and the automatic mode's choice on each mesh.

    python3 bench/scale.py [--build build] [--rounds 3] [--big-rounds 1] [--sizes 10k,100k,1M,2M,10M]

Installs what it needs and builds first (bench/prepare.sh; --no-prepare skips it).

The meshes are the benchmark's noisy Bunny0.2 (34,834 vertices), decimated where a size needs it
(MeshLab's Quadric Edge Collapse Decimation), taken through Loop subdivision steps in MeshLab (its
"Subdivision Surfaces: Loop") and given noise of 0.2 mean edge lengths in random directions
(tools/add_noise, seed 1); the 2M one is the scale issue's mesh (three Loop steps, no decimation).
They are made once and cached under bench/out/scale/meshes. Writes bench/out/scale/scale.json,
bench/SCALE.md and docs/img/scale.png. Meshes above 3M vertices get `--big-rounds` rounds.
"""
import argparse
import json
import pathlib
import re
import statistics
import subprocess
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import bench  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[1]
BUNNY = REPO.parent / "shared" / "data" / "benchmark" / "Bunny0.2" / "noisy.ply"
OUT = REPO / "bench" / "out" / "scale"
# label -> (faces to decimate the noisy bunny to, or None; Loop subdivision steps)
SIZES = {"10k": (5000, 1), "100k": (50000, 1), "1M": (31250, 3), "2M": (None, 3),
         "10M": (19600, 5)}
NOISE = 0.2
TARGET_RATIO = 2.0      # the default against Taubin x10, time and memory, up to 2.2M vertices
BIG_MEMORY_GB = 8.0     # a 10M-vertex mesh in one run
RUNS = ["load+save", "Taubin x10", "ours (automatic)"]


def param(name, kind, value, extra=""):
    return f'  <Param name="{name}" type="{kind}" value="{value}"{extra}/>\n'


def making_mlx(decimate_faces, loop_steps):
    """meshlabserver script: decimation (if any), then Loop subdivision. The decimation keeps the
    topology (Loop subdivision refuses a mesh with non-manifold edges)."""
    body = ""
    if decimate_faces:
        body += (' <filter name="Simplification: Quadric Edge Collapse Decimation">\n' +
                 param("TargetFaceNum", "RichInt", decimate_faces) +
                 param("TargetPerc", "RichFloat", 0) + param("QualityThr", "RichFloat", 0.3) +
                 param("PreserveBoundary", "RichBool", "true") +
                 param("BoundaryWeight", "RichFloat", 1) +
                 param("PreserveNormal", "RichBool", "true") +
                 param("PreserveTopology", "RichBool", "true") +
                 param("OptimalPlacement", "RichBool", "true") +
                 param("PlanarQuadric", "RichBool", "false") +
                 param("PlanarWeight", "RichFloat", 0.001) +
                 param("QualityWeight", "RichBool", "false") +
                 param("AutoClean", "RichBool", "true") + param("Selected", "RichBool", "false") +
                 " </filter>\n")
    body += (' <filter name="Subdivision Surfaces: Loop">\n' +
             param("LoopWeight", "RichEnum", 0) + param("Iterations", "RichInt", loop_steps) +
             param("Threshold", "RichAbsPerc", 0, ' min="0" max="1"') +
             param("Selected", "RichBool", "false") + " </filter>\n")
    return f"<!DOCTYPE FilterScript>\n<FilterScript>\n{body}</FilterScript>\n"


def make_mesh(runner, label):
    meshes = OUT / "meshes"
    meshes.mkdir(parents=True, exist_ok=True)
    noisy = meshes / f"bunny_{label}_n{NOISE}.ply"
    if noisy.exists():
        return noisy
    decimate, steps = SIZES[label]
    mlx = meshes / f"make_{label}.mlx"
    mlx.write_text(making_mlx(decimate, steps))
    subdivided = meshes / f"bunny_{label}_subdivided.ply"
    bench.log(f"making the {label} mesh (decimation {decimate}, {steps} Loop steps)")
    runner.meshlab(BUNNY, subdivided, mlx)
    runner.tool("add_noise", subdivided, noisy, NOISE, "random", 1)
    subdivided.unlink()
    return noisy


def vertex_count(path):
    with open(path, "rb") as f:
        header = f.read(4096).split(b"end_header")[0].decode("ascii", "replace")
    return int(re.search(r"element vertex (\d+)", header).group(1))


def automatic_choice(log):
    """The automatic mode's log line (meshlabserver echoes the filter's log as 'LOG: n <line>')."""
    for line in log.splitlines():
        m = re.match(r"^LOG: \d+ (Automatic .*)", line)
        if m:
            return m.group(1)
    return ""


def choice_summary(line):
    m = re.match(r"Automatic \((.*?)\) -> (Feature-preserving|Organic)", line)
    return (m.group(2), m.group(1)) if m else ("?", line[:120])


def run_size(runner, label, mesh, rounds, ours_mlx, taubin_mlx):
    out = OUT / "work" / f"out_{label}.ply"
    out.parent.mkdir(parents=True, exist_ok=True)
    samples = {r: [] for r in RUNS}
    choice = ""
    for rnd in range(rounds):
        for run in RUNS:
            mlx = {"load+save": None, "Taubin x10": taubin_mlx, "ours (automatic)": ours_mlx}[run]
            r = runner.meshlab(mesh, out, mlx, timed=True)
            if run == "ours (automatic)":
                choice = automatic_choice(r["log"]) or choice
            samples[run].append({"wall": r["wall"], "rss": r["rss"]})
            bench.log(f"{label} round {rnd + 1} {run}: {r['wall']:.2f} s, {r['rss']:.0f} MB")
    if out.exists():
        out.unlink()
    med = {run: {"wall": statistics.median(x["wall"] for x in s),
                 "rss_mb": statistics.median(x["rss"] for x in s),
                 "walls": [round(x["wall"], 3) for x in s],
                 "rss_all_mb": [round(x["rss"]) for x in s]} for run, s in samples.items()}
    return {"label": label, "vertices": vertex_count(mesh), "rounds": rounds, "runs": med,
            "automatic": choice}


def write_markdown(results, args, path):
    lines = ["# Scale: the default against MeshLab's Taubin x10, from 10k to 10M vertices", "",
             "Whole `meshlabserver` runs (binary PLY in and out) of our filter at its defaults (the "
             "automatic mode), MeshLab's Taubin Smooth x10 (lambda 0.5, mu -0.53) and a load+save-only "
             "run; the rounds interleave the three, each figure is the median over the rounds "
             "(wall time; peak memory = maximum resident set of the process, /usr/bin/time). "
             "Meshes: the benchmark's noisy Bunny0.2, decimated where the size needs it, Loop "
             "subdivision in MeshLab, then noise of 0.2 mean edge lengths in random directions "
             "(bench/scale.py). Machine: 2 cores, shared with other jobs while this ran (see the "
             "spread of the rounds in bench/out/scale/scale.json).", "",
             f"Command: `python3 bench/scale.py --rounds {args.rounds} --big-rounds {args.big_rounds}"
             f" --sizes {args.sizes}` ({time.strftime('%Y-%m-%d')}).", "",
             "| mesh | vertices | rounds | load+save s | Taubin x10 s | ours s | ours ÷ Taubin (time) "
             "| load+save MB | Taubin x10 MB | ours MB | ours ÷ Taubin (memory) |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in results:
        ls, tb, us = (r["runs"][k] for k in RUNS)
        lines.append(f"| {r['label']} | {r['vertices']:,} | {r['rounds']} | {ls['wall']:.2f} | "
                     f"{tb['wall']:.2f} | {us['wall']:.2f} | **{us['wall'] / tb['wall']:.2f}** | "
                     f"{ls['rss_mb']:.0f} | {tb['rss_mb']:.0f} | {us['rss_mb']:.0f} | "
                     f"**{us['rss_mb'] / tb['rss_mb']:.2f}** |")
    lines += ["", f"Targets: at most {TARGET_RATIO:g}x Taubin x10 in time and in memory up to 2.2M "
              f"vertices; the 10M mesh within {BIG_MEMORY_GB:g} GB in one run.", "",
              "## The automatic mode's choice", "",
              "| mesh | vertices | chose | evidence (log line) |", "|---|---:|---|---|"]
    for r in results:
        mode, why = choice_summary(r["automatic"])
        lines.append(f"| {r['label']} | {r['vertices']:,} | {mode} | {why} |")
    lines.append("")
    path.write_text("\n".join(lines))


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3.2))
    n = [r["vertices"] for r in results]
    for run, style in zip(RUNS, ["s:", "o--", "o-"]):
        a.loglog(n, [r["runs"][run]["wall"] for r in results], style, label=run)
        b.loglog(n, [r["runs"][run]["rss_mb"] / 1024 for r in results], style, label=run)
    a.loglog(n, [2 * r["runs"]["Taubin x10"]["wall"] for r in results], color="grey", lw=0.8,
             label="2x Taubin x10")
    b.loglog(n, [2 * r["runs"]["Taubin x10"]["rss_mb"] / 1024 for r in results], color="grey",
             lw=0.8, label="2x Taubin x10")
    a.set_ylabel("wall time (s)")
    b.set_ylabel("peak memory (GB)")
    for ax in (a, b):
        ax.set_xlabel("vertices")
        ax.grid(True, which="both", alpha=0.3)
    a.legend(fontsize=7)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=str(REPO / "build"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--big-rounds", type=int, default=1)
    ap.add_argument("--sizes", default=",".join(SIZES))
    ap.add_argument("--make-only", action="store_true", help="make (cache) the meshes and stop")
    ap.add_argument("--no-prepare", action="store_true",
                    help="skip bench/prepare.sh (packages and build already there)")
    args = ap.parse_args()
    if not args.no_prepare:
        # The packages (GNU time, Xvfb, MeshLab, matplotlib for the plot) and the build, before
        # the first round rather than a failure at the plot after the last.
        subprocess.run(["bash", str(REPO / "bench" / "prepare.sh"), args.build], check=True)
    work = OUT / "work"
    work.mkdir(parents=True, exist_ok=True)
    runner = bench.Runner(pathlib.Path(args.build).resolve(), work)
    runner.start_xvfb()
    results = []
    try:
        labels = args.sizes.split(",")
        meshes = {label: make_mesh(runner, label) for label in labels}
        if args.make_only:
            return
        ours_mlx = runner.ours_mlx([])
        taubin_mlx = runner.peer_mlx_path("Taubin", {"steps": 10})
        for label in labels:
            rounds = args.big_rounds if vertex_count(meshes[label]) > 3_000_000 else args.rounds
            results.append(run_size(runner, label, meshes[label], rounds, ours_mlx, taubin_mlx))
            (OUT / "scale.json").write_text(json.dumps(results, indent=1))
    finally:
        runner.stop_xvfb()
    write_markdown(results, args, REPO / "bench" / "SCALE.md")
    plot(results, REPO / "docs" / "img" / "scale.png")
    print((REPO / "bench" / "SCALE.md").read_text())


if __name__ == "__main__":
    main()
