#!/usr/bin/env python3
"""The automatic mode's choice on large meshes, none of which its thresholds were fitted on:
organic and CAD meshes subdivided at their edge midpoints to 0.4-1.7M vertices, with noise. For
each: the chosen mode, its flat share (on meshes of 450k faces and more it compares faces several
edges apart, vcg_ext/methods/automatic/mode_choice.h), and θ / Ev of the automatic, feature and organic modes
against the subdivided clean mesh; with --old, the automatic mode of another build beside it.
Writes docs/studies/mode-choice.md.

    python3 bench/studies/large_mode_choice.py [--build build] [--old OTHER_BUILD]

About 5 minutes on two cores (10 with --old). Needs libcgal-demo (apt-get install libcgal-demo).
"""
import argparse
import datetime
import json
import pathlib
import re
import subprocess
import sys
import tarfile

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import meshio  # noqa: E402
(pathlib.Path(__file__).resolve().parents[1] / "out" / "studies").mkdir(parents=True, exist_ok=True)

REPO = pathlib.Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared" / "data" / "benchmark"
CGAL_DATA = pathlib.Path("/usr/share/doc/libcgal-demo/data.tar.gz")
WORK = REPO / "bench" / "out" / "large_mode_choice"
SEED = 20090601
# (name, source, midpoint subdivisions, noise level in mean edge lengths, direction, kind)
MESHES = [
    ("armadillo", "cgal", 3, 0.2, "normal", "organic"),
    ("lion-head", "cgal", 3, 0.2, "random", "organic"),
    ("Fandisk", "Fandisk0.3", 3, 0.2, "random", "CAD"),
    ("Fandisk", "Fandisk0.3", 4, 0.2, "random", "CAD"),
    ("Block", "Block0.4", 3, 0.2, "random", "CAD"),
]


def clean_mesh(name, source):
    if source == "cgal":
        off = WORK / "cgal" / f"{name}.off"
        if not off.exists():
            off.parent.mkdir(parents=True, exist_ok=True)
            with tarfile.open(CGAL_DATA) as tar:
                member = next(m for m in tar.getmembers()
                              if m.name.endswith(f"meshes/{name}.off"))
                member.name = off.name
                tar.extract(member, off.parent)
        return meshio.read_off(off)
    points, faces, _ = meshio.read_mesh(SHARED / source / "clean.ply")
    return points, faces


def make(build, name, source, levels, level, direction):
    stem = f"{name}_x{levels}_{direction[0]}{level}"
    clean, noisy = WORK / f"{stem}_clean.ply", WORK / f"{stem}.ply"
    if not noisy.exists():
        points, faces = clean_mesh(name, source)
        for _ in range(levels):
            points, faces = meshio.midpoint_subdivide(points, faces)
        meshio.write_ply(clean, points, faces)
        subprocess.run([str(build / "tools" / "add_noise"), str(clean), str(noisy), str(level),
                        direction, str(SEED)], check=True, capture_output=True)
    return stem, clean, noisy


def score(build, noisy, clean, mode, scorer):
    """`build`'s auto_params in `mode`, scored by `scorer`'s mesh_compare."""
    out = WORK / "out.ply"
    log = subprocess.run([str(build / "tools" / "auto_params"), str(noisy), str(out),
                          f"mode={mode}"], check=True, capture_output=True, text=True)
    fields = json.loads(next(line for line in (log.stdout + log.stderr).splitlines()
                             if line.startswith("{")))
    quality = json.loads(subprocess.run([str(scorer / "tools" / "mesh_compare"), str(out),
                                         str(clean)], check=True, capture_output=True,
                                        text=True).stdout)
    return dict(mode=fields["mode"], flat=fields["flat_share"], theta=quality["theta_deg"],
                ev=quality["ev_1e3"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", type=pathlib.Path, default=REPO / "build")
    ap.add_argument("--old", type=pathlib.Path, help="another build: its automatic mode beside")
    ap.add_argument("--out", type=pathlib.Path, default=REPO / "bench" / "out" / "studies" / "LARGE_MODE_CHOICE.md")
    args = ap.parse_args()
    WORK.mkdir(parents=True, exist_ok=True)
    rows = []
    for name, source, levels, level, direction, kind in MESHES:
        stem, clean, noisy = make(args.build, name, source, levels, level, direction)
        vertices = int(re.search(rb"element vertex (\d+)", noisy.read_bytes()[:400]).group(1))
        r = {m: score(args.build, noisy, clean, m, args.build) for m in ("auto", "feature", "organic")}
        if args.old:
            r["old"] = score(args.old, noisy, clean, "auto", args.build)
        rows.append((stem, kind, vertices, r))
        print(stem, json.dumps(r), flush=True)
    cmd = "python3 bench/studies/large_mode_choice.py" + (" --old OTHER_BUILD" if args.old else "")
    lines = [
        "# The automatic choice on large meshes",
        "",
        f"Produced by `{cmd}` on {datetime.date.today()}. Meshes none of the thresholds were "
        "fitted on: libcgal-demo's armadillo and lion head and the benchmark's clean Fandisk and "
        "Block, subdivided at their edge midpoints, with noise (tools/add_noise, mean edge "
        "lengths, along the normals or in random directions). θ in degrees / Ev ×1e-3 against "
        "the subdivided clean mesh; chosen: F feature-preserving, O organic; flat share as the "
        "automatic mode measures it.",
        "",
        "| mesh | kind | vertices | chosen (flat share) | automatic | feature | organic |"
        + (" other build's automatic: chosen (flat share), θ / Ev |" if args.old else ""),
        "|---|---|---:|---|---|---|---|" + ("---|" if args.old else ""),
    ]
    for stem, kind, vertices, r in rows:
        cells = [f"{r[m]['theta']:.2f} / {r[m]['ev']:.3f}" for m in ("auto", "feature", "organic")]
        line = (f"| {stem} | {kind} | {vertices:,} | {r['auto']['mode']} ({r['auto']['flat']:.3f}) | "
                + " | ".join(cells) + " |")
        if args.old:
            o = r["old"]
            line += f" {o['mode']} ({o['flat']:.3f}), {o['theta']:.2f} / {o['ev']:.3f} |"
        lines.append(line)
    args.out.write_text("\n".join(lines) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
