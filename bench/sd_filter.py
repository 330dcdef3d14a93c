"""The SD filter as a benchmark peer: Zhang, Deng, Hong, Peng, Qin, Liu, *Static/Dynamic Filtering
for Mesh Geometry* (IEEE TVCG 2019), the denoiser Meshroom/AliceVision ships, from Debian's
`meshsdfilter-tools` (`MeshDenoiser OPTIONS_FILE IN OUT`, OpenMesh I/O, OpenMP).

The package ships no options file: DEFAULT holds the values of `DenoisingOptions.txt` in its
source (Debian source package meshsdfilter 1.0+1gitb81411, the authors' file). SWEEP is the small
grid whose best setting per case (lowest theta against the clean mesh: an oracle, like MeshLab's
best) is reported beside the defaults; bench/README.md says why these values.

Vertex order: MeshDenoiser writes the input's vertices in their order, but OpenMesh refuses faces
that would make a complex (non-manifold) edge and adds each as a separate triangle on copies of its
three vertices, appended after the input's (the paper cow: 4 faces, 12 copies). `run` checks that
every other face is the input's, drops the copies and writes the input's faces on the first n
vertices, so that the result scores vertex by vertex; the count of such faces is in the result.
"""
import os
import pathlib
import re
import shutil
import subprocess
import time

import numpy as np

import meshio

BINARY = "MeshDenoiser"
PACKAGE = "meshsdfilter-tools"
# DenoisingOptions.txt of meshsdfilter 1.0+1gitb81411, in its order.
DEFAULT = {"Lambda": 2, "Eta": 1.5, "Mu": 1.5, "Nu": 0.3, "MeshUpdateClosenessWeight": 0.001,
           "MeshUpdateIterations": 20, "OuterIterations": 5}
# Lambda (regularisation weight: more = smoother) x (Eta: spatial Gaussian in mean face-centroid
# distances; Nu: the normals' range Gaussian, more = smooths across larger normal differences).
# Chosen on trial runs (bench/README.md): the defaults over-smooth dense meshes (Bunny0.2 13.4 deg
# vs Taubin's 6.3), their best theta came at Lambda 0.3-1 with Eta 0.75, Nu 0.3-0.45, stronger
# noise wants a larger Lambda; Eta above 1.5 was worse and several times slower everywhere tried.
SWEEP = [{"Lambda": lam, "Eta": eta, "Nu": nu} for lam in (0.25, 1, 4)
         for eta, nu in ((0.75, 0.3), (0.75, 0.45), (1.5, 0.3))]


class SDError(RuntimeError):
    pass


def available():
    return shutil.which(BINARY) is not None


def full(setting):
    return dict(DEFAULT, **(setting or {}))


def setting_text(setting):
    """'defaults' or the values that differ from them, e.g. 'Lambda 0.5, Eta 0.75'."""
    diff = [f"{k} {v:g}" for k, v in full(setting).items() if v != DEFAULT[k]]
    return ", ".join(diff) if diff else "defaults"


def defaults_text():
    return ", ".join(f"{k} {v:g}" for k, v in DEFAULT.items())


def options_text(setting):
    return "".join(f"{k} {v:g}\n" for k, v in full(setting).items())


def options_file(folder, setting):
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    name = "sd_" + re.sub(r"[^A-Za-z0-9.]+", "_", setting_text(setting)) + ".txt"
    path = folder / name
    if not path.exists():
        path.write_text(options_text(setting))
    return path


def restore_order(raw_off, src_faces, n, out_ply):
    """Writes `out_ply` with the input's faces on MeshDenoiser's first n vertices; returns the
    number of faces OpenMesh had split off (see the module doc)."""
    points, faces = meshio.read_off(raw_off)
    if len(points) < n or len(faces) != len(src_faces):
        raise SDError(f"{raw_off}: {len(points)} vertices / {len(faces)} faces, input "
                      f"{n} / {len(src_faces)}")
    split = np.any(faces >= n, axis=1)
    same = np.zeros(len(faces), dtype=bool)
    for r in range(3):
        same |= np.all(np.roll(faces, r, axis=1) == src_faces, axis=1)
    if not np.all(same | split):
        raise SDError(f"{raw_off}: {int((~(same | split)).sum())} faces differ from the input's")
    meshio.write_ply(out_ply, points[:n], src_faces)
    return int(split.sum())


def run(src, out, setting=None, options_dir=None, threads=None, timed=False, timeout=3600):
    """Runs MeshDenoiser on `src` and writes `out` (binary PLY, the input's connectivity).
    Returns {wall, rss, filter, split_faces, log}: wall = the whole process (load, filter, save),
    filter = the denoising time it logs, rss = peak MB (timed runs, GNU time)."""
    if not available():
        raise SDError(f"{BINARY} not found: apt-get install {PACKAGE}")
    out = pathlib.Path(out)
    opts = options_file(options_dir or out.parent, setting)
    raw = out.with_suffix(".sd.off")
    cmd = [BINARY, str(opts), str(src), str(raw)]
    rss_file = out.with_suffix(".time.txt")
    if timed:
        cmd = ["/usr/bin/time", "-v", "-o", str(rss_file)] + cmd
    env = dict(os.environ)
    if threads:
        env["OMP_NUM_THREADS"] = str(threads)
    if raw.exists():
        raw.unlink()
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    wall = time.perf_counter() - start
    text = proc.stdout + proc.stderr
    if proc.returncode != 0 or not raw.exists():
        raise SDError(f"MeshDenoiser {src} ({setting_text(setting)}) failed "
                      f"(rc {proc.returncode}): {text[-800:]}")
    rss = None
    if timed and rss_file.exists():
        m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", rss_file.read_text())
        rss = int(m.group(1)) / 1024.0 if m else None
        rss_file.unlink()
    m = re.search(r"Denoising completed, timing: ([\d.eE+-]+)", text)
    src_points, src_faces, _ = meshio.read_mesh(src)
    split = restore_order(raw, src_faces, len(src_points), out)
    raw.unlink()
    return {"wall": wall, "rss": rss, "filter": float(m.group(1)) if m else None,
            "split_faces": split, "log": text}
