#!/usr/bin/env python3
"""Impulsive noise on organic meshes with fine relief (heads, busts, statues, figures): ours
against MeshLab's filters and the SD filter, with the criteria: below the SD filter at its
defaults on every case, and the ratio to the best of every peer's sweep (the oracle, chosen per
case with the clean mesh). Writes bench/out/studies/IMPULSIVE_NOISE.md.

    python3 bench/studies/impulsive_noise.py [--build DIR] [--jobs 2] [--quick]

The noise is the literature's impulsive noise (the benchmark's Twelve0.5Impulsive: half of the
vertices moved along their normal by a Gaussian of 0.5 mean edge lengths): a share of the vertices,
picked at random, moved along the clean mesh's area-weighted vertex normal by a Gaussian of the
given std in mean edge lengths. Two kinds per mesh:
- dense: 50 % of the vertices, std 0.3 (the benchmark's kind, a little lighter);
- sparse: 10 % of the vertices, std 1.0 (a few vertices far off the surface).
Meshes: libcgal-demo's lion-head, ChineseDragon-10kv, armadillo, homer, mannequin-devil and man,
and the benchmark's clean Bunny (14 cases, about 45 minutes on two cores; --quick: the lion head
only, the SD filter at its defaults only). Seeded: the same noisy meshes every run.
"""
import json
import pathlib
import signal
import sys
import time
import zlib

import numpy as np

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import bench  # noqa: E402
import heavy_noise  # noqa: E402
import meshio  # noqa: E402
import noref  # noqa: E402
import scanner_bench  # noqa: E402
import scanner_noise  # noqa: E402

REPO = bench.REPO
MESHES = [("lion-head", "cgal", "lion-head"), ("ChineseDragon", "cgal", "ChineseDragon-10kv"),
          ("armadillo", "cgal", "armadillo"), ("homer", "cgal", "homer"),
          ("mannequin-devil", "cgal", "mannequin-devil"), ("man", "cgal", "man"),
          ("Bunny", "bench", "Bunny0.2")]
KINDS = [("dense_0.3", 0.5, 0.3), ("sparse_1.0", 0.1, 1.0)]  # (name, share of vertices, std)
SEED = 20091


def impulsive_noise(points, faces, share, std, seed):
    """`points` with `share` of the vertices moved along their normal by N(0, std) mean edge
    lengths."""
    rng = np.random.default_rng(seed)
    points = np.asarray(points, dtype=np.float64)
    edge = noref.mean_edge_length(points, np.asarray(faces))
    normals = noref.vertex_normals(points, np.asarray(faces))
    picked = rng.random(len(points)) < share
    amount = rng.standard_normal(len(points)) * std * edge * picked
    return points + normals * amount[:, None]


def make_cases(work, quick):
    dest = work / "cases"
    dest.mkdir(parents=True, exist_ok=True)
    cases = []
    for label, kind, name in (MESHES[:1] if quick else MESHES):
        clean, _ = scanner_noise.clean_mesh(kind, name, dest)
        for suffix, share, std in KINDS:
            case = f"{label} {suffix}"
            noisy = dest / f"{label}_{suffix}_noisy.ply"
            if not noisy.exists():
                points, faces, _ = meshio.read_mesh(clean)
                meshio.write_ply(noisy, impulsive_noise(points, faces, share, std,
                                                        SEED + zlib.crc32(case.encode())), faces)
            d = work / "runs" / case.replace(" ", "_")
            d.mkdir(parents=True, exist_ok=True)
            cases.append({"name": case, "clean": clean, "noisy": noisy, "dir": d,
                          "group": "scanner"})
    return cases


def main():
    args, cmd = scanner_bench.peer_script_arguments(__doc__, "bench/studies/impulsive_noise.py")
    args.out = str(REPO / "bench" / "out" / "studies" / "IMPULSIVE_NOISE.md")
    started = time.time()
    work = REPO / "bench" / "out" / ("impulsive_quick" if args.quick else "impulsive")
    work.mkdir(parents=True, exist_ok=True)
    cases = make_cases(work, args.quick)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    results, machine = scanner_bench.run_with_peers(args.build, work, cases, args.quick,
                                                    args.jobs, heavy_noise.STRONGER)
    elapsed = time.time() - started
    (work / "raw.json").write_text(json.dumps({"results": results, "machine": machine},
                                              indent=1, default=str))
    lines = [f"Produced by `{cmd}` on {machine['date']}, commit {machine['commit']}, in "
             f"{elapsed / 60:.1f} min. Do not edit by hand: rerun the command.", "",
             "Noise: impulsive (bench/studies/impulsive_noise.py): dense = 50 % of the vertices "
             "moved along their normal by N(0, 0.3) mean edge lengths, sparse = 10 % by "
             "N(0, 1.0).", ""]
    lines += heavy_noise.table(cases, results)
    pathlib.Path(args.out).write_text("# Impulsive noise on organic meshes against the peers\n\n" +
                                      "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
