#!/usr/bin/env python3
"""Whole-process timings for docs/studies/performance.md (issue 7): our filter inside meshlabserver vs
MeshLab's Taubin x10, TwoStep and Laplacian x5 in the same run, on the armadillo at 26k, 104k,
416k and 1.66M vertices (midpoint subdivisions of libcgal-demo's armadillo, normal noise 0.2 x mean
edge) and libcgal-demo's camel (~10k), plus our in-process stage split.

    python3 bench/studies/perf_scaling.py --build build-perf [--runs 3] [--sizes 0,1,2,3] [--out DIR]

Uses bench.py's Runner (Xvfb, /usr/bin/time for peak RSS). Rounds are interleaved (every method
once per round); medians. Writes DIR/perf_scaling.json and DIR/perf_scaling.png (log-log).
"""
import argparse
import json
import pathlib
import statistics
import sys

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import bench  # noqa: E402
(pathlib.Path(__file__).resolve().parents[1] / "out" / "studies").mkdir(parents=True, exist_ok=True)

PEERS = [("Taubin x10", "Taubin", {"steps": 10}), ("TwoStep x3, 60deg", "TwoStep",
                                                   {"steps": 3, "thr": 60}),
         ("Laplacian x5", "Laplacian", {"steps": 5})]


def make_meshes(runner, work, sizes):
    src = bench.cgal_meshes(work)
    meshes = []
    for name, levels in [("camel", 0)] + [("armadillo", k) for k in sizes]:
        noisy = bench.noisy_subdivided(runner, src, work, name, levels)
        info = json.loads(runner.tool("mesh_compare", "--volume", noisy))
        meshes.append({"name": f"{name} x{levels}", "path": noisy, "vertices": info["vertices"]})
    return meshes


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True, type=pathlib.Path)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--sizes", default="0,1,2,3")
    ap.add_argument("--out", type=pathlib.Path, default=None)
    ap.add_argument("--skip-slow", type=float, default=120,
                    help="a method whose first run takes longer is not repeated")
    args = ap.parse_args()
    out_dir = args.out or pathlib.Path(__file__).resolve().parents[1] / "out" / "perf"
    work = out_dir / "work"
    work.mkdir(parents=True, exist_ok=True)
    runner = bench.Runner(args.build.resolve(), work)
    runner.start_xvfb()
    results = []
    try:
        meshes = make_meshes(runner, work, [int(s) for s in args.sizes.split(",")])
        for mesh in meshes:
            bench.log(f"{mesh['name']}: {mesh['vertices']} vertices")
            out = work / "out.ply"
            methods = ["load+save only", "ours in meshlabserver", "ours in-process"] + \
                [label for label, _, _ in PEERS]
            samples = {m: [] for m in methods}
            for rnd in range(args.runs):
                for label in methods:
                    if rnd > 0 and samples[label] and samples[label][0]["wall"] > args.skip_slow:
                        continue
                    if label == "load+save only":
                        r = runner.meshlab(mesh["path"], out, None, timed=True)
                    elif label == "ours in meshlabserver":
                        r = runner.meshlab(mesh["path"], out, runner.ours_mlx([]), timed=True)
                        r["stages"] = bench.parse_stages(r["log"])
                    elif label == "ours in-process":
                        r = runner.smooth_inprocess(mesh["path"], out, [], timed=True)
                    else:
                        peer, setting = [(p, s) for lab, p, s in PEERS if lab == label][0]
                        r = runner.meshlab(mesh["path"], out, runner.peer_mlx_path(peer, setting),
                                           timed=True)
                    r.pop("log", None)
                    samples[label].append(r)
                    bench.log(f"  round {rnd + 1} {label}: {r['wall']:.2f} s, "
                              f"{r['rss'] or 0:.0f} MB")
            med = {}
            for label in methods:
                s = samples[label]
                m = {"wall": statistics.median(x["wall"] for x in s), "walls": [x["wall"] for x in s],
                     "rss": statistics.median(x["rss"] for x in s if x["rss"] is not None)}
                if "filter" in s[0]:
                    m["filter"] = statistics.median(x["filter"] for x in s)
                stages = [x["stages"] for x in s if x.get("stages")]
                if stages:
                    m["stages"] = {k: statistics.median(st[k] for st in stages) for k in stages[0]}
                med[label] = m
            results.append({"mesh": {k: str(v) for k, v in mesh.items()}, "methods": med})
            (out_dir / "perf_scaling.json").write_text(json.dumps(results, indent=1))
    finally:
        runner.stop_xvfb()
    plot(results, out_dir / "perf_scaling.png")


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4.5))
    n = [int(r["mesh"]["vertices"]) for r in results]
    order = sorted(range(len(n)), key=lambda i: n[i])
    base = [results[i]["methods"]["load+save only"]["wall"] for i in order]
    for label in ["ours in meshlabserver", "Taubin x10", "TwoStep x3, 60deg", "Laplacian x5"]:
        y = [max(results[i]["methods"][label]["wall"] - b, 1e-3) for i, b in zip(order, base)]
        ax.loglog([n[i] for i in order], y, "o-", label=label + " (minus load+save)")
    x = [n[i] for i in order]
    ours = [max(results[i]["methods"]["ours in meshlabserver"]["wall"] - b, 1e-3)
            for i, b in zip(order, base)]
    ax.loglog(x, [ours[-1] * v / x[-1] for v in x], "k:", label="linear")
    ax.set_xlabel("vertices")
    ax.set_ylabel("seconds (whole meshlabserver run minus load+save)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
