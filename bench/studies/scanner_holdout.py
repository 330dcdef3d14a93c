#!/usr/bin/env python3
"""Held-out scanner noise: the scanner-noise comparison of bench/scanner_bench.py on meshes and
noise that no rule of the filter was fitted on, written into docs/studies/scanner-noise.md (between its
<!-- holdout --> markers).

    python3 bench/studies/scanner_holdout.py [--build DIR] [--jobs 2] [--quick]

- Meshes: twelve libcgal-demo meshes outside the twelve scanner-noise cases (six CAD parts, six
  organic shapes; bench/scanner_bench.py's cases are Fandisk, Block, SharpSphere, Bunny, the paper's
  cow and the armadillo).
- Noise: bench/scanner_noise.py's model with other parameters than the cases' (3 views, level 0.3,
  correlation over 4 smoothing steps instead of 6, a white share of 0.15 instead of 0.1, another
  seed), chosen before any result was seen.
- Methods and scores as in bench/scanner_bench.py (ours through meshlabserver in three modes,
  MeshLab's four filters at defaults and best, the SD filter at defaults and best of its sweep).
--quick: four meshes, the SD filter at its defaults only.
"""
import json
import pathlib
import signal
import sys
import tarfile
import time
import zlib

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import bench  # noqa: E402
import meshio  # noqa: E402
import scanner_bench  # noqa: E402
import scanner_noise  # noqa: E402
(pathlib.Path(__file__).resolve().parents[1] / "out" / "studies").mkdir(parents=True, exist_ok=True)

REPO = bench.REPO
CAD = ["fandisk_large", "anchor_dense", "turbine", "mech-holes-shark", "rotor_small", "couplingdown"]
ORGANIC = ["lion-head", "camel", "dino", "homer", "mannequin-devil", "hand"]
NOISE = {"views": 3, "corr_steps": 4, "white": 0.15}
LEVEL = 0.3
SEED = 77031
MARK_BEGIN, MARK_END = "<!-- holdout: bench/studies/scanner_holdout.py -->", "<!-- /holdout -->"


def make_cases(work, quick):
    meshes = CAD[:2] + ORGANIC[:2] if quick else CAD + ORGANIC
    dest = work / "holdout_cases"
    dest.mkdir(parents=True, exist_ok=True)
    cases = []
    with tarfile.open(bench.CGAL_DATA) as tar:
        for name in meshes:
            clean = dest / f"{name}_clean.ply"
            if not clean.exists():
                off = dest / f"{name}.off"
                off.write_bytes(tar.extractfile(f"data/meshes/{name}.off").read())
                points, faces = meshio.read_off(off)
                off.unlink()
                meshio.write_ply(clean, points, faces)
            points, faces, _ = meshio.read_mesh(clean)
            case = f"{name} 3views_{LEVEL}"
            noisy = dest / f"{name}_noisy.ply"
            out, _ = scanner_noise.scanner_noise(points, faces, LEVEL,
                                                 SEED + zlib.crc32(case.encode()), **NOISE)
            meshio.write_ply(noisy, out, faces)
            d = work / "runs" / case.replace(" ", "_")
            d.mkdir(parents=True, exist_ok=True)
            cases.append({"name": case, "clean": clean, "noisy": noisy, "dir": d,
                          "group": "scanner", "kind": "CAD" if name in CAD else "organic"})
    return cases


def main():
    args, cmd = scanner_bench.peer_script_arguments(__doc__, "bench/studies/scanner_holdout.py")
    started = time.time()
    work = REPO / "bench" / "out" / ("holdout_quick" if args.quick else "holdout")
    if (work / "runs").exists():
        import shutil
        shutil.rmtree(work / "runs")
    work.mkdir(parents=True, exist_ok=True)
    cases = make_cases(work, args.quick)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    results, machine = scanner_bench.run_with_peers(args.build, work, cases, args.quick, args.jobs)
    elapsed = time.time() - started
    (work / "raw.json").write_text(json.dumps({"results": results, "machine": machine},
                                              indent=1, default=str))
    lines = [f"Produced by `{cmd}` on {machine['date']}, commit {machine['commit']}, in "
             f"{elapsed / 60:.1f} min. Do not edit by hand: rerun the command.", "",
             f"Noise: bench/scanner_noise.py, level {LEVEL}, " +
             ", ".join(f"{k} {v}" for k, v in NOISE.items()) + f", seed {SEED} + crc32(case). "
             "CAD: " + ", ".join(c for c in CAD if any(x["name"].startswith(c + " ")
                                                           for x in cases)) +
             "; organic: " + ", ".join(c for c in ORGANIC if any(x["name"].startswith(c + " ")
                                                                   for x in cases)) + ".", ""]
    lines += scanner_bench.scanner_tables(cases, results, {}, 0)
    bench.write_between_markers(args.out, MARK_BEGIN, MARK_END, lines)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
