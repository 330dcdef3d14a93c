#!/usr/bin/env python3
"""The noise estimate against the truth: what vcg_ext reads (tools/noise_probe: the finest-band
level of analysis/noise_estimate.h and the amplitude of analysis/noise_amplitude.h) on noisy
meshes whose noise is known, over

- levels 0.05, 0.1, 0.2, 0.4, 0.6, 1.0 mean edge lengths along the clean mesh's normals;
- white noise and noise correlated over 2, 4 and 10 steps of x <- (x + mean of the 1-ring) / 2
  (bench/scanner_noise.py's smoothing), renormalised to the level;
- without and with sparse impulses (2 % of the vertices moved a further 3 to 6 levels along
  their normal, at least one mean edge length);
- CAD meshes (the benchmark's clean Fandisk, Block, Twelve, SharpSphere) and organic ones (its
  Bunny, the paper's cow, libcgal-demo's armadillo and lion head), the Fandisk and the cow also
  midpoint-subdivided once (the same shape at four times the vertices).

The truth: the root mean square of the added displacement along the clean normals, in the clean
mesh's mean edge lengths, over all vertices; beside it the part above its own 10-step low-pass
(the figure quoted for real depth scans). Writes bench/out/studies/NOISE_TRUTH.md: one row per
case, and the share of cases whose reading is within 0.7-1.3 of the truth, per noise kind and
level. Seeded, deterministic.

    python3 bench/studies/noise_truth.py [--build build] [--quick] [--amplitude-noisy T]
    python3 bench/studies/noise_truth.py --heavy      # the heavy depth-camera set instead

About 10 minutes on two cores (--quick: two meshes, a few minutes). --heavy reads the 44 cases of
bench/scanner_noise.py's make_heavy_cases (made once into bench/out/sweep/cases/heavy, as
bench/studies/method_sweep.py's heavy set): the model moves vertices along camera rays, so the
truth is `noisy - clean` projected on the clean vertex normals; writes NOISE_TRUTH_HEAVY.md
(about a minute).
"""
import argparse
import json
import math
import os
import pathlib
import subprocess
import sys
import tarfile

import numpy as np

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import meshio  # noqa: E402
import noref  # noqa: E402
from scanner_noise import make_heavy_cases, smooth_field  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared" / "data"
CGAL_DATA = pathlib.Path("/usr/share/doc/libcgal-demo/data.tar.gz")
OUT = REPO / "bench" / "out" / "studies"

MESHES = [("Fandisk", "CAD", SHARED / "benchmark/Fandisk0.3/clean.ply"),
          ("Block", "CAD", SHARED / "benchmark/Block0.4/clean.ply"),
          ("Twelve", "CAD", SHARED / "benchmark/Twelve0.5Impulsive/clean.ply"),
          ("SharpSphere", "CAD", SHARED / "benchmark/SharpSphere0.3/clean.ply"),
          ("Bunny", "organic", SHARED / "benchmark/Bunny0.2/clean.ply"),
          ("cow", "organic", SHARED / "paper/cow.ply"),
          ("armadillo", "organic", "cgal:armadillo"),
          ("lion-head", "organic", "cgal:lion-head")]
SUBDIVIDED = ("Fandisk", "cow")
LEVELS = (0.05, 0.1, 0.2, 0.4, 0.6, 1.0)
STEPS = (0, 2, 4, 10)
IMPULSES = (0.02, 3.0, 6.0)  # share, size range in levels (at least one mean edge length)
SEED = 20261206


def clean_mesh(source, work):
    if str(source).startswith("cgal:"):
        name = str(source)[5:]
        out = work / f"{name}_clean.ply"
        if not out.exists():
            with tarfile.open(CGAL_DATA) as tar:
                (work / f"{name}.off").write_bytes(
                    tar.extractfile(tar.getmember(f"data/meshes/{name}.off")).read())
            pts, faces = meshio.read_off(work / f"{name}.off")
            meshio.write_ply(out, pts, faces)
        source = out
    points, faces, _ = meshio.read_mesh(source)
    return points, faces


def clean_version(label, work):
    """The clean mesh of a case's `mesh` label (points, faces): " x4" is midpoint-subdivided."""
    name = label[:-len(" x4")] if label.endswith(" x4") else label
    points, faces = clean_mesh(dict((m[0], m[2]) for m in MESHES)[name], work)
    return meshio.midpoint_subdivide(points, faces) if label.endswith(" x4") else (points, faces)


def noise_field(rng, n, edges, steps, level, impulses):
    """Unit-less displacement per vertex along the normal, in mean edge lengths."""
    g = rng.standard_normal(n)
    if steps:
        g = smooth_field(g, edges, steps)
    g *= level / max(g.std(), 1e-300)
    if impulses:
        share, lo, hi = IMPULSES
        pick = np.flatnonzero(rng.random(n) < share)
        size = np.maximum(rng.uniform(lo, hi, len(pick)) * level, 1.0)
        g[pick] += rng.choice([-1.0, 1.0], len(pick)) * size
    return g


def cases(work, quick):
    meshes = MESHES[:1] + MESHES[4:5] if quick else MESHES
    out = []
    for name, kind, source in meshes:
        points, faces = clean_mesh(source, work)
        versions = [(name, points, faces)]
        if name in SUBDIVIDED and not quick:
            versions.append((name + " x4",) + tuple(meshio.midpoint_subdivide(points, faces)))
        for label, pts, f in versions:
            edges = noref.unique_edges(f)
            h = noref.mean_edge_length(pts, f)
            normals = noref.vertex_normals(pts, f)
            for steps in STEPS:
                for level in (LEVELS[::2] if quick else LEVELS):
                    for impulses in (False, True):
                        rng = np.random.default_rng([SEED, steps, int(level * 1000), impulses])
                        g = noise_field(rng, len(pts), edges, steps, level, impulses)
                        path = work / f"{label.replace(' ', '_')}_s{steps}_l{level}_i{int(impulses)}.ply"
                        meshio.write_ply(path, pts + (g * h)[:, None] * normals, f)
                        above = g - smooth_field(g, edges, 10)
                        out.append({"mesh": label, "kind": kind, "steps": steps, "level": level,
                                    "impulses": impulses, "path": str(path),
                                    "truth": float(np.sqrt(np.mean(g ** 2))),
                                    "truth_above_10": float(np.sqrt(np.mean(above ** 2)))})
    return out


def probe(build, paths, jobs, flags=()):
    """tools/noise_probe's JSON per mesh, in chunks over `jobs` processes."""
    chunks = [paths[i::jobs] for i in range(jobs)]
    procs = [subprocess.Popen([str(build / "tools" / "noise_probe"), *flags, *c],
                              stdout=subprocess.PIPE,
                              text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
             for c in chunks if c]
    out = {}
    for p in procs:
        for line in p.communicate()[0].splitlines():
            r = json.loads(line)
            out[r["mesh"]] = r
    return out


def within(x):
    return 0.7 <= x <= 1.3


def report(rows, clean_rows, cmd):
    lines = [f"# The noise estimate against the truth\n\n`{cmd}`. *level*: the finest-band level "
             "(noise_estimate.h); *amplitude*: noise_amplitude.h, with the correlation *s* it was "
             "read with; *truth*: rms of the added noise along the normals (mean edge lengths); "
             "*above 10*: its part above the 10-step low-pass.\n",
             "*read noisy*: by one Taubin pair's test or, where that reads clean, by the amplitude "
             "(*by amplitude*: its trimmed reading at least noise_estimate.h's amplitude_noisy, "
             "0.5, or the command's --amplitude-noisy, and 0.7 of the plain one). *read anyway*: the amplitude also where the "
             "mesh reads clean (noise_probe --amplitude-always; the filter keeps it only on "
             "meshes that read noisy). *dense*: with impulses, the reading against the dense "
             "noise's level (the impulses are read apart, analysis/impulses.h).\n",
             "## Share within 0.7-1.3 of the truth\n",
             "| noise | cases | read noisy | by amplitude | level | amplitude | "
             "amplitude vs above-10 | read anyway | read anyway vs dense |",
             "|---|---|---|---|---|---|---|---|---|"]

    def group(label, pick):
        g = [r for r in rows if pick(r)]
        if not g:
            return
        share = lambda key, truth: sum(within(r[key] / r[truth]) for r in g) / len(g)
        noisy = sum(r["noisy"] for r in g) / len(g)
        by_amplitude = sum(r["noisy_by_amplitude"] for r in g) / len(g)
        lines.append(f"| {label} | {len(g)} | {noisy:.2f} | {by_amplitude:.2f} | "
                     f"{share('level_read', 'truth'):.2f} | "
                     f"{share('amplitude', 'truth'):.2f} | {share('amplitude', 'truth_above_10'):.2f} | "
                     f"{share('anyway', 'truth'):.2f} | {share('anyway', 'level'):.2f} |")
    group("all", lambda r: True)
    for kind in ("CAD", "organic"):
        group(kind, lambda r, k=kind: r["kind"] == k)
    for steps in STEPS:
        group(f"correlation {steps} steps", lambda r, s=steps: r["steps"] == s)
    for level in LEVELS:
        group(f"level {level}", lambda r, l=level: r["level"] == l)
    group("with impulses", lambda r: r["impulses"])
    group("levels 0.2-1.0, no impulses", lambda r: r["level"] >= 0.2 and not r["impulses"])
    lines += ["\n## Every case\n",
              "| mesh | kind | s | level | impulses | truth | above 10 | noisy | level read | "
              "amplitude | s read | read anyway |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['mesh']} | {r['kind']} | {r['steps']} | {r['level']} | "
                     f"{'yes' if r['impulses'] else ''} | {r['truth']:.3f} | {r['truth_above_10']:.3f} | "
                     f"{('by amplitude' if r['noisy_by_amplitude'] else 'yes') if r['noisy'] else 'no'} | "
                     f"{r['level_read']:.3f} | {r['amplitude']:.3f} | "
                     f"{r['correlation_read']} | {r['anyway']:.3f} |")
    lines += ["\n## The clean meshes, read anyway\n",
              "What the amplitude reads on the clean meshes themselves (the truth is 0): the shape "
              "it cannot tell from noise; *trimmed*: its reading on trimmed bands.\n",
              "| mesh | kind | noisy | level read | read anyway | trimmed |",
              "|---|---|---|---|---|---|"]
    for r in clean_rows:
        lines.append(f"| {r['mesh']} | {r['kind']} | {'yes' if r['noisy'] else 'no'} | "
                     f"{r['level_read']:.3f} | {r['anyway']:.3f} | {r['trimmed']:.3f} |")
    return "\n".join(lines) + "\n"


def heavy_rows(build, jobs):
    """The heavy set's cases with their truth along the clean normals and what is read."""
    rows = []
    for c in make_heavy_cases(REPO / "bench" / "out" / "sweep" / "cases" / "heavy"):
        points, faces, _ = meshio.read_mesh(c["clean"])
        noisy, _, _ = meshio.read_mesh(c["noisy"])
        h = noref.mean_edge_length(points, faces)
        g = np.einsum("ij,ij->i", noisy - points, noref.vertex_normals(points, faces)) / h
        above = g - smooth_field(g, noref.unique_edges(faces), 10)
        rows.append({"case": c["name"], "path": str(c["noisy"]),
                     "truth": float(np.sqrt(np.mean(g ** 2))),
                     "truth_above_10": float(np.sqrt(np.mean(above ** 2)))})
    read = probe(build, [r["path"] for r in rows], jobs)
    for r in rows:
        p = read[r["path"]]
        r.update(amplitude=p["amplitude"], correlated_share=p["correlated_share"])
    return rows


def heavy_report(rows):
    def within(key, subset):
        return sum(0.7 <= r["amplitude"] / r[key] <= 1.3 for r in subset)
    lines = ["# The amplitude against the truth on the heavy depth-camera set", "",
             "Produced by `python3 bench/studies/noise_truth.py --heavy`. Do not edit by hand.", "",
             "Truth: `noisy - clean` along the clean vertex normals, rms in mean edge lengths; "
             "above 10: the same after its 10-step low-pass is removed.", "",
             "| case | truth | above 10 | amplitude | read / truth | read / above 10 | "
             "correlated share |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['case']} | {r['truth']:.3f} | {r['truth_above_10']:.3f} | "
                     f"{r['amplitude']:.3f} | {r['amplitude'] / r['truth']:.2f} | "
                     f"{r['amplitude'] / r['truth_above_10']:.2f} | {r['correlated_share']:.2f} |")
    lines.append("")
    for kind in ("4views", "red"):
        subset = [r for r in rows if kind in r["case"]]
        lines.append(f"- {kind}: within 0.7-1.3 of the truth on {within('truth', subset)} of "
                     f"{len(subset)}, of the part above 10 on {within('truth_above_10', subset)}.")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.environ.get("SBS_BUILD_DIR", str(REPO / "build")))
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--out", default=None)
    ap.add_argument("--heavy", action="store_true", help="the heavy depth-camera set instead")
    ap.add_argument("--amplitude-noisy", type=float, default=None,
                    help="the amplitude's decision threshold instead of the estimate's default "
                         "(noise_probe --amplitude-noisy; 0: the pair's test alone)")
    args = ap.parse_args()
    if args.heavy:
        text = heavy_report(heavy_rows(pathlib.Path(args.build), args.jobs))
        pathlib.Path(args.out or OUT / "NOISE_TRUTH_HEAVY.md").write_text(text)
        print(text)
        return
    args.out = args.out or str(OUT / "NOISE_TRUTH.md")
    work = OUT / "noise_truth"
    work.mkdir(parents=True, exist_ok=True)
    rows = cases(work, args.quick)
    clean_rows = []
    for name, kind, source in (MESHES[:1] + MESHES[4:5] if args.quick else MESHES):
        points, faces = clean_mesh(source, work)
        path = work / f"{name}_clean_read.ply"
        meshio.write_ply(path, points, faces)
        clean_rows.append({"mesh": name, "kind": kind, "path": str(path)})
        if name in SUBDIVIDED and not args.quick:
            path = work / f"{name}_x4_clean_read.ply"
            meshio.write_ply(path, *meshio.midpoint_subdivide(points, faces))
            clean_rows.append({"mesh": name + " x4", "kind": kind, "path": str(path)})
    build = pathlib.Path(args.build)
    flags = [] if args.amplitude_noisy is None else ["--amplitude-noisy", str(args.amplitude_noisy)]
    read = probe(build, [r["path"] for r in rows], args.jobs, flags)
    anyway = probe(build, [r["path"] for r in rows + clean_rows], args.jobs,
                   flags + ["--amplitude-always"])
    for r in rows:
        p = read[r["path"]]
        r.update(level_read=p["level"], amplitude=p["amplitude"], noisy=p["noisy"],
                 noisy_by_amplitude=p["noisy_by_amplitude"],
                 correlation_read=p["correlation_steps"], anyway=anyway[r["path"]]["amplitude"])
    for r in clean_rows:
        p = anyway[r["path"]]
        r.update(level_read=p["level"], noisy=p["noisy"], anyway=p["amplitude"],
                 trimmed=p["trimmed_amplitude"])
    cmd = "python3 bench/studies/noise_truth.py" + (" --quick" if args.quick else "") + (
        f" --amplitude-noisy {args.amplitude_noisy}" if args.amplitude_noisy is not None else "")
    (work / "rows.json").write_text(json.dumps(rows, indent=1))
    text = report(rows, clean_rows, cmd)
    pathlib.Path(args.out).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
