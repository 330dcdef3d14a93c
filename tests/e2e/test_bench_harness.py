"""The benchmark harness's own building blocks (bench/): the scanner-noise model, the SD filter's
vertex-order repair and the no-reference figures, against answers known in closed form. numpy only;
no meshlabserver, no MeshDenoiser."""
import math
import sys

import numpy as np
import pytest

from conftest import REPO

sys.path.insert(0, str(REPO / "bench"))
import meshio  # noqa: E402
import noref  # noqa: E402
import scanner_noise  # noqa: E402
import sd_filter  # noqa: E402


def grid(n=40, spacing=1.0):
    """A flat n x n vertex grid in the z = 0 plane, two triangles per square."""
    xs, ys = np.meshgrid(np.arange(n) * spacing, np.arange(n) * spacing)
    points = np.stack([xs.ravel(), ys.ravel(), np.zeros(n * n)], axis=1)
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    faces = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])
    return points, faces


def octahedron():
    points = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    faces = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4],
                      [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    return points, faces


def test_scanner_noise_is_deterministic_per_seed():
    points, faces = grid(30)
    a, _ = scanner_noise.scanner_noise(points, faces, 0.3, 7)
    b, _ = scanner_noise.scanner_noise(points, faces, 0.3, 7)
    c, _ = scanner_noise.scanner_noise(points, faces, 0.3, 8)
    assert a.shape == points.shape
    assert np.array_equal(a, b)
    assert not np.allclose(a, c)


def test_scanner_noise_moves_vertices_along_their_camera_rays():
    points, faces = grid(30)
    noisy, info = scanner_noise.scanner_noise(points, faces, 0.3, 3, details=True, views=4)
    cams = np.array(info["cameras"])[info["view"]]
    ray = points - cams
    move = noisy - points
    cross = np.linalg.norm(np.cross(move, ray), axis=1) / np.linalg.norm(ray, axis=1)
    assert cross.max() < 1e-9 * np.linalg.norm(ray, axis=1).max()
    assert np.linalg.norm(move, axis=1).max() > 0


def test_depth_error_has_the_modelled_std():
    # white noise only, no quantisation or outliers: the depth error divided by the modelled sigma
    # is standard normal; sigma at the reference depth head-on is level x mean edge
    points, faces = grid(60)
    level = 0.3
    _, info = scanner_noise.scanner_noise(points, faces, level, 5, details=True, views=1,
                                          white=1.0, quant=0.0, outliers=0.0, grazing=0.0)
    err = (info["measured"] - info["depth"]) / info["sigma"]
    assert abs(err.std() - 1) < 0.05 and abs(err.mean()) < 0.05
    z_ref = scanner_noise.DEFAULTS["distance"] * np.linalg.norm(points.max(0) - points.min(0))
    expected = level * info["mean_edge"] * (info["depth"] / z_ref) ** 2
    assert np.allclose(info["sigma"], expected, rtol=1e-12)


def test_correlated_field_is_correlated_over_a_few_rings():
    points, faces = grid(60)
    edges = scanner_noise.edges_of(faces)
    field = scanner_noise.correlated_noise(np.random.default_rng(1), len(points), edges, 6, 0.0)
    assert abs(field.std() - 1) < 1e-12
    corr = scanner_noise.ring_correlation(field, edges, rings=4)
    assert corr[0] > 0.7 and corr[1] > 0.4 and corr[3] < 0.2  # falls off over a few rings


def test_measured_depths_lie_on_the_disparity_grid():
    points, faces = grid(40)
    _, info = scanner_noise.scanner_noise(points, faces, 0.3, 9, details=True, views=2)
    keep = ~info["outlier"]
    k = 1.0 / (info["measured"][keep] * info["disparity_step"])
    assert np.allclose(k, np.round(k), atol=1e-6)
    assert info["outlier"].sum() == round(scanner_noise.DEFAULTS["outliers"] * len(points))


def test_sd_restore_order_drops_split_face_copies(tmp_path):
    points, faces = octahedron()
    moved = points * 0.9
    # OpenMesh's output: face 3 split off onto copies 6, 7, 8 of its vertices 3, 0, 4
    copies = moved[[3, 0, 4]] + 0.5
    out_faces = faces.copy()
    out_faces[3] = [6, 7, 8]
    out_faces[5] = np.roll(out_faces[5], 1)  # a face may start at another corner
    raw = tmp_path / "raw.off"
    raw.write_text("OFF\n9 8 0\n" + "".join(f"{x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in
                                             np.concatenate([moved, copies])) +
                   "".join(f"3 {a} {b} {c}\n" for a, b, c in out_faces))
    out = tmp_path / "out.ply"
    assert sd_filter.restore_order(raw, faces, 6, out) == 1
    p, f, _ = meshio.read_mesh(out)
    assert np.array_equal(f, faces)
    assert np.allclose(p, moved, atol=1e-6)
    out_faces[1] = [1, 2, 5]  # a face that is not the input's: an error, not a silent mismatch
    raw.write_text("OFF\n9 8 0\n" + "".join(f"{x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in
                                             np.concatenate([moved, copies])) +
                   "".join(f"3 {a} {b} {c}\n" for a, b, c in out_faces))
    with pytest.raises(sd_filter.SDError):
        sd_filter.restore_order(raw, faces, 6, out)


def test_sd_setting_text_and_options():
    assert sd_filter.setting_text({}) == "defaults"
    assert sd_filter.setting_text({"Lambda": 0.25, "Eta": 0.75, "Nu": 0.3}) == "Lambda 0.25, Eta 0.75"
    text = sd_filter.options_text({"Lambda": 4})
    assert "Lambda 4\n" in text and "OuterIterations 5\n" in text and "Eta 1.5\n" in text


def test_dihedral_spread_known_answers():
    points, faces = grid(20)
    assert noref.median_dihedral_spread_deg(points, faces) == pytest.approx(0, abs=1e-9)
    # the octahedron bends by the same angle across every edge: no spread
    points, faces = octahedron()
    assert noref.median_dihedral_spread_deg(points, faces) == pytest.approx(0, abs=1e-9)
    # one interior grid vertex lifted: its faces' three edges bend differently (convex, concave)
    points, faces = grid(5)
    points[12, 2] = 0.5
    assert noref.median_dihedral_spread_deg(points, faces) > 0


def test_displacement_in_mean_edges():
    points, faces = grid(20, spacing=2.0)
    edge = noref.mean_edge_length(points, faces)
    # 760 axis edges of length 2, 361 diagonals of 2 sqrt(2)
    assert edge == pytest.approx((760 * 2 + 361 * 2 * math.sqrt(2)) / 1121)
    normal = noref.vertex_normals(points, faces)[0]
    d = noref.displacement(points, points - 0.5 * edge * normal, faces)
    assert d["mean"] == pytest.approx(0.5) and d["p99"] == pytest.approx(0.5)
    assert d["normal_mean"] == pytest.approx(-0.5)
    assert d["normal"] == pytest.approx(0.5) and d["tangential"] == pytest.approx(0, abs=1e-12)
    # a slide within the plane: no normal part; half the vertices up, half down: signed mean 0
    d = noref.displacement(points, points + [0.3 * edge, 0.4 * edge, 0], faces)
    assert d["mean"] == pytest.approx(0.5) and d["tangential"] == pytest.approx(0.5)
    assert d["normal"] == pytest.approx(0, abs=1e-12)
    sign = np.where(np.arange(len(points)) % 2 == 0, 1.0, -1.0)[:, None]
    d = noref.displacement(points, points + 0.2 * edge * sign * normal, faces)
    assert d["normal"] == pytest.approx(0.2) and d["tangential"] == pytest.approx(0, abs=1e-12)
    assert d["normal_mean"] == pytest.approx(0, abs=1e-12)
