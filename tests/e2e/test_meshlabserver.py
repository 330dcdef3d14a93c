"""End-to-end: the real meshlabserver 2020.09 (private copy, under Xvfb) runs our filters."""
import shutil

import numpy as np
import pytest

from conftest import (BUILD, PRIVATE_MESHLAB, REPO, mesh_compare, read_ply, run_meshlabserver,
                      write_mlx)


def sharp_vertex_mask(vertices, faces, angle_deg=30.0):
    """Vertices on an edge whose two faces' normals differ by more than angle_deg."""
    p = np.stack([vertices["x"], vertices["y"], vertices["z"]], axis=1).astype(np.float64)
    n = np.cross(p[faces[:, 1]] - p[faces[:, 0]], p[faces[:, 2]] - p[faces[:, 0]])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    edges = {}
    for f, tri in enumerate(faces):
        for k in range(3):
            a, b = sorted((tri[k], tri[(k + 1) % 3]))
            edges.setdefault((a, b), []).append(f)
    sharp = np.zeros(len(p), dtype=bool)
    cos_limit = np.cos(np.radians(angle_deg))
    for (a, b), fs in edges.items():
        if len(fs) == 2 and np.dot(n[fs[0]], n[fs[1]]) < cos_limit:
            sharp[a] = sharp[b] = True
    return sharp


def test_compute_saliency_on_fandisk(tmp_path, shared):
    out = tmp_path / "fandisk_saliency.ply"
    run = run_meshlabserver(["-i", shared / "data" / "paper" / "fandisk.ply", "-o", out, "-m", "vq",
                             "-s", REPO / "examples" / "compute_saliency_curvature.mlx"])
    assert run.returncode == 0, run.stdout + run.stderr
    assert out.exists(), run.stdout + run.stderr
    vertices, faces = read_ply(out)
    quality = np.asarray(vertices["quality"], dtype=np.float64)
    assert len(quality) == 6475
    # The display scale: saliency over its 99th percentile, clipped at 1.
    assert quality.min() >= 0.0
    assert quality.max() == pytest.approx(1.0, abs=1e-6)
    assert 0.005 < np.mean(quality >= 1.0 - 1e-6) < 0.02
    sharp = sharp_vertex_mask(vertices, faces)
    assert 100 < sharp.sum() < 3000
    # Saliency marks the creases: on average far above the flat regions.
    assert quality[sharp].mean() > 2.0 * quality[~sharp].mean()
    # Positions are untouched by the inspection filter.
    original, _ = read_ply(shared / "data" / "paper" / "fandisk.ply")
    assert np.array_equal(vertices["x"], original["x"])


def test_saliency_filter_refuses_a_point_cloud(tmp_path):
    cloud = tmp_path / "cloud.ply"
    cloud.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                     "end_header\n0 0 0\n1 0 0\n0 1 0\n")
    out = tmp_path / "cloud_out.ply"
    run = run_meshlabserver(["-i", cloud, "-o", out, "-s",
                             REPO / "examples" / "compute_saliency_curvature.mlx"])
    text = run.stdout + run.stderr
    # No crash (an abort would be 134 / a negative signal), our message in the log, no output.
    assert run.returncode >= 0 and run.returncode != 134, text
    assert "the mesh has no faces (a point cloud)" in text, text
    assert "Problem with filter" in text, text
    assert not out.exists()


def test_smoothing_fandisk_lowers_theta(tmp_path, shared):
    case = shared / "data" / "benchmark" / "Fandisk0.3"
    out = tmp_path / "fandisk_smoothed.ply"
    run = run_meshlabserver(["-i", case / "noisy.ply", "-o", out, "-m", "vq",
                             "-s", REPO / "examples" / "saliency_bezier_smooth.mlx"])
    assert run.returncode == 0, run.stdout + run.stderr
    assert out.exists(), run.stdout + run.stderr
    noisy = mesh_compare(case / "noisy.ply", case / "clean.ply")
    smoothed = mesh_compare(out, case / "clean.ply")
    assert noisy["theta_deg"] == pytest.approx(28.42, abs=0.05)
    assert smoothed["theta_deg"] < 0.5 * noisy["theta_deg"]
    assert smoothed["ev_1e3"] < noisy["ev_1e3"]
    assert abs(smoothed["volume_ratio"] - 1.0) < 0.01



def test_example_scripts_list_every_parameter_at_its_default(tmp_path):
    """examples/*.mlx are tools/write_mlx's output: every parameter, at the current defaults."""
    for kind, name in (("smooth", "saliency_bezier_smooth.mlx"),
                       ("saliency", "compute_saliency_curvature.mlx")):
        generated = write_mlx(tmp_path, kind).read_text()
        assert (REPO / "examples" / name).read_text() == generated, name


def test_a_script_written_before_the_color_parameter_still_runs(tmp_path, shared):
    """meshlabserver 2020.09 fills in one missing parameter of a script only when it is the
    filter's first: scripts written before 'color' existed run, with the same result."""
    case = shared / "data" / "benchmark" / "Fandisk0.3"
    results = []
    for script in (REPO / "tests" / "e2e" / "data" / "saliency_bezier_smooth_before_color.mlx",
                   REPO / "examples" / "saliency_bezier_smooth.mlx"):
        out = tmp_path / (script.stem + ".ply")
        run = run_meshlabserver(["-i", case / "noisy.ply", "-o", out, "-s", script])
        assert run.returncode == 0 and out.exists(), run.stdout + run.stderr
        results.append(out.read_bytes())
    assert results[0] == results[1]


@pytest.mark.parametrize("source", ["clean", "smoothed noisy"])
def test_saliency_map_shows_fandisks_creases_at_default_colour_settings(tmp_path, shared, source):
    """Vertex quality after the analysis filter on the clean Fandisk, and after the smoothing
    filter on the noisy one (its default quality is the result's saliency): MeshLab's colour map
    spreads quality's full range over its colours, so the creases must reach the top half of the
    range and the flat parts stay near the bottom."""
    case = shared / "data" / "benchmark" / "Fandisk0.3"
    out = tmp_path / "quality.ply"
    if source == "clean":
        args = ["-i", case / "clean.ply", "-s", REPO / "examples" / "compute_saliency_curvature.mlx"]
    else:
        args = ["-i", case / "noisy.ply", "-s", REPO / "examples" / "saliency_bezier_smooth.mlx"]
    run = run_meshlabserver(args + ["-o", out, "-m", "vq"])
    assert run.returncode == 0 and out.exists(), run.stdout + run.stderr
    vertices, _ = read_ply(out)
    clean_vertices, faces = read_ply(case / "clean.ply")
    quality = np.asarray(vertices["quality"], dtype=np.float64)
    sharp = sharp_vertex_mask(clean_vertices, faces)
    span = quality.max() - quality.min()
    shown = (quality - quality.min()) / span  # what the default colour map does
    print(f"{source}: median shown value on creases {np.median(shown[sharp]):.3f}, "
          f"elsewhere {np.median(shown[~sharp]):.3f}")
    assert np.median(shown[sharp]) > 0.5, np.median(shown[sharp])
    assert np.median(shown[~sharp]) < 0.2, np.median(shown[~sharp])


def test_write_mlx_takes_labels_keys_and_on_off_and_explains_errors():
    """write_mlx: choices by label, index or method key, booleans by name; a bad value or an
    unknown parameter exits 2 with a message that lists what is allowed, never an abort."""
    import subprocess
    tool = str(BUILD / "tools" / "write_mlx")

    def run(*args):
        return subprocess.run([tool, *args], capture_output=True, text=True)

    by_label = run("smooth", "placement=Organic scan", "preserve_volume=no", "color=on")
    assert by_label.returncode == 0, by_label.stderr
    assert 'name="placement" type="RichEnum" value="4"' in by_label.stdout
    assert 'name="preserve_volume" type="RichBool" value="false"' in by_label.stdout
    assert 'name="color" type="RichBool" value="true"' in by_label.stdout
    assert run("smooth", "placement=organic").stdout == run("smooth", "placement=4").stdout
    bad_choice = run("smooth", "placement=Organix")
    assert bad_choice.returncode == 2
    assert "'placement' is one of 0 = 'Ring barycentre' (ring)" in bad_choice.stderr
    bad_bool = run("smooth", "preserve_volume=maybe")
    assert bad_bool.returncode == 2 and "on or off" in bad_bool.stderr
    bad_int = run("smooth", "iterations=2.5")
    assert bad_int.returncode == 2 and "whole number" in bad_int.stderr
    unknown = run("smooth", "iteration=3")
    assert unknown.returncode == 2 and "newton_step_limit" in unknown.stderr  # lists them all
    usage = run()
    assert usage.returncode == 2
    for name in ("color", "placement", "iterations", "alpha_override", "saliency_scale", "quality"):
        assert f"  {name} (" in usage.stderr
