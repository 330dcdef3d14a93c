#!/usr/bin/env python3
"""Scanner noise with ground truth: a clean mesh as a depth camera would measure it, connectivity
kept so that a smoothing result can be scored vertex by vertex against the clean mesh. The model
and why its parameters are plausible: bench/SCANNER_NOISE.md.

Each vertex is seen by the camera (of `views` cameras on a turntable ring) that faces it most
directly; its depth along that camera's optical axis is measured with
  - axial noise of std  level x mean edge x (z / z_ref)^2 x incidence(theta)  (quadratic in depth,
    Khoshelham & Elberink 2012; Nguyen, Izadi & Lovell 2012 for the incidence-angle term),
  - spatially correlated: white noise smoothed by `corr_steps` graph-Laplacian steps and
    renormalised, mixed with a `white` share of per-vertex noise,
  - quantised in disparity (depth steps growing as z^2, like a structured-light camera's
    sub-pixel disparity steps),
  - plus a few outliers (flying pixels), preferably at grazing incidence;
and the vertex moves along its camera ray to the measured depth.

    python3 bench/scanner_noise.py CLEAN OUT.ply --level 0.3 [--views 2] [--seed 1] [...]
    python3 bench/scanner_noise.py --cases DIR     # the benchmark's cases (bench/scanner_bench.py)

numpy only; seeded and deterministic (numpy's PCG64).
"""
import argparse
import json
import math
import pathlib
import sys
import tarfile
import zlib

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import meshio  # noqa: E402
import noref  # noqa: E402
from noref import mean_edge_length, unique_edges as edges_of, vertex_normals  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared" / "data"
CGAL_DATA = pathlib.Path("/usr/share/doc/libcgal-demo/data.tar.gz")

# Defaults of the model (bench/SCANNER_NOISE.md gives the source of each).
DEFAULTS = dict(
    views=2,            # cameras on a ring around the object (2: front and back)
    elevation=25.0,     # degrees above the ring's plane
    distance=2.0,       # camera to bounding-box centre, in bbox diagonals
    corr_steps=6,       # graph-Laplacian smoothing steps of the correlated part
    white=0.1,          # share of the variance that is per-vertex (uncorrelated)
    broad=0.0,          # share correlated over broad_steps steps (the "red" set-ups: 0.45)
    broad_steps=50,
    quant=1.75,         # depth step / noise std at the reference depth (K&E 2012: 7 cm / 4 cm)
    grazing=0.05,       # incidence term weight (Nguyen et al. 2012: 0.1 mm vs 1.9 mm at 1 m)
    max_incidence=75.0, # degrees: beyond, a depth camera returns no data; clipped there
    outliers=0.002,     # share of vertices that are flying pixels
    outlier_sigmas=(4.0, 8.0),  # their depth error, in local noise stds (uniform, random sign)
)


def smooth_field(values, edges, steps):
    """`steps` graph-Laplacian steps x <- (x + mean of the 1-ring) / 2 (uniform weights, so the
    correlation length is in rings, independent of the mesh's scale)."""
    n = len(values)
    deg = np.bincount(edges.ravel(), minlength=n).astype(float)
    x = values.copy()
    for _ in range(steps):
        s = np.bincount(edges[:, 0], x[edges[:, 1]], n) + \
            np.bincount(edges[:, 1], x[edges[:, 0]], n)
        x = 0.5 * x + 0.5 * s / np.maximum(deg, 1)
    return x


def correlated_noise(rng, n, edges, steps, white, broad=0.0, broad_steps=50):
    """Unit-variance noise per vertex: a smoothed (correlated) part, a white part and, with
    `broad` > 0, that share of the variance correlated over `broad_steps` steps (tens of rings: a
    depth camera's calibration-like error, which puts more energy in the coarse bands than in the
    fine ones)."""
    corr = smooth_field(rng.standard_normal(n), edges, steps)
    corr /= max(corr.std(), 1e-300)
    out = math.sqrt(1 - white - broad) * corr + math.sqrt(white) * rng.standard_normal(n)
    if broad > 0:
        wide = smooth_field(rng.standard_normal(n), edges, broad_steps)
        out += math.sqrt(broad) * wide / max(wide.std(), 1e-300)
    return out


def cameras(rng, centre, diag, views, elevation, distance):
    """Camera positions on a ring around a seeded random axis (a turntable), the first azimuth
    random."""
    axis = rng.standard_normal(3)
    axis /= np.linalg.norm(axis)
    e1 = np.cross(axis, [1.0, 0, 0] if abs(axis[0]) < 0.9 else [0, 1.0, 0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    az0 = rng.uniform(0, 2 * math.pi)
    el = math.radians(elevation)
    out = []
    for k in range(views):
        az = az0 + 2 * math.pi * k / views
        d = math.cos(el) * (math.cos(az) * e1 + math.sin(az) * e2) + math.sin(el) * axis
        out.append(centre + distance * diag * d)
    return np.array(out)


def scanner_noise(points, faces, level, seed, details=False, **params):
    """(noisy points, info): the model of the module doc. `level`: the noise std at the reference
    depth (the bounding box centre's) and head-on incidence, in mean edge lengths. info: the
    parameters and figures (JSON-ready); with `details`, also per-vertex numpy arrays: the camera
    index `view`, `depth` (clean) and `measured` depth along its optical axis, `sigma`, `outlier`
    (bool), and `optical_axes`, `disparity_step`."""
    p = dict(DEFAULTS, **params)
    points = np.asarray(points, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    n = len(points)
    rng = np.random.default_rng(seed)
    edges = edges_of(faces)
    mean_edge = mean_edge_length(points, faces)
    lo, hi = points.min(0), points.max(0)
    centre, diag = 0.5 * (lo + hi), float(np.linalg.norm(hi - lo))
    cams = cameras(rng, centre, diag, p["views"], p["elevation"], p["distance"])
    normals = vertex_normals(points, faces)

    # each vertex is measured by the camera that sees it most head-on
    to_cam = cams[None, :, :] - points[:, None, :]                       # (n, views, 3)
    to_cam /= np.linalg.norm(to_cam, axis=2, keepdims=True)
    cos_inc = np.einsum("nvk,nk->nv", to_cam, normals)
    view = np.argmax(cos_inc, axis=1)
    cos_inc = cos_inc[np.arange(n), view]
    theta = np.minimum(np.arccos(np.clip(cos_inc, -1, 1)), math.radians(p["max_incidence"]))
    cam = cams[view]
    optical_axis = (centre - cams) / np.linalg.norm(centre - cams, axis=1, keepdims=True)
    z = np.einsum("nk,nk->n", points - cam, optical_axis[view])          # depth along the axis
    z_ref = p["distance"] * diag

    incidence = 1 + p["grazing"] * theta ** 2 / (math.pi / 2 - theta) ** 2
    sigma = level * mean_edge * (z / z_ref) ** 2 * incidence
    # one noise field per camera: a vertex takes its camera's (seams between views, as in a
    # multi-view scan)
    fields = np.stack([correlated_noise(rng, n, edges, p["corr_steps"], p["white"], p["broad"],
                                        p["broad_steps"])
                       for _ in range(p["views"])], axis=1)
    measured = z + sigma * fields[np.arange(n), view]

    # disparity quantisation: steps of 1/z uniform, so depth steps grow as z^2 and equal
    # quant x level x mean edge at the reference depth
    step = p["quant"] * level * mean_edge
    du = None
    if step > 0:
        du = step / z_ref ** 2
        measured = 1.0 / (np.maximum(np.round(1.0 / (measured * du)), 1) * du)

    # flying pixels: a few vertices far off along their ray, more likely at grazing incidence
    count = int(round(p["outliers"] * n))
    chosen = np.array([], dtype=np.int64)
    if count > 0:
        weight = 0.1 + np.sin(theta)
        chosen = rng.choice(n, size=count, replace=False, p=weight / weight.sum())
        lo_s, hi_s = p["outlier_sigmas"]
        sign = rng.choice([-1.0, 1.0], size=count)
        measured[chosen] += sign * rng.uniform(lo_s, hi_s, size=count) * sigma[chosen]

    noisy = cam + (points - cam) * (measured / z)[:, None]               # along the camera ray
    moved = np.linalg.norm(noisy - points, axis=1)
    info = {"vertices": n, "mean_edge": mean_edge, "level": level, "seed": seed,
            "cameras": cams.tolist(),
            "params": {k: list(v) if isinstance(v, tuple) else v for k, v in p.items()},
            "vertices_per_view": np.bincount(view, minlength=p["views"]).tolist(),
            "sigma_over_edge": {"min": float(sigma.min() / mean_edge),
                                "median": float(np.median(sigma) / mean_edge),
                                "max": float(sigma.max() / mean_edge)},
            "rms_displacement_edges": float(np.sqrt(np.mean(moved ** 2)) / mean_edge),
            "outliers": int(count)}
    if details:
        outlier = np.zeros(n, dtype=bool)
        outlier[chosen] = True
        info.update(view=view, depth=z, measured=measured, sigma=sigma, outlier=outlier,
                    optical_axes=optical_axis, disparity_step=du if step > 0 else None)
    return noisy, info


# --------------------------------------------------------------------------------------------
# The benchmark's cases

# Clean meshes (none chosen for this model): three of the denoising literature's clean CAD models
# (flat and curved) and its Bunny (shared/data/benchmark), the paper's cow, and the largest of the
# libcgal-demo meshes bench/bench.py already uses.
CASE_MESHES = [("Fandisk", "bench", "Fandisk0.3"), ("Block", "bench", "Block0.4"),
               ("SharpSphere", "bench", "SharpSphere0.3"), ("Bunny", "bench", "Bunny0.2"),
               ("cow", "paper", "cow"), ("armadillo", "cgal", "armadillo")]
# (suffix, level in mean edge lengths, overrides): two scanning set-ups per mesh (SCANNER_NOISE.md).
CASE_VARIANTS = [("2views_0.2", 0.2, {"views": 2}), ("4views_0.4", 0.4, {"views": 4})]
CASE_SEED = 20240516


# The heavy set: the levels of a raw depth frame (0.6 and 1 mean edge lengths) on the objects people
# scan with depth cameras (bench/shapes.py's analytic shapes, at 10k vertices) and on two of the
# meshes above, with the model's four-view set-up and a "red" one whose coarse bands carry more
# than its fine ones: more of the variance correlated over 12 steps and a broad share over 200
# (tens of rings), fine disparity steps, fewer outliers (docs/studies/scanner-noise.md).
RED = dict(views=2, quant=0.25, white=0.02, corr_steps=12, broad=0.6, broad_steps=200,
           outliers=0.0005)
HEAVY_SHAPES = ["box", "prism3", "prism6", "cylinder", "cone", "pyramid", "stacked_blocks",
                "bracket"]
HEAVY_MESHES = [("Fandisk", "bench", "Fandisk0.3"), ("Bunny", "bench", "Bunny0.2"),
                ("armadillo", "cgal", "armadillo")]
HEAVY_VARIANTS = [("4views_0.6", 0.6, {"views": 4}), ("4views_1.0", 1.0, {"views": 4}),
                  ("red_0.6", 0.6, RED), ("red_1.0", 1.0, RED)]
HEAVY_SEED = 20261206
SHAPE_VERTICES = 10000


def shape_mesh(name, dest):
    """bench/shapes.py's `name` at SHAPE_VERTICES vertices, made once with the checkout's .venv
    Python (PyMeshLab) and cached in dest."""
    out = pathlib.Path(dest) / f"{name}_{SHAPE_VERTICES}.ply"
    if not out.exists():
        import subprocess
        subprocess.run([str(REPO / ".venv" / "bin" / "python"), str(REPO / "bench" / "shapes.py"),
                        str(dest), "--vertices", str(SHAPE_VERTICES), "--shapes", name],
                       check=True, capture_output=True)
    return out


def make_heavy_cases(dest, shapes=None, meshes=None):
    """The heavy set's cases (noisy.ply beside the clean mesh), made once."""
    dest = pathlib.Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    sources = [(n, shape_mesh(n, dest), f"bench/shapes.py {n}") for n in (shapes or HEAVY_SHAPES)]
    for label, kind, name in (HEAVY_MESHES if meshes is None else meshes):
        clean, note = clean_mesh(kind, name, dest)
        sources.append((label, clean, note))
    cases = []
    for label, clean, note in sources:
        points = faces = None
        for suffix, level, overrides in HEAVY_VARIANTS:
            case = f"{label} {suffix}"
            noisy = dest / f"{label}_{suffix}_noisy.ply"
            if not noisy.exists():
                if points is None:
                    points, faces, _ = meshio.read_mesh(clean)
                seed = (HEAVY_SEED + zlib.crc32(case.encode())) % 2**32
                x, _ = scanner_noise(points, faces, level, seed, **overrides)
                meshio.write_ply(noisy, x, faces)
            cases.append({"name": case, "mesh": label, "variant": suffix, "clean": clean,
                          "noisy": noisy, "note": note})
    return cases


def clean_mesh(kind, name, dest):
    """(path of the clean mesh as a PLY, display note)."""
    if kind == "bench":
        return SHARED / "benchmark" / name / "clean.ply", f"clean {name} (benchmark release)"
    if kind == "paper":
        return SHARED / "paper" / f"{name}.ply", f"the paper's {name}"
    out = dest / f"{name}_clean.ply"
    if not out.exists():
        with tarfile.open(CGAL_DATA) as tar:
            member = tar.getmember(f"data/meshes/{name}.off")
            text = tar.extractfile(member).read()
        tmp = dest / f"{name}.off"
        tmp.write_bytes(text)
        pts, faces = meshio.read_off(tmp)
        tmp.unlink()
        meshio.write_ply(out, pts, faces)
    return out, f"libcgal-demo {name}"


def make_cases(dest, meshes=None):
    """Writes DIR/<mesh>_<variant>/{noisy.ply, info.json} and returns
    [{name, mesh, variant, clean, noisy, note, info}]. Deterministic: the seed is CASE_SEED plus a
    hash of the case name."""
    dest = pathlib.Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    cases = []
    for label, kind, name in CASE_MESHES:
        if meshes and label not in meshes:
            continue
        clean, note = clean_mesh(kind, name, dest)
        pts, faces, _ = meshio.read_mesh(clean)
        for suffix, level, overrides in CASE_VARIANTS:
            case = f"{label} {suffix}"
            d = dest / case.replace(" ", "_")
            d.mkdir(exist_ok=True)
            seed = CASE_SEED + zlib.crc32(case.encode())
            noisy, info = scanner_noise(pts, faces, level, seed, **overrides)
            meshio.write_ply(d / "noisy.ply", noisy, faces)
            (d / "info.json").write_text(json.dumps(info, indent=1))
            cases.append({"name": case, "mesh": label, "variant": suffix, "clean": clean,
                          "noisy": d / "noisy.ply", "note": note, "info": info})
    return cases


# --------------------------------------------------------------------------------------------
# Calibration figures (bench/SCANNER_NOISE.md): the cases next to the real scans

def taubin_lowpass(points, edges, pairs=20, lam=0.5, mu=-0.53):
    """Uniform-weight Taubin smoothing: the low-pass whose residual stands for the noise."""
    n = len(points)
    deg = np.maximum(np.bincount(edges.ravel(), minlength=n), 1).astype(float)[:, None]
    x = points.copy()
    for _ in range(pairs):
        for w in (lam, mu):
            s = np.stack([np.bincount(edges[:, 0], x[edges[:, 1], k], n) +
                          np.bincount(edges[:, 1], x[edges[:, 0], k], n) for k in range(3)], 1)
            x = x + w * (s / deg - x)
    return x


def ring_correlation(values, edges, rings=3, sources=2000, seed=0):
    """Correlation of `values` (zero mean, unit variance) between a vertex and the vertices
    exactly 1..rings edges away (breadth-first search from sampled vertices)."""
    n = len(values)
    a = np.concatenate([edges[:, 0], edges[:, 1]])
    b = np.concatenate([edges[:, 1], edges[:, 0]])
    order = np.argsort(a, kind="stable")
    ptr, adj = np.searchsorted(a[order], np.arange(n + 1)), b[order]
    sums, counts = np.zeros(rings), np.zeros(rings)
    for s in np.random.default_rng(seed).choice(n, min(sources, n), replace=False):
        seen, front = {int(s)}, [int(s)]
        for d in range(rings):
            nxt = [int(w) for v in front for w in adj[ptr[v]:ptr[v + 1]] if int(w) not in seen]
            nxt = list(dict.fromkeys(nxt))
            seen.update(nxt)
            sums[d] += values[s] * values[nxt].sum()
            counts[d] += len(nxt)
            front = nxt
    return sums / np.maximum(counts, 1)


def noise_profile(points, faces):
    """(median dihedral spread in degrees, residual correlation at 1, 2, 3 rings): the residual
    is the displacement from a 20-pair Taubin low-pass along the vertex normals, standardised."""
    edges = edges_of(faces)
    r = np.einsum("ij,ij->i", points - taubin_lowpass(points, edges), vertex_normals(points, faces))
    r = (r - r.mean()) / max(r.std(), 1e-300)
    return noref.median_dihedral_spread_deg(points, faces), ring_correlation(r, edges)


def calibration(dest):
    """Prints the calibration table of bench/SCANNER_NOISE.md."""
    rows = [("real: " + n, SHARED / "real" / f"{n}.ply", None) for n in ("angel", "rabbit", "iron")]
    bunny = SHARED / "benchmark" / "Bunny0.2"
    rows += [("Bunny clean", bunny / "clean.ply", None),
             ("Bunny0.2 (benchmark: white noise along normals)", bunny / "noisy.ply", None)]
    pts, faces, _ = meshio.read_mesh(bunny / "clean.ply")
    variants = [("white only (corr_steps 0, white 1)", dict(corr_steps=0, white=1.0)),
                ("correlated only (white 0)", dict(white=0.0)),
                ("the model's defaults", {})]
    print("| mesh | median dihedral spread (°) | residual correlation at 1 / 2 / 3 rings |")
    print("|---|---|---|")
    for label, path, _ in rows:
        p, f, _ = meshio.read_mesh(path)
        spread, corr = noise_profile(p, f)
        print(f"| {label} | {spread:.1f} | {' / '.join(f'{c:.2f}' for c in corr)} |")
    for level in (0.2, 0.4):
        for label, overrides in variants:
            noisy, _ = scanner_noise(pts, faces, level, CASE_SEED, views=2, **overrides)
            spread, corr = noise_profile(noisy, faces)
            print(f"| Bunny clean + model {level}, 2 views, {label} | {spread:.1f} | "
                  f"{' / '.join(f'{c:.2f}' for c in corr)} |")
    field = correlated_noise(np.random.default_rng(1), len(pts), edges_of(faces),
                             DEFAULTS["corr_steps"], 0.0)
    print(f"\nThe correlated part alone on the Bunny (no low-pass): correlation at 1 / 2 / 3 / 4 "
          f"rings {' / '.join(f'{c:.2f}' for c in ring_correlation(field, edges_of(faces), 4))}")
    if dest:
        print("\n| case | median dihedral spread (°) |\n|---|---|")
        for c in make_cases(dest):
            p, f, _ = meshio.read_mesh(c["noisy"])
            print(f"| {c['name']} | {noref.median_dihedral_spread_deg(p, f):.1f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("clean", nargs="?", help="clean mesh (PLY or OFF)")
    ap.add_argument("out", nargs="?", help="noisy mesh to write (binary PLY, same connectivity)")
    ap.add_argument("--level", type=float, default=0.3,
                    help="noise std at the reference depth, head-on, in mean edge lengths")
    ap.add_argument("--seed", type=int, default=1)
    for key, value in DEFAULTS.items():
        if not isinstance(value, tuple):
            ap.add_argument("--" + key.replace("_", "-"), type=type(value), default=value)
    ap.add_argument("--cases", metavar="DIR", help="write the benchmark's cases into DIR")
    ap.add_argument("--calibration", metavar="DIR", nargs="?", const="",
                    help="print the calibration tables of bench/SCANNER_NOISE.md (with DIR: also "
                         "the cases' spreads, written there)")
    args = ap.parse_args()
    if args.calibration is not None:
        calibration(args.calibration)
        return
    if args.cases:
        for c in make_cases(args.cases):
            print(f"{c['name']}: {c['noisy']} ({c['info']['rms_displacement_edges']:.3f} mean "
                  "edges RMS displacement)")
        return
    if not args.clean or not args.out:
        ap.error("CLEAN and OUT are required (or --cases DIR)")
    pts, faces, _ = meshio.read_mesh(args.clean)
    params = {k: getattr(args, k) for k in DEFAULTS if not isinstance(DEFAULTS[k], tuple)}
    noisy, info = scanner_noise(pts, faces, args.level, args.seed, **params)
    meshio.write_ply(args.out, noisy, faces)
    print(json.dumps(info))


if __name__ == "__main__":
    main()
