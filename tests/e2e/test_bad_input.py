"""End-to-end: the worst of the bad-input catalogue (tests/unit/test_bad_input.cpp) through the real
meshlabserver 2020.09 (float meshes) and PyMeshLab 2025.07 (double meshes): no crash, our message
where the filters refuse, the mesh unchanged then, finite results otherwise.

The PyMeshLab cases run one per process (this file run as a script with the case's name): a crash
then fails that one case, and pymeshlab's dangling static logger after an exception
(test_pymeshlab.py's docstring) cannot leak into the other tests.
"""
import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from conftest import BUILD, read_ply, run_meshlabserver, write_mlx  # noqa: E402

SMOOTH = "apply_coord_saliency_bezier_smoothing"
ANALYSE = "compute_scalar_by_mesh_saliency_per_vertex"


# ---------------------------------------------------------------------------------------------
# Meshes (numpy) and PLY files


def noisy_grid(n=12, sigma=0.01, seed=5):
    """An n x n grid over [0,1]^2 with noise along z; vertices row by row."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    points = np.stack([x.ravel(), y.ravel(), rng.normal(0, sigma, n * n)], axis=1)
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            faces += [[a, a + 1, a + n + 1], [a, a + n + 1, a + n]]
    return points, np.array(faces, dtype=np.int64)


def with_defects(points, faces, n=12):
    """The grid plus a fin on an interior edge (non-manifold edge), a second fan touching one
    interior vertex (non-manifold vertex), a face with a repeated index and an unreferenced vertex.
    Returns points, faces and the indices of the non-manifold vertices (the repeated index gives
    its edge a third and fourth face: non-manifold too)."""
    a, b = 5 * n + 5, 5 * n + 6
    apex = 8 * n + 3
    p = len(points)
    extra = [[(points[a][0] + points[b][0]) / 2, points[a][1], 0.3],
             [points[apex][0] - 0.05, points[apex][1] + 0.05, 0.2],
             [points[apex][0], points[apex][1] + 0.08, 0.25],
             [points[apex][0] + 0.05, points[apex][1] + 0.05, 0.2],
             [5.0, 5.0, 5.0]]
    more_faces = [[a, b, p], [apex, p + 1, p + 2], [apex, p + 2, p + 3], [2 * n + 2, 2 * n + 3, 2 * n + 3]]
    return (np.vstack([points, extra]), np.vstack([faces, more_faces]),
            [a, b, apex, 2 * n + 2, 2 * n + 3])


def write_ply(path, points, faces, dtype="<f4"):
    """Binary little-endian PLY; `faces` is a list of index lists (any polygon size)."""
    points = np.asarray(points)
    kind = {"<f4": "float", "<f8": "double"}[dtype]
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {len(points)}\nproperty {kind} x\nproperty {kind} y\n"
              f"property {kind} z\nelement face {len(faces)}\n"
              "property list uchar int vertex_indices\nend_header\n")
    body = points.astype(dtype).tobytes()
    for f in faces:
        body += np.uint8(len(f)).tobytes() + np.asarray(f, dtype="<i4").tobytes()
    pathlib.Path(path).write_bytes(header.encode("ascii") + body)


def positions(vertices):
    return np.stack([vertices["x"], vertices["y"], vertices["z"]], axis=1).astype(np.float64)


def smooth_with_meshlabserver(tmp_path, points, faces, *overrides, name="mesh"):
    source = tmp_path / f"{name}.ply"
    write_ply(source, points, faces)
    out = tmp_path / f"{name}_out.ply"
    run = run_meshlabserver(["-i", source, "-o", out, "-m", "vq",
                             "-s", write_mlx(tmp_path, "smooth", *overrides)])
    text = run.stdout + run.stderr
    # An abort (assertion) is 134, a crash a negative signal: neither may happen.
    assert run.returncode >= 0 and run.returncode != 134, text
    return run, text, out


# ---------------------------------------------------------------------------------------------
# meshlabserver 2020.09


def test_meshlabserver_refuses_non_finite_coordinates(tmp_path):
    points, faces = noisy_grid()
    for bad in (np.nan, np.inf):
        points = points.copy()
        points[40, 2] = bad
        run, text, out = smooth_with_meshlabserver(tmp_path, points, faces, name=f"bad_{bad}")
        assert "the mesh has NaN or infinite vertex coordinates" in text, text
        assert "Problem with filter" in text, text
        assert not out.exists()


def test_meshlabserver_refuses_absurd_scales(tmp_path):
    points, faces = noisy_grid()
    huge = points.copy()
    huge[7, 1] = 1e31
    run, text, out = smooth_with_meshlabserver(tmp_path, huge, faces, name="huge")
    assert "coordinates beyond 1e30" in text, text
    assert not out.exists()
    run, text, out = smooth_with_meshlabserver(tmp_path, points * 1e-31, faces, name="tiny")
    assert "smaller than 1e-30 across" in text, text
    assert not out.exists()


def test_meshlabserver_skips_and_reports_non_manifold_and_smooths_the_rest(tmp_path):
    n = 12
    points, faces, nonmanifold = with_defects(*noisy_grid(n), n=n)
    # The ring barycentre (placement 0): its per-kind skip counts, and noise this light (0.08 mean
    # edge lengths) is smoothed; the default automatic mode judges it clean and leaves it.
    run, text, out = smooth_with_meshlabserver(tmp_path, points, faces, "boundary=1", "placement=0")
    assert out.exists(), text
    assert "Skipped (left in place): 5 non-manifold, 1 isolated" in text, text
    vertices, result_faces = read_ply(out)
    result = positions(vertices)
    assert np.isfinite(result).all()
    np.testing.assert_array_equal(result_faces, faces)
    before = points.astype(np.float32).astype(np.float64)
    np.testing.assert_array_equal(result[nonmanifold], before[nonmanifold])
    np.testing.assert_array_equal(result[-1], before[-1])  # unreferenced
    interior = [j * n + i for j in range(2, n - 2) for i in range(2, n - 2)
                if j * n + i not in nonmanifold]
    assert np.sqrt(np.mean(result[interior, 2] ** 2)) < 0.5 * np.sqrt(np.mean(before[interior, 2] ** 2))


def test_meshlabserver_triangulates_quads_and_smooths_them(tmp_path):
    n = 14
    points, _ = noisy_grid(n, seed=8)
    quads = [[j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i]
             for j in range(n - 1) for i in range(n - 1)]
    run, text, out = smooth_with_meshlabserver(tmp_path, points, quads, "boundary=1", "placement=0",
                                               name="quads")
    assert out.exists(), text
    vertices, triangles = read_ply(out)
    assert len(triangles) == 2 * len(quads)  # MeshLab's importer fan-triangulates
    result = positions(vertices)
    assert np.isfinite(result).all()
    interior = [j * n + i for j in range(2, n - 2) for i in range(2, n - 2)]
    assert np.abs(result[interior, 2]).mean() < 0.5 * np.abs(points[interior, 2]).mean()


def test_meshlabserver_refuses_an_empty_mesh_and_a_point_cloud(tmp_path):
    for name, points, faces, message in (
            ("empty", np.zeros((0, 3)), [], "Error: The mesh is empty."),
            ("cloud", np.eye(3), [], "Error: the mesh has no faces (a point cloud)")):
        run, text, out = smooth_with_meshlabserver(tmp_path, points, faces, name=name)
        assert message in text and "Problem with filter" in text, text
        assert not out.exists(), text


def test_meshlabserver_vertices_deleted_by_a_filter_give_the_compacted_result(tmp_path):
    """MeshLab 2020.09's delete filters mark vertices and faces deleted and leave them in the
    containers; our filter, run next in the same script, must ignore them."""
    n = 16
    points, faces = noisy_grid(n, seed=12)
    points = points.astype(np.float32).astype(np.float64)
    source = tmp_path / "grid.ply"
    write_ply(source, points, faces)
    condition = "(x &gt; 0.3) &amp;&amp; (x &lt; 0.45) &amp;&amp; (y &gt; 0.25) &amp;&amp; (y &lt; 0.55)"
    smooth = write_mlx(tmp_path, "smooth").read_text()
    script = smooth.replace(
        "<FilterScript>",
        "<FilterScript>\n <filter name=\"Conditional Vertex Selection\">\n"
        f"  <Param type=\"RichString\" value=\"{condition}\" name=\"condSelect\"/>\n"
        " </filter>\n <filter name=\"Delete Selected Vertices\"/>", 1)
    mlx = tmp_path / "delete_then_smooth.mlx"
    mlx.write_text(script)
    out = tmp_path / "deleted_out.ply"
    run = run_meshlabserver(["-i", source, "-o", out, "-s", mlx])
    text = run.stdout + run.stderr
    assert run.returncode == 0 and out.exists(), text

    x, y = points[:, 0], points[:, 1]
    dead = (x > 0.3) & (x < 0.45) & (y > 0.25) & (y < 0.55)
    assert dead.sum() == 10
    live_faces = faces[~dead[faces].any(axis=1)]
    new_index = np.cumsum(~dead) - 1
    compact_points, compact_faces = points[~dead], new_index[live_faces]
    reference_run, text, reference_out = smooth_with_meshlabserver(
        tmp_path, compact_points, compact_faces, name="compacted")
    assert reference_out.exists(), text
    result, result_faces = read_ply(out)
    reference, reference_faces = read_ply(reference_out)
    np.testing.assert_array_equal(result_faces, reference_faces)
    np.testing.assert_array_equal(positions(result), positions(reference))


def test_meshlabserver_degenerate_faces_and_components(tmp_path):
    points, faces = noisy_grid(8)
    parts_points, parts_faces = [points], [faces]
    rng = np.random.default_rng(3)
    for k in range(30):  # small components: single triangles and zero-area triangles
        base = sum(len(p) for p in parts_points)
        tri = rng.normal(0, 0.05, (3, 3)) + [3 + k % 6, k // 6, 0]
        if k % 5 == 0:
            tri[2] = (tri[0] + tri[1]) / 2  # zero area
        parts_points.append(tri)
        parts_faces.append(np.array([[base, base + 1, base + 2]]))
    points, faces = np.vstack(parts_points), np.vstack(parts_faces)
    run, text, out = smooth_with_meshlabserver(tmp_path, points, faces, name="parts")
    assert out.exists(), text
    result = positions(read_ply(out)[0])
    assert np.isfinite(result).all()


# ---------------------------------------------------------------------------------------------
# PyMeshLab 2025.07: each case runs in its own process (see the module docstring)


def run_case(name):
    env = dict(os.environ, SBS_BUILD_DIR=str(BUILD))
    run = subprocess.run([sys.executable, __file__, name], env=env, capture_output=True,
                         text=True, timeout=600)
    assert run.returncode == 0, f"case {name}: exit {run.returncode}\n{run.stdout}\n{run.stderr}"
    return json.loads(run.stdout.strip().splitlines()[-1])


def test_pymeshlab_refuses_inf_and_absurd_scales_and_keeps_the_mesh():
    result = run_case("refusals")
    for case, message in result.items():
        assert message["unchanged"], case
        assert message["expected"] in message["text"], (case, message["text"])


def test_pymeshlab_non_manifold_is_skipped_and_the_rest_smoothed():
    result = run_case("nonmanifold")
    assert result["finite"]
    assert result["nonmanifold_unchanged"]
    assert result["rms_after"] < 0.5 * result["rms_before"], result


def test_pymeshlab_deleted_elements_give_the_compacted_result():
    """PyMeshLab 2025.07 compacts the mesh after every filter (measured: is_compact() is true
    right after meshing_remove_selected_vertices), so our filter never sees deleted elements there;
    the result still has to match the compacted mesh's. (The library-level test and the
    meshlabserver one cover deleted elements left in the containers.)"""
    result = run_case("deleted")
    assert result["was_compact"] is True
    assert result["deleted_vertices"] == 10
    assert result["max_difference"] == 0.0, result


def test_pymeshlab_scale_equivariance():
    result = run_case("scale")
    for scale, relative in result.items():
        assert relative < 1e-6, (scale, relative)


def _pymeshlab_case(name):
    """Runs in a child process; prints one JSON line."""
    import pymeshlab
    plugin = pathlib.Path(os.environ.get("SBS_BUILD_DIR", BUILD)) / "pymeshlab" / \
        "libfilter_saliency_bezier_smooth.so"
    pymeshlab.load_plugin(str(plugin))

    def mesh_set(points, faces):
        ms = pymeshlab.MeshSet()
        ms.add_mesh(pymeshlab.Mesh(vertex_matrix=np.asarray(points, dtype=np.float64),
                                   face_matrix=np.asarray(faces, dtype=np.int32)))
        return ms

    def reset_logger():  # test_pymeshlab.py: a successful filter after every expected failure
        ok = mesh_set(np.eye(3), [[0, 1, 2]])
        ok.apply_filter("set_selection_none")

    if name == "refusals":
        points, faces = noisy_grid()
        cases = {}
        inf = points.copy()
        inf[40, 0] = np.inf
        huge = points.copy()
        huge[7, 1] = -1e31
        for case, p, expected in (("inf", inf, "NaN or infinite vertex coordinates"),
                                  ("huge", huge, "coordinates beyond 1e30"),
                                  ("tiny", points * 1e-31, "smaller than 1e-30 across")):
            for filter_name in (SMOOTH, ANALYSE):
                ms = mesh_set(p, faces)
                try:
                    ms.apply_filter(filter_name)
                    text = "no exception"
                except pymeshlab.PyMeshLabException as error:
                    text = str(error)
                unchanged = bool(np.array_equal(ms.current_mesh().vertex_matrix(), p,
                                                equal_nan=True))
                reset_logger()
                cases[f"{case} {filter_name}"] = {"text": text, "expected": expected,
                                                  "unchanged": unchanged}
        return cases
    if name == "nonmanifold":
        n = 12
        points, faces, nonmanifold = with_defects(*noisy_grid(n), n=n)
        ms = mesh_set(points, faces)
        ms.apply_filter(SMOOTH, boundary=1, placement=0)  # the ring barycentre, as above
        result = ms.current_mesh().vertex_matrix()
        interior = [j * n + i for j in range(2, n - 2) for i in range(2, n - 2)
                    if j * n + i not in nonmanifold]
        return {"finite": bool(np.isfinite(result).all()),
                "nonmanifold_unchanged": bool(np.array_equal(result[nonmanifold],
                                                             points[nonmanifold])),
                "rms_before": float(np.sqrt(np.mean(points[interior, 2] ** 2))),
                "rms_after": float(np.sqrt(np.mean(result[interior, 2] ** 2)))}
    if name == "deleted":
        points, faces = noisy_grid(16, seed=12)
        ms = mesh_set(points, faces)
        ms.apply_filter("compute_selection_by_condition_per_vertex",
                        condselect="(x > 0.3) && (x < 0.45) && (y > 0.25) && (y < 0.55)")
        ms.apply_filter("meshing_remove_selected_vertices")  # deletes, does not compact
        mesh = ms.current_mesh()
        was_compact = mesh.is_compact()
        ms.apply_filter(SMOOTH)
        smoothed = ms.current_mesh().vertex_matrix()  # the live vertices, in order
        # The same mesh compacted before smoothing.
        reference = mesh_set(*_compacted(pymeshlab, points, faces))
        reference.apply_filter(SMOOTH)
        expected = reference.current_mesh().vertex_matrix()
        return {"was_compact": bool(was_compact),
                "deleted_vertices": int(len(points) - len(smoothed)),
                "max_difference": float(np.abs(smoothed - expected).max())
                if smoothed.shape == expected.shape else float("inf")}
    if name == "scale":
        points, faces = noisy_grid(12, 0.02, 21)
        ms = mesh_set(points, faces)
        ms.apply_filter(SMOOTH)
        reference = ms.current_mesh().vertex_matrix()
        out = {}
        for scale in (1e7, 1e-7):
            scaled = mesh_set(points * scale, faces)
            scaled.apply_filter(SMOOTH)
            difference = np.abs(scaled.current_mesh().vertex_matrix() / scale - reference).max()
            out[str(scale)] = float(difference / np.sqrt(2.0))
        return out
    raise ValueError(name)


def _compacted(pymeshlab, points, faces):
    """The grid after the same selection and deletion as the 'deleted' case, compacted."""
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=points, face_matrix=np.asarray(faces, np.int32)))
    ms.apply_filter("compute_selection_by_condition_per_vertex",
                    condselect="(x > 0.3) && (x < 0.45) && (y > 0.25) && (y < 0.55)")
    ms.apply_filter("meshing_remove_selected_vertices")
    mesh = ms.current_mesh()
    mesh.compact()
    return mesh.vertex_matrix().copy(), mesh.face_matrix().copy()


if __name__ == "__main__":
    print(json.dumps(_pymeshlab_case(sys.argv[1])))
