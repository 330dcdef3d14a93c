"""End-to-end: the result does not depend on the thread count. The real meshlabserver with
OMP_NUM_THREADS=1 and =2 on a mesh above the size from which the stages run in parallel (20k
vertices), for the default (automatic) and each of the two modes it chooses between: the output
files must be the same bytes (positions, and the vertex quality the filter writes)."""
import pathlib
import subprocess
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from conftest import PRIVATE_MESHLAB, meshlab_env, write_mlx  # noqa: E402
from test_memory_limit import noisy_torus, write_ply  # noqa: E402


def smooth(source, out, mlx, threads):
    env = meshlab_env()
    env["OMP_NUM_THREADS"] = str(threads)
    cmd = ["xvfb-run", "-a", str(PRIVATE_MESHLAB / "meshlabserver"), "-i", str(source), "-o",
           str(out), "-m", "vq", "-s", str(mlx)]
    run = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0 and out.exists(), run.stdout[-2000:] + run.stderr[-2000:]
    return out.read_bytes()


def test_one_and_two_threads_give_the_same_bytes(tmp_path):
    source = tmp_path / "torus.ply"
    points, faces = noisy_torus(major=300, minor=150, seed=4)  # 45,000 vertices
    # Noise of a fifth of the mean edge length, so that every mode has something to do.
    edge = np.linalg.norm(points[faces[:, 0]] - points[faces[:, 1]], axis=1).mean()
    points = points + (0.2 * edge * np.random.default_rng(7).normal(size=points.shape)).astype("<f4")
    write_ply(source, points, faces)
    for name, overrides in (("automatic", []), ("feature", ["placement=feature"]),
                            ("organic", ["placement=organic"])):
        mlx = write_mlx(tmp_path, "smooth", *overrides)
        one = smooth(source, tmp_path / f"{name}_1.ply", mlx, 1)
        two = smooth(source, tmp_path / f"{name}_2.ply", mlx, 2)
        assert one == two, f"{name}: 1 and 2 threads differ"
        assert one != source.read_bytes()
