#!/usr/bin/env python3
"""The amplitude's part of the noise decision (analysis/noise_estimate.h, amplitude_noisy) checked on
meshes its threshold was not fitted on.

- Clean meshes: every clean mesh the benchmark holds (the public ones, the paper's, and those
  bench/studies/method_sweep.py and mode_choice.py made under bench/out), read with
  `noise_probe --amplitude-always`: how many the amplitude would make noisy, and the highest
  trimmed readings (the threshold must stay above them).
- Noisy meshes: the mode-choice set's clean meshes of at least 4096 vertices that
  bench/studies/noise_truth.py does not use, under noise along the normals correlated over 4 and
  10 smoothing steps at 0.3 and 0.6 mean edge lengths (noise_truth.py's model, seeded): how many
  read noisy by the pair's test alone (`--amplitude-noisy 0`) and now, the amplitude within
  0.7-1.3 of the truth, and θ of the default's output (tools/auto_params) on the meshes that only
  the amplitude reads noisy, against the noisy input (what the pair's test alone leaves).

    python3 bench/studies/noise_decision.py [--build build]

Needs the mode-choice meshes (`python3 bench/studies/mode_choice.py --work bench/out/sweep/mc`
once) and the sweep's cases (any `bench/studies/method_sweep.py` run). About three minutes on two
cores. Writes bench/out/studies/NOISE_DECISION.md.
"""
import argparse
import glob
import hashlib
import json
import os
import pathlib
import subprocess
import sys
import tarfile
from concurrent.futures import ThreadPoolExecutor

import numpy as np

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),
                str(pathlib.Path(__file__).resolve().parents[1])]
import meshio  # noqa: E402
import noref  # noqa: E402
from noise_truth import CGAL_DATA, MESHES, noise_field, probe  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared" / "data"
OUT = REPO / "bench" / "out" / "studies"
MC = REPO / "bench" / "out" / "sweep" / "mc"
FITTED = {name.lower() for name, _, _ in MESHES} | {"fandisk0.3", "block0.4", "sharpsphere0.3",
                                                    "twelve0.5impulsive", "fandisk"}
SEED = 7


def unique(paths):
    seen = {}
    for p in paths:
        seen.setdefault(hashlib.md5(pathlib.Path(p).read_bytes()).hexdigest(), p)
    return seen


def clean_meshes():
    """The clean meshes the benchmark's studies use (where the threshold was set)."""
    paths = sorted(glob.glob(str(REPO / "bench/out/**/*clean*.ply"), recursive=True))
    paths = [p for p in paths if "/runs/" not in p and "noise_decision" not in p and
             not p.endswith("_noisy.ply")]
    paths += sorted(glob.glob(str(SHARED / "benchmark/*/clean.ply")))
    paths += [str(SHARED / "paper" / n) for n in ("cow.ply", "fandisk.ply", "mountain_clean.ply")]
    return sorted(unique(paths).values())


def held_out_clean(work, known):
    """libcgal-demo's triangle meshes of at least 1024 vertices that the studies do not use
    (`known`), and every one of them midpoint-subdivided once (four times the vertices: the
    amplitude reads meshes from 4096)."""
    known_digests = set(unique(known))
    known_names = {os.path.basename(p).split(" ")[0].replace("_clean.ply", "").lower()
                   for p in known}
    out = []
    with tarfile.open(CGAL_DATA) as tar:
        names = sorted(m.name for m in tar.getmembers()
                       if m.name.startswith("data/meshes/") and m.name.endswith(".off"))
        for name in names:
            stem = pathlib.Path(name).stem
            try:
                (work / f"{stem}.off").write_bytes(tar.extractfile(name).read())
                points, faces = meshio.read_off(work / f"{stem}.off")
            except Exception:  # polygons, empty or unreadable: not a triangle mesh
                continue
            if len(points) < 1024 or len(faces) == 0:
                continue
            versions = [(stem + " x4", meshio.midpoint_subdivide(points, faces))]
            if stem.lower() not in known_names:  # the studies' meshes themselves are not held out
                versions.insert(0, (stem, (points, faces)))
            for label, (pts, f) in versions:
                path = work / f"clean_{label.replace(' ', '_')}.ply"
                meshio.write_ply(path, pts, f)
                if len(pts) >= 4096 and hashlib.md5(path.read_bytes()).hexdigest() not in known_digests:
                    out.append(str(path))
    return out


def held_out_cases(work):
    cases = []
    for digest, path in sorted(unique(sorted(glob.glob(str(MC / "*_clean.ply")))).items(),
                               key=lambda kv: kv[1]):
        name = os.path.basename(path).split(" ")[0].replace("_clean.ply", "")
        if name.lower() in FITTED:
            continue
        points, faces, _ = meshio.read_mesh(path)
        if len(points) < 4096:
            continue
        edges = noref.unique_edges(faces)
        normals = noref.vertex_normals(points, faces)
        h = noref.mean_edge_length(points, faces)
        for steps in (4, 10):
            for level in (0.3, 0.6):
                rng = np.random.default_rng([SEED, steps, int(level * 1000), len(points)])
                g = noise_field(rng, len(points), edges, steps, level, False)
                out = work / f"{digest[:6]}_{name}_s{steps}_l{level}.ply"
                if not out.exists():
                    meshio.write_ply(out, points + (g * h)[:, None] * normals, faces)
                cases.append(dict(path=str(out), clean=path, name=f"{name} s{steps} {level}",
                                  truth=float(np.sqrt(np.mean(g ** 2)))))
    return cases


def theta(build, case, work):
    """θ of the noisy input, of the default's output, and of the output at strength 2 (Iterations
    6), with the mode that ran."""
    def run(out, *knobs):
        r = subprocess.run([str(build / "tools" / "auto_params"), case["path"], str(out), *knobs],
                           capture_output=True, text=True, check=True,
                           env=dict(os.environ, OMP_NUM_THREADS="1"))
        return json.loads(r.stdout.strip().splitlines()[-1]).get("mode", "?")

    def score(path):
        r = subprocess.run([str(build / "tools" / "mesh_compare"), str(path), case["clean"]],
                           capture_output=True, text=True, check=True)
        return json.loads(r.stdout)["theta_deg"]
    out = work / ("out_" + os.path.basename(case["path"]))
    mode = run(out)
    default = score(out)
    run(out, "strength=2")
    return score(case["path"]), default, score(out), mode


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.environ.get("SBS_BUILD_DIR", str(REPO / "build")))
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    build = pathlib.Path(args.build)
    if not MC.exists():
        sys.exit(f"{MC} missing: python3 bench/studies/mode_choice.py --work {MC} first")
    work = OUT / "noise_decision"
    work.mkdir(parents=True, exist_ok=True)

    lines = ["# The amplitude's part of the noise decision, checked on meshes it was not fitted on",
             "", "Produced by `python3 bench/studies/noise_decision.py`. Do not edit by hand.", ""]
    fitted = clean_meshes()
    for title, clean in ((f"The studies' clean meshes ({len(fitted)}; the threshold was set above "
                          "their readings)", fitted),
                         ("libcgal-demo's other meshes, and each subdivided once (held out)",
                          held_out_clean(work, fitted))):
        read = probe(build, clean, args.jobs, ["--amplitude-always"])
        lines += [f"## {title}", "",
                  f"{len(clean)} meshes of at least 4096 vertices; read noisy by the amplitude: "
                  f"{sum(read[p]['noisy_by_amplitude'] for p in clean)}. The highest trimmed "
                  "readings (`noise_probe --amplitude-always`):", "",
                  "| mesh | trimmed | amplitude | noisy by the pair's test |", "|---|---|---|---|"]
        for p in sorted(clean, key=lambda p: -read[p]["trimmed_amplitude"])[:8]:
            r = read[p]
            lines.append(f"| {os.path.basename(p)} | {r['trimmed_amplitude']:.3f} | "
                         f"{r['amplitude']:.3f} | "
                         f"{'yes' if r['noisy'] and not r['noisy_by_amplitude'] else 'no'} |")
        lines.append("")

    cases = held_out_cases(work)
    paths = [c["path"] for c in cases]
    now = probe(build, paths, args.jobs)
    pair = probe(build, paths, args.jobs, ["--amplitude-noisy", "0"])
    within = lambda reads: sum(0.7 <= reads[c["path"]]["amplitude"] / c["truth"] <= 1.3 for c in cases)
    newly = [c for c in cases if now[c["path"]]["noisy"] and not pair[c["path"]]["noisy"]]
    with ThreadPoolExecutor(args.jobs) as ex:
        thetas = list(ex.map(lambda c: theta(build, c, work), newly))
    ratios = [after / before for before, after, _, _ in thetas]
    organic = [t for t in thetas if t[3] == "O"]
    lines += [f"## Correlated noise on {len(cases) // 4} held-out meshes ({len(cases)} cases)", "",
              f"- read noisy: {sum(pair[p]['noisy'] for p in paths)} by the pair's test alone, "
              f"{sum(now[p]['noisy'] for p in paths)} now;",
              f"- amplitude within 0.7-1.3 of the truth: {within(pair)} before, {within(now)} now;",
              f"- θ on the {len(newly)} the amplitude alone reads noisy: mean ratio to the noisy "
              f"input {np.mean(ratios) if ratios else float('nan'):.3f}, "
              f"{sum(r > 1.0 for r in ratios)} higher;",
              f"- the {len(organic)} of them in the organic mode at strength 2 (Iterations 6): mean "
              f"ratio to the default's θ "
              f"{np.mean([s2 / d for _, d, s2, _ in organic]) if organic else float('nan'):.3f}.",
              "", "| case | mode | θ noisy | θ default | θ strength 2 | amplitude | trimmed | truth |",
              "|---|---|---|---|---|---|---|---|"]
    for c, (before, after, stronger, mode) in zip(newly, thetas):
        r = now[c["path"]]
        lines.append(f"| {c['name']} | {mode} | {before:.2f} | {after:.2f} | {stronger:.2f} | "
                     f"{r['amplitude']:.3f} | {r['trimmed_amplitude']:.3f} | {c['truth']:.2f} |")
    text = "\n".join(lines) + "\n"
    (OUT / "NOISE_DECISION.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
