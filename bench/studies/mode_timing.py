#!/usr/bin/env python3
"""Filter time of the smoothing modes against the ring barycentre (the smoothing issue's default),
in-process on one thread, the runs of all modes interleaved so that a busy machine slows them alike:
the median over `--rounds` rounds per mesh and mode, its ratio to the ring barycentre's median, and
the peak memory (maximum resident set of the whole process, /usr/bin/time). Issue 8 asks the
automatic mode to stay within 3x of the ring barycentre's time.

    python3 bench/studies/mode_timing.py [--build build] [--rounds 3] [mesh.ply ...]

Without meshes: the timing meshes of `bash bench/run.sh` (bench/out/full/timing, made by its
timing section) from 10k to 1.66M vertices.
"""
import argparse
import json
import os
import pathlib
import statistics
import subprocess
(pathlib.Path(__file__).resolve().parents[1] / "out" / "studies").mkdir(parents=True, exist_ok=True)

REPO = pathlib.Path(__file__).resolve().parents[2]
TIMING = REPO / "bench" / "out" / "full" / "timing"
DEFAULT_MESHES = ["camel_x0_n0.2.ply", "armadillo_x0_n0.2.ply", "armadillo_x1_n0.2.ply",
                  "armadillo_x2_n0.2.ply", "armadillo_x3_n0.2.ply"]
MODES = [("ring barycentre", ["placement=0"]), ("automatic", []), ("feature", ["placement=3"]),
         ("organic", ["placement=4"])]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=str(REPO / "build"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("meshes", nargs="*")
    args = ap.parse_args()
    exe = pathlib.Path(args.build) / "tools" / "smooth_mesh"
    meshes = [pathlib.Path(m) for m in args.meshes] or [TIMING / m for m in DEFAULT_MESHES]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    out = pathlib.Path("/tmp") / f"mode_timing_{os.getpid()}.ply"
    print("| mesh | vertices | " + " | ".join(f"{m} (s)" for m, _ in MODES) +
          " | automatic ÷ ring barycentre | peak memory ring barycentre / automatic (MB) |")
    print("|---|---|" + "---|" * (len(MODES) + 2))
    for mesh in meshes:
        if not mesh.exists():
            print(f"| {mesh.name} | missing (run bash bench/run.sh first) |")
            continue
        seconds = {m: [] for m, _ in MODES}
        memory = {m: [] for m, _ in MODES}
        vertices = 0
        for _ in range(args.rounds):
            for mode, params in MODES:
                r = subprocess.run(["/usr/bin/time", "-f", "peak_kb %M", str(exe), str(mesh),
                                    str(out)] + params, env=env, capture_output=True, text=True,
                                   check=True)
                stats = json.loads(r.stdout.strip().splitlines()[-1])
                seconds[mode].append(stats["seconds"])
                memory[mode].append(int(r.stderr.split("peak_kb")[-1]) / 1024)
                vertices = stats["vertices"]
        median = {m: statistics.median(s) for m, s in seconds.items()}
        rss = {m: statistics.median(s) for m, s in memory.items()}
        print(f"| {mesh.name} | {vertices:,} | " +
              " | ".join(f"{median[m]:.2f}" for m, _ in MODES) +
              f" | {median['automatic'] / median['ring barycentre']:.2f} | "
              f"{rss['ring barycentre']:.0f} / {rss['automatic']:.0f} |", flush=True)
    out.unlink(missing_ok=True)


if __name__ == "__main__":
    main()
