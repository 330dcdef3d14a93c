#!/usr/bin/env python3
"""The default on a busy machine: whole meshlabserver runs of our filter (automatic mode) and of
MeshLab's Taubin x10 on the scale benchmark's meshes, on a quiet machine and with one other
process keeping a core busy (a Python busy loop, as a compile or a second tool would), medians of
interleaved rounds.

    python3 bench/studies/busy_machine.py [--build build] [--rounds 3] [--sizes 10k,100k,1M] [--no-prepare]

Ours runs three ways: as installed (the OpenMP runtime's defaults), with OMP_WAIT_POLICY=passive
(threads that wait for the others sleep instead of spinning) and with OMP_NUM_THREADS=1. The
outputs of the three are compared byte for byte (results do not depend on the thread count).
Writes bench/out/busy/busy.json and docs/studies/performance.md. Installs what it needs and builds first
(bench/prepare.sh). Run it on an otherwise quiet machine: the busy process is its own.
"""
import argparse
import filecmp
import json
import os
import pathlib
import statistics
import subprocess
import sys
import time

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import bench  # noqa: E402
import scale  # noqa: E402
(pathlib.Path(__file__).resolve().parents[1] / "out" / "studies").mkdir(parents=True, exist_ok=True)

REPO = pathlib.Path(__file__).resolve().parents[2]
OUT = REPO / "bench" / "out" / "busy"
VARIANTS = {"ours": {}, "ours, OMP_WAIT_POLICY=passive": {"OMP_WAIT_POLICY": "passive"},
            "ours, OMP_NUM_THREADS=1": {"OMP_NUM_THREADS": "1"}, "Taubin x10": {}}
BUSY_LOOP = "while True: pass"


def measure(runner, label, mesh, rounds, busy, mlx):
    walls = {v: [] for v in VARIANTS}
    identical = []
    loop = subprocess.Popen([sys.executable, "-c", BUSY_LOOP]) if busy else None
    try:
        time.sleep(0.5 if busy else 0)
        for rnd in range(rounds):
            outs = {}
            for v, extra in VARIANTS.items():
                outs[v] = OUT / "work" / f"out_{len(outs)}.ply"
                walls[v].append(runner.meshlab(mesh, outs[v], mlx[v], extra_env=extra)["wall"])
                bench.log(f"{label} {'busy' if busy else 'quiet'} round {rnd + 1} {v}: "
                          f"{walls[v][-1]:.2f} s")
            ours = [outs[v] for v in VARIANTS if v.startswith("ours")]
            identical.append(all(filecmp.cmp(ours[0], o, shallow=False) for o in ours[1:]))
    finally:
        if loop is not None:
            loop.kill()
            loop.wait()
    return {"walls": walls, "median": {v: statistics.median(w) for v, w in walls.items()},
            "identical": identical}


def write_markdown(results, args, path):
    lines = ["# The default on a busy machine", "",
             "Whole `meshlabserver` runs (binary PLY in and out) of our filter at its defaults and "
             "of MeshLab's Taubin Smooth x10 (lambda 0.5, mu -0.53) on the scale benchmark's "
             "meshes (bench/SCALE.md), on a quiet machine and with one other process keeping a core busy "
             "(a Python busy loop). Ours runs as installed (the OpenMP runtime's defaults), with "
             "`OMP_WAIT_POLICY=passive` and with `OMP_NUM_THREADS=1`. Medians of interleaved "
             "rounds, wall seconds; machine: "
             f"{os.cpu_count()} cores.", "",
             f"Command: `python3 bench/studies/busy_machine.py --rounds {args.rounds} --sizes {args.sizes}`"
             f" ({time.strftime('%Y-%m-%d')}).", "",
             "| mesh | vertices | machine | ours | ours, passive wait | ours, one thread | "
             "Taubin x10 | ours ÷ Taubin | passive ÷ Taubin | outputs identical |",
             "|---|---:|---|---:|---:|---:|---:|---:|---:|---|"]
    for r in results:
        for state in ("quiet", "busy"):
            m = r[state]["median"]
            same = r[state]["identical"]
            lines.append(
                f"| {r['label']} | {r['vertices']:,} | {state} | {m['ours']:.2f} | "
                f"{m['ours, OMP_WAIT_POLICY=passive']:.2f} | {m['ours, OMP_NUM_THREADS=1']:.2f} | "
                f"{m['Taubin x10']:.2f} | {m['ours'] / m['Taubin x10']:.2f} | "
                f"{m['ours, OMP_WAIT_POLICY=passive'] / m['Taubin x10']:.2f} | "
                f"{sum(same)} of {len(same)} |")
    lines += ["", "Why: the OpenMP runtime (GNU libgomp) lets a thread that has finished its share "
              "spin for a while before it sleeps, so that the next parallel step starts at once. "
              "With another process on one of the cores, the spinning thread takes CPU time from "
              "the thread still working, at every one of the filter's few hundred parallel steps. "
              "`OMP_WAIT_POLICY=passive` makes waiting threads sleep at once. The runtime reads it "
              "when it starts, before any plugin runs, so it is set where MeshLab, meshlabserver "
              "or Python is started (the plugin cannot change it). Below 20k vertices only the "
              "heavy stages run in parallel (from 5k elements: a few regions per run; "
              "vcg_ext/core/rings.h `parallelHeavy`), so the 10k mesh waits for threads far less "
              "often than the larger ones."]
    path.write_text("\n".join(lines) + "\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=str(REPO / "build"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--sizes", default="10k,100k,1M")
    ap.add_argument("--no-prepare", action="store_true",
                    help="skip bench/prepare.sh (packages and build already there)")
    args = ap.parse_args()
    if not args.no_prepare:
        subprocess.run(["bash", str(REPO / "bench" / "prepare.sh"), args.build], check=True)
    (OUT / "work").mkdir(parents=True, exist_ok=True)
    runner = bench.Runner(pathlib.Path(args.build).resolve(), OUT / "work")
    runner.start_xvfb()
    results = []
    try:
        ours = runner.ours_mlx([])
        mlx = {v: ours for v in VARIANTS}
        mlx["Taubin x10"] = runner.peer_mlx_path("Taubin", {"steps": 10})
        for label in args.sizes.split(","):
            mesh = scale.make_mesh(runner, label)
            r = {"label": label, "vertices": scale.vertex_count(mesh)}
            for state in ("quiet", "busy"):
                r[state] = measure(runner, label, mesh, args.rounds, state == "busy", mlx)
            results.append(r)
            OUT.mkdir(parents=True, exist_ok=True)
            (OUT / "busy.json").write_text(json.dumps(results, indent=1))
    finally:
        runner.stop_xvfb()
    write_markdown(results, args, REPO / "bench" / "out" / "studies" / "BUSY_MACHINE.md")
    print((REPO / "bench" / "out" / "studies" / "BUSY_MACHINE.md").read_text())


if __name__ == "__main__":
    main()
