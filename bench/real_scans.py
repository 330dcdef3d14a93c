#!/usr/bin/env python3
"""Real scans without ground truth (shared/data/real: angel, rabbit, iron): our default (through
meshlabserver), MeshLab's Taubin x10 and the SD filter at its defaults on each; prints and writes
into bench/REAL_SCANS.md (between its <!-- results --> markers):

- the mean vertex displacement in the input's mean edge lengths (issue 16: the default must move
  vertices by at least as much as Taubin x10), its 99th percentile and its mean signed part along
  the normals (negative: the surface moved inwards, i.e. shrank);
- the median dihedral spread before and after (bench/noref.py: noise bends a face's three edges at
  random, curvature alike, so the spread falls as noise is removed and not as shape is);
- the whole-process wall time of each run;
and renders before/after pictures (flat shading, one view and frame per scan, full view and a
close-up) into docs/img/real_<scan>.png.

    python3 bench/real_scans.py [--build DIR] [--out FILE] [--img DIR]

Runs against whatever plugin DIR holds (default build/).
"""
import argparse
import json
import os
import pathlib
import resource
import signal
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import bench  # noqa: E402
import figures  # noqa: E402
import meshio  # noqa: E402
import noref  # noqa: E402
import render  # noqa: E402
import sd_filter  # noqa: E402
from figures import plt  # noqa: E402

REPO = bench.REPO
REAL = bench.SHARED / "data" / "real"
# scan -> (world up axis for the picture, close-up centre as a fraction of the bbox, close-up
# half extent as a fraction of the frame); the view looks along the scan's mean face normal (for
# a single range scan: towards the scanner).
SCANS = {"angel": ((0, -1, 0), (0.5, 0.42, 0.5), 0.22),   # close-up: the face
         "rabbit": ((0, 1, 0), (0.7, 0.4, 0.5), 0.22),     # the haunch's relief
         "iron": ((0, 0, 1), (0.5, 0.5, 0.5), 0.25)}
# The SD filter also at the sweep setting that was best on most scanner-noise cases
# (SCANNER_NOISE.md: 8 of 12), since its defaults over-smooth: a reference, not an oracle.
SD_SCANNER_SETTING = {"Lambda": 0.25, "Eta": 0.75, "Nu": 0.45}
METHODS = ["ours automatic (default)", "MeshLab Taubin x10", "SD filter defaults",
           "SD filter Lambda 0.25, Eta 0.75, Nu 0.45"]
MARK_BEGIN, MARK_END = "<!-- results: bench/real_scans.py -->", "<!-- /results -->"
PANEL = 300


def log(*a):
    print("[real]", *a, file=sys.stderr, flush=True)


def run_method(runner, method, src, out):
    if method == "ours automatic (default)":
        r = runner.meshlab(src, out, runner.ours_mlx([]))
    elif method == "MeshLab Taubin x10":
        r = runner.meshlab(src, out, runner.peer_mlx_path("Taubin", {"steps": 10}))
    elif method == "SD filter defaults":
        r = sd_filter.run(src, out, {}, options_dir=runner.mlx_dir)
    else:
        r = sd_filter.run(src, out, SD_SCANNER_SETTING, options_dir=runner.mlx_dir)
    return r


def facing_rotation(points, faces, up):
    """Rotation to camera coordinates with the mean face normal towards the viewer."""
    fn = np.cross(points[faces[:, 1]] - points[faces[:, 0]],
                  points[faces[:, 2]] - points[faces[:, 0]]).sum(0)
    z = fn / np.linalg.norm(fn)
    y = np.asarray(up, dtype=float) - np.dot(up, z) * z
    y /= np.linalg.norm(y)
    return np.stack([np.cross(y, z), y, z])


def picture(name, meshes, path):
    """Two rows (full view, close-up), one column per mesh: [(title, points, faces)]."""
    up, centre_frac, half_frac = SCANS[name]
    points0, faces0 = meshes[0][1], meshes[0][2]
    rot = facing_rotation(points0, faces0, up)
    full = render.camera_frame(points0 @ rot.T)
    lo, hi = points0.min(0), points0.max(0)
    centre = lo + np.asarray(centre_frac) * (hi - lo)
    close = render.crop_frame(points0, rot, centre, full[1] * half_frac)
    fig, axes = plt.subplots(2, len(meshes), figsize=(len(meshes) * PANEL / 100,
                                                      2 * PANEL / 100 + 0.5), squeeze=False)
    for col, (title, points, faces) in enumerate(meshes):
        for row, frame in enumerate((full, close)):
            ax = axes[row, col]
            ax.imshow(render.render(points, faces, rot, size=PANEL, frame=frame))
            ax.axis("off")
            if row == 0:
                ax.set_title(title, fontsize=8)
    fig.suptitle(f"Real scan: {name} (full view and close-up, flat shading)", fontsize=10)
    fig.tight_layout(pad=0.3, rect=(0, 0, 1, 0.93))
    figures.save(fig, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.environ.get("SBS_BUILD_DIR", str(REPO / "build")))
    ap.add_argument("--out", default=str(REPO / "bench" / "REAL_SCANS.md"))
    ap.add_argument("--img", default=str(REPO / "docs" / "img"))
    ap.add_argument("--scans", nargs="*", default=list(SCANS))
    args = ap.parse_args()
    started = time.time()
    if not sd_filter.available():
        sys.exit(f"{sd_filter.BINARY} not found: apt-get install {sd_filter.PACKAGE}")
    work = REPO / "bench" / "out" / "real"
    work.mkdir(parents=True, exist_ok=True)
    img = pathlib.Path(args.img)
    img.mkdir(parents=True, exist_ok=True)
    runner = bench.Runner(pathlib.Path(args.build).resolve(), work)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    runner.start_xvfb()
    results = {}
    try:
        machine = bench.machine_info()
        for name in args.scans:
            src = REAL / f"{name}.ply"
            points, faces, _ = meshio.read_mesh(src)
            row = {"vertices": len(points), "mean_edge": noref.mean_edge_length(points, faces),
                   "spread": noref.median_dihedral_spread_deg(points, faces)}
            meshes = [("input", points, faces)]
            for method in METHODS:
                out = work / f"{name}_{METHODS.index(method)}.ply"
                before = resource.getrusage(resource.RUSAGE_CHILDREN)
                r = run_method(runner, method, src, out)
                after = resource.getrusage(resource.RUSAGE_CHILDREN)
                cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
                p, f, _ = meshio.read_mesh(out)
                if len(p) != len(points) or not np.array_equal(f, faces):
                    sys.exit(f"{method} changed {name}'s connectivity: cannot compare")
                row[method] = dict(noref.displacement(points, p, faces), wall=r["wall"], cpu=cpu,
                                   spread=noref.median_dihedral_spread_deg(p, faces))
                if "split_faces" in r:
                    row[method]["split_faces"] = r["split_faces"]
                meshes.append((f"{method}\nmoved {row[method]['mean']:.3f} edges, spread "
                               f"{row[method]['spread']:.1f}°", p, faces))
                log(f"{name} {method}: moved {row[method]['mean']:.4f} mean edges, spread "
                    f"{row['spread']:.1f} -> {row[method]['spread']:.1f}, {r['wall']:.1f} s")
            meshes[0] = (f"input\nspread {row['spread']:.1f}°", points, faces)
            picture(name, meshes, img / f"real_{name}.png")
            results[name] = row
    finally:
        runner.stop_xvfb()
    (work / "raw.json").write_text(json.dumps(results, indent=1))
    elapsed = time.time() - started
    cmd = "python3 bench/real_scans.py" + (
        f" --build {args.build}" if args.build != str(REPO / "build") else "")
    L = [f"Produced by `{cmd}` on {machine['date']}, commit {machine['commit']}, in "
         f"{elapsed / 60:.1f} min. Do not edit by hand: rerun the command.", "",
         "Displacement in the input's mean edge lengths: mean / 99th percentile / mean signed "
         "part along the input's normals (negative = inwards), then the means of its parts along "
         "the normals (n, what changes the surface) and across them (t, vertices sliding within "
         "the surface); median dihedral spread (°) of the input → the result; whole-process wall "
         "/ CPU (user + system) time in seconds, one run (a shared machine: wall time swings with "
         "the other jobs' load, CPU time much less).", "",
         "| scan | vertices | input spread | " + " | ".join(METHODS) +
         " | default ÷ Taubin ×10: mean displacement / its part along the normals |",
         "|---|---|---|" + "---|" * len(METHODS) + "---|"]
    for name, row in results.items():
        cells = [f"{row[m]['mean']:.3f} / {row[m]['p99']:.3f} / {row[m]['normal_mean']:+.3f} "
                 f"(n {row[m]['normal']:.3f}, t {row[m]['tangential']:.3f}); "
                 f"spread → {row[m]['spread']:.1f}; {row[m]['wall']:.1f} / {row[m]['cpu']:.1f} s"
                 for m in METHODS]
        taubin = row["MeshLab Taubin x10"]

        def ratio(key):
            return row[METHODS[0]][key] / taubin[key] if taubin[key] > 0 else float("nan")
        L.append(f"| {name} | {row['vertices']} | {row['spread']:.1f} | " + " | ".join(cells) +
                 f" | {ratio('mean'):.2f} / {ratio('normal'):.2f} |")
    L += ["", "Pictures (input, then the methods in the table's order; full view above, close-up "
          "below; flat shading, one view and frame per scan):", ""]
    L += [f"![{name}](../docs/img/real_{name}.png)" for name in results]
    bench.write_between_markers(args.out, MARK_BEGIN, MARK_END, L)
    log(f"wrote {args.out} ({elapsed / 60:.1f} min)")
    print("\n".join(L))


if __name__ == "__main__":
    main()
