"""End-to-end: the real PyMeshLab 2025.7.post1 wheel (double precision, MeshLab 2025.07 API) loads
our plugin from <build>/pymeshlab/ and runs both filters; the float 2020.09 meshlabserver and the
double 2025.07 plugin agree.

Run with the venv that scripts/setup_pymeshlab.sh creates: .venv/bin/python -m pytest tests/e2e.

pymeshlab 2025.7.post1 leaves a static pointer to the MeshSet's log behind when a filter throws
inside applyFilter (meshset_helper.cpp, applyFilterRPL: the catch block skips
`VerbosityManager::staticLogger = nullptr`). Once that MeshSet is freed, the next progress
callback of any MeshSet (a load, a save, a filter) writes through the dangling pointer and
segfaults. It happens with MeshLab's own filters too. `apply_expecting_error` therefore runs one
successful filter right after every expected failure, which resets the pointer.
"""
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

import numpy as np
import pytest

from conftest import BUILD, REPO, mesh_compare, read_ply, run_meshlabserver

SMOOTH = "apply_coord_saliency_bezier_smoothing"
ANALYSE = "compute_scalar_by_mesh_saliency_per_vertex"
PLUGIN = BUILD / "pymeshlab" / "libfilter_saliency_bezier_smooth.so"
ATTRIBUTES = ["Saliency", "MeanCurvature", "GaussianCurvature", "K1", "K2"]


@pytest.fixture(scope="session")
def pymeshlab():
    """The pymeshlab module with our plugin loaded (once per process: a second load raises)."""
    try:
        import pymeshlab as module
    except ImportError:
        pytest.fail("pymeshlab is not importable: run pytest with .venv/bin/python "
                    "(scripts/setup_pymeshlab.sh creates it)")
    if not PLUGIN.exists():
        pytest.fail(f"{PLUGIN} not built (cmake -DBUILD_PYMESHLAB_PLUGIN=ON, target "
                    "filter_saliency_bezier_smooth_pymeshlab)")
    before = module.plugin_number()
    module.load_plugin(str(PLUGIN))
    assert module.plugin_number() == before + 1
    # MeshSet methods are bound at import only; bind ours by hand.
    for name in (SMOOTH, ANALYSE):
        assert name in module.filter_list()
        setattr(module.MeshSet, name, module.bind_function(name))
    return module


def apply_expecting_error(pymeshlab, ms, filter_name, exception, **params):
    """The message of the `exception` that applying the filter raises; then resets pymeshlab's
    static logger (see the module docstring)."""
    with pytest.raises(exception) as error:
        ms.apply_filter(filter_name, **params)
    reset = pymeshlab.MeshSet()
    reset.add_mesh(pymeshlab.Mesh(vertex_matrix=np.eye(3), face_matrix=np.array([[0, 1, 2]])))
    reset.apply_filter("set_selection_none")
    return str(error.value)


def load(pymeshlab, path):
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    return ms


def display_percentile(values):
    """vcg_ext/analysis/display_scale.h's 99th percentile: the nearest rank."""
    return np.sort(values)[int(0.99 * (len(values) - 1) + 0.5)]


def bbox_diagonal(points):
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def mlx_parameters(path):
    """name -> value of the filter's parameters in one of the examples/*.mlx scripts (2020.09)."""
    params = {}
    for p in ElementTree.parse(path).getroot().iter("Param"):
        kind, value = p.get("type"), p.get("value")
        params[p.get("name")] = {"RichInt": int, "RichEnum": int, "RichFloat": float,
                                 "RichBool": lambda v: v == "true"}[kind](value)
    return params


def test_smoothing_fandisk_with_defaults(pymeshlab, tmp_path, shared):
    case = shared / "data" / "benchmark" / "Fandisk0.3"
    ms = load(pymeshlab, case / "noisy.ply")
    before = ms.current_mesh().vertex_matrix().copy()
    assert ms.apply_coord_saliency_bezier_smoothing()["method"] == 3  # it chose Feature-preserving
    mesh = ms.current_mesh()
    after = mesh.vertex_matrix()
    out = tmp_path / "fandisk_smoothed.ply"
    ms.save_current_mesh(str(out))

    noisy = mesh_compare(case / "noisy.ply", case / "clean.ply")
    smoothed = mesh_compare(out, case / "clean.ply")
    assert noisy["theta_deg"] == pytest.approx(28.42, abs=0.05)
    assert smoothed["theta_deg"] < 14.0  # measured 10.6, as meshlabserver
    assert smoothed["ev_1e3"] < noisy["ev_1e3"]
    assert abs(smoothed["volume_ratio"] - 1.0) < 0.01

    n = mesh.vertex_number()
    saliency = mesh.vertex_custom_scalar_attribute_array("Saliency")
    assert len(saliency) == n == 6475
    # Saliency is divided by its maximum (0 keeps meaning "not salient", vcg_ext/analysis/saliency.h), so
    # the maximum is 1 and the minimum is >= 0 but not 0 here (measured 0.0043).
    assert saliency.max() == pytest.approx(1.0, abs=1e-6)
    assert saliency.min() >= 0.0
    # Default "Store in vertex quality": Saliency on its display scale (over its 99th percentile,
    # clipped at 1: vcg_ext/analysis/display_scale.h).
    np.testing.assert_allclose(mesh.vertex_scalar_array(),
                               np.clip(saliency / display_percentile(saliency), 0, 1),
                               rtol=0, atol=1e-12)
    for name in ATTRIBUTES + ["Alpha", "Displacement"]:
        assert len(mesh.vertex_custom_scalar_attribute_array(name)) == n
    # Displacement is |new - old|, in double on both sides.
    np.testing.assert_allclose(mesh.vertex_custom_scalar_attribute_array("Displacement"),
                               np.linalg.norm(after - before, axis=1), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(mesh.vertex_custom_scalar_attribute_array("Alpha"), 1.0)


def test_alpha_attribute_shows_the_alpha_the_patches_used(pymeshlab, shared):
    """The Alpha attribute holds the α the default method's patch fits used: the user's α with
    the override on, the paper's saliency rule (below 1 where saliency varies) with it off."""
    noisy = shared / "data" / "benchmark" / "Fandisk0.3" / "noisy.ply"
    ms = load(pymeshlab, noisy)
    ms.apply_coord_saliency_bezier_smoothing(alpha=0.5)
    np.testing.assert_array_equal(ms.current_mesh().vertex_custom_scalar_attribute_array("Alpha"),
                                  0.5)
    ms = load(pymeshlab, noisy)
    ms.apply_coord_saliency_bezier_smoothing(alpha_override=False)
    alpha = ms.current_mesh().vertex_custom_scalar_attribute_array("Alpha")
    print(f"Fandisk0.3, the paper's alpha rule: min {alpha.min():.4f}, mean {alpha.mean():.4f}")
    assert alpha.min() > 0 and alpha.max() <= 1
    assert alpha.mean() < 0.9


def test_parameter_names_and_defaults_match_the_2020_script(pymeshlab, shared):
    """Every parameter of examples/saliency_bezier_smooth.mlx (the 2020.09 script, all defaults)
    is accepted by name as a Python kwarg, with enums as their index, and gives the defaults'
    result; enums also take their label."""
    noisy = shared / "data" / "benchmark" / "Fandisk0.3" / "noisy.ply"
    params = mlx_parameters(REPO / "examples" / "saliency_bezier_smooth.mlx")
    assert list(params) == ["color", "placement", "iterations", "alpha_override", "alpha",
                            "boundary", "preserve_volume", "selected_only", "quality",
                            "saliency_scale", "fold_handling", "uniform_curvature",
                            "newton_iterations", "newton_step_limit"]
    defaults = load(pymeshlab, noisy)
    defaults.apply_filter(SMOOTH)
    explicit = load(pymeshlab, noisy)
    explicit.apply_filter(SMOOTH, **params)
    np.testing.assert_array_equal(explicit.current_mesh().vertex_matrix(),
                                  defaults.current_mesh().vertex_matrix())
    by_label = load(pymeshlab, noisy)
    by_label.apply_filter(SMOOTH, iterations=1, placement="Patch point", quality="Displacement")
    by_index = load(pymeshlab, noisy)
    by_index.apply_filter(SMOOTH, iterations=1, placement=1, quality=6)
    np.testing.assert_array_equal(by_label.current_mesh().vertex_matrix(),
                                  by_index.current_mesh().vertex_matrix())
    np.testing.assert_array_equal(
        by_label.current_mesh().vertex_scalar_array(),
        by_label.current_mesh().vertex_custom_scalar_attribute_array("Displacement"))
    # One iteration of another placement is a different result.
    assert not np.array_equal(by_label.current_mesh().vertex_matrix(),
                              defaults.current_mesh().vertex_matrix())


def test_analysis_filter_on_clean_fandisk(pymeshlab, shared):
    ms = load(pymeshlab, shared / "data" / "paper" / "fandisk.ply")
    before = ms.current_mesh().vertex_matrix().copy()
    assert ms.compute_scalar_by_mesh_saliency_per_vertex() is None  # bound methods: None for {}
    mesh = ms.current_mesh()
    np.testing.assert_array_equal(mesh.vertex_matrix(), before)  # positions untouched
    a = {name: mesh.vertex_custom_scalar_attribute_array(name) for name in ATTRIBUTES}
    assert all(len(v) == mesh.vertex_number() == 6475 for v in a.values())
    k1, k2, h, k = a["K1"], a["K2"], a["MeanCurvature"], a["GaussianCurvature"]
    assert np.all(k1 >= k2)
    np.testing.assert_allclose((k1 + k2) / 2, h, rtol=0, atol=1e-12)
    # k1,2 = H +- sqrt(max(H^2 - K, 0)): their product is K where H^2 >= K, else k1 = k2 = H.
    real = h * h >= k
    assert 0 < real.sum() < len(k)
    np.testing.assert_allclose(k1[real] * k2[real], k[real], rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(k1[~real], h[~real])
    np.testing.assert_array_equal(k2[~real], h[~real])
    assert a["Saliency"].min() >= 0.0
    assert a["Saliency"].max() == pytest.approx(1.0, abs=1e-6)
    np.testing.assert_allclose(mesh.vertex_scalar_array(),
                               np.clip(a["Saliency"] / display_percentile(a["Saliency"]), 0, 1),
                               rtol=0, atol=1e-12)
    # "Colour the mesh" is on by default here: colours from red (low) to blue (high).
    colours = mesh.vertex_color_matrix()
    assert len(np.unique(colours[:, :3].round(3), axis=0)) > 50
    # The curvature-direction requirement (MM_VERTCURVDIR) made PyMeshLab enable the component.
    d1 = mesh.vertex_curvature_principal_dir1_matrix()
    d2 = mesh.vertex_curvature_principal_dir2_matrix()
    np.testing.assert_allclose(np.linalg.norm(d1, axis=1), 1.0, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(d2, axis=1), 1.0, atol=1e-9)
    assert np.abs(np.sum(d1 * d2, axis=1)).max() < 1e-9

    # The quality choice by label: K1 into vertex quality, on the signed log scale.
    ms.apply_filter(ANALYSE, saliency_scale=0.3, quality="K1")
    np.testing.assert_allclose(ms.current_mesh().vertex_scalar_array(),
                               np.arcsinh(k1 / np.median(np.abs(k1))), rtol=1e-12, atol=1e-12)


def test_wrong_parameter_name_is_reported(pymeshlab, shared):
    ms = load(pymeshlab, shared / "data" / "benchmark" / "Fandisk0.3" / "noisy.ply")
    message = apply_expecting_error(pymeshlab, ms, SMOOTH, pymeshlab.PyMeshLabException,
                                    iteration=3)
    assert message == (f"Parameter iteration not found for filter {SMOOTH}. "
                       "Please check the documentation.")


def test_wrong_types_raise_without_crashing(pymeshlab, shared):
    ms = load(pymeshlab, shared / "data" / "benchmark" / "Fandisk0.3" / "noisy.ply")
    before = ms.current_mesh().vertex_matrix().copy()
    # pybind11's cast error: a RuntimeError, not a PyMeshLabException.
    message = apply_expecting_error(pymeshlab, ms, SMOOTH, RuntimeError, iterations="abc")
    assert "Unable to cast Python instance of type <class 'str'>" in message
    apply_expecting_error(pymeshlab, ms, SMOOTH, RuntimeError, iterations=2.5)
    message = apply_expecting_error(pymeshlab, ms, SMOOTH, pymeshlab.InvalidEnumException,
                                    placement="Newton")
    assert "'Ring barycentre'; 'Patch point'; 'Paper (Newton)'; 'Feature-preserving'" in message
    np.testing.assert_array_equal(ms.current_mesh().vertex_matrix(), before)


def test_out_of_range_value_reports_our_message(pymeshlab, shared):
    ms = load(pymeshlab, shared / "data" / "benchmark" / "Fandisk0.3" / "noisy.ply")
    before = ms.current_mesh().vertex_matrix().copy()
    message = apply_expecting_error(pymeshlab, ms, SMOOTH, pymeshlab.PyMeshLabException,
                                    alpha=2.0)
    assert message == (f"Failed to apply filter: {SMOOTH}\n"
                       "Details: Parameter 'alpha' = 2 is outside [0, 1].")
    np.testing.assert_array_equal(ms.current_mesh().vertex_matrix(), before)
    with pytest.raises(pymeshlab.PyMeshLabException, match="No valid per vertex scalar"):
        ms.current_mesh().vertex_custom_scalar_attribute_array("Saliency")


def test_point_cloud_is_refused_and_unchanged(pymeshlab):
    """Both filters declare the precondition MM_FACENUMBER (as the 2020.09 adapter), so PyMeshLab
    refuses a point cloud before calling the plugin, with its own message (meshlabserver 2020.09
    does not check preconditions and shows ours, "the mesh has no faces (a point cloud)")."""
    points = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=points))
    for name in (SMOOTH, ANALYSE):
        message = apply_expecting_error(pymeshlab, ms, name, pymeshlab.PyMeshLabException)
        assert message == f"Failed to apply filter:  '{name}. Current mesh does not have Any Faces."
    np.testing.assert_array_equal(ms.current_mesh().vertex_matrix(), points)
    assert ms.current_mesh().face_number() == 0


def test_invalid_mesh_reports_our_message_and_is_unchanged(pymeshlab, shared):
    """A mesh the plugin itself rejects (a NaN vertex): our MLException text reaches Python."""
    ms = load(pymeshlab, shared / "data" / "benchmark" / "Fandisk0.3" / "noisy.ply")
    points = ms.current_mesh().vertex_matrix().copy()
    points[5] = np.nan
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=points, face_matrix=ms.current_mesh().face_matrix()))
    for name in (SMOOTH, ANALYSE):
        message = apply_expecting_error(pymeshlab, ms, name, pymeshlab.PyMeshLabException)
        assert message == (f"Failed to apply filter: {name}\nDetails: the mesh has NaN or "
                           "infinite vertex coordinates; remove them first")
    np.testing.assert_array_equal(ms.current_mesh().vertex_matrix(), points)  # NaN == NaN here


def test_selection_makes_selected_only_the_default(pymeshlab, shared):
    """As in the MeshLab dialog, 'selected_only' defaults to on when the mesh has a selection."""
    ms = load(pymeshlab, shared / "data" / "benchmark" / "Fandisk0.3" / "noisy.ply")
    before = ms.current_mesh().vertex_matrix().copy()
    median_x = float(np.median(before[:, 0]))
    ms.apply_filter("compute_selection_by_condition_per_vertex", condselect=f"x > {median_x}")
    selected = ms.current_mesh().vertex_selection_array().copy()
    assert 0.4 < selected.mean() < 0.6
    ms.apply_filter(SMOOTH)
    moved = np.linalg.norm(ms.current_mesh().vertex_matrix() - before, axis=1) > 0
    assert moved[selected].mean() > 0.99
    assert not moved[~selected].any()


def test_float_2020_and_double_2025_agree(pymeshlab, tmp_path, shared):
    """The same default smoothing (and analysis) through meshlabserver 2020.09 (float mesh) and
    PyMeshLab 2025.07 (double mesh). vcg_ext computes in double either way and keeps positions in
    double between iterations, so only the float output (and float32 parameters in both) differ:
    measured max |difference| / bbox diagonal = 1.2e-7 for positions, 3e-8 for saliency."""
    noisy = shared / "data" / "benchmark" / "Fandisk0.3" / "noisy.ply"
    out = tmp_path / "meshlabserver.ply"
    run = run_meshlabserver(["-i", noisy, "-o", out, "-m", "vq",
                             "-s", REPO / "examples" / "saliency_bezier_smooth.mlx"])
    assert run.returncode == 0 and out.exists(), run.stdout + run.stderr
    vertices, faces = read_ply(out)
    float_result = np.stack([vertices["x"], vertices["y"], vertices["z"]], axis=1).astype(float)

    ms = load(pymeshlab, noisy)
    diagonal = bbox_diagonal(ms.current_mesh().vertex_matrix())
    ms.apply_filter(SMOOTH)
    mesh = ms.current_mesh()
    np.testing.assert_array_equal(mesh.face_matrix(), faces)
    difference = np.linalg.norm(mesh.vertex_matrix() - float_result, axis=1).max() / diagonal
    print(f"float vs double smoothing: max |difference| / bbox diagonal = {difference:.3g}")
    assert difference < 1e-6
    quality = np.asarray(vertices["quality"], dtype=float)
    assert np.abs(mesh.vertex_scalar_array() - quality).max() < 1e-6

    clean = shared / "data" / "paper" / "fandisk.ply"
    out = tmp_path / "meshlabserver_saliency.ply"
    run = run_meshlabserver(["-i", clean, "-o", out, "-m", "vq",
                             "-s", REPO / "examples" / "compute_saliency_curvature.mlx"])
    assert run.returncode == 0 and out.exists(), run.stdout + run.stderr
    ms = load(pymeshlab, clean)
    ms.apply_filter(ANALYSE)
    quality = np.asarray(read_ply(out)[0]["quality"], dtype=float)
    assert np.abs(ms.current_mesh().vertex_scalar_array() - quality).max() < 1e-6


def test_example_script_runs(shared):
    """examples/pymeshlab_smooth.py in its own process (its own load_plugin)."""
    env = dict(os.environ, SBS_BUILD_DIR=str(BUILD), SBS_SHARED_DIR=str(shared))
    run = subprocess.run([sys.executable, str(REPO / "examples" / "pymeshlab_smooth.py")],
                         env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    found = re.search(r"noisy 28\.42 deg -> smoothed ([0-9.]+) deg", run.stdout)
    assert found, run.stdout
    assert float(found.group(1)) < 12.0, run.stdout
    assert "max 1.0000" in run.stdout, run.stdout


def test_organic_mode_on_random_noise_in_both_generations(pymeshlab, tmp_path, shared):
    """The organic mode (placement 4) on the bunny with noise in random 3-D directions, through
    meshlabserver 2020.09 (examples/saliency_bezier_smooth_organic.mlx) and PyMeshLab 2025.07 (by
    the choice's label): both remove most of the noise and agree closely. Not to float rounding:
    the noise probe is hashed from each vertex's coordinates, which the float mesh has rounded
    (measured: 2.2e-5 of the bbox diagonal at most, θ equal to 0.01°)."""
    clean = shared / "data" / "benchmark" / "Bunny0.2" / "clean.ply"
    noisy = tmp_path / "bunny_random.ply"
    subprocess.run([str(BUILD / "tools" / "add_noise"), str(clean), str(noisy), "0.25", "random",
                    "1"], check=True, capture_output=True)
    out = tmp_path / "meshlabserver_organic.ply"
    run = run_meshlabserver(["-i", noisy, "-o", out, "-s",
                             REPO / "examples" / "saliency_bezier_smooth_organic.mlx"])
    assert run.returncode == 0 and out.exists(), run.stdout + run.stderr
    before, after = mesh_compare(noisy, clean), mesh_compare(out, clean)
    assert before["theta_deg"] > 25 and before["flipped_faces"] > 1000, before
    assert after["theta_deg"] < 0.3 * before["theta_deg"], after
    assert after["flipped_faces"] < 0.01 * before["flipped_faces"], after
    assert after["ev_1e3"] < 0.6 * before["ev_1e3"], after
    vertices, faces = read_ply(out)
    float_result = np.stack([vertices["x"], vertices["y"], vertices["z"]], axis=1).astype(float)

    ms = load(pymeshlab, noisy)
    diagonal = bbox_diagonal(ms.current_mesh().vertex_matrix())
    ms.apply_filter(SMOOTH, placement="Organic scan")
    mesh = ms.current_mesh()
    np.testing.assert_array_equal(mesh.face_matrix(), faces)
    difference = np.linalg.norm(mesh.vertex_matrix() - float_result, axis=1).max() / diagonal
    print(f"organic mode, float vs double: max |difference| / bbox diagonal = {difference:.3g}")
    assert difference < 1e-4
    double_result = tmp_path / "pymeshlab_organic.ply"
    ms.save_current_mesh(str(double_result))
    assert abs(mesh_compare(double_result, clean)["theta_deg"] - after["theta_deg"]) < 0.05


# Every parameter of the dialog, a value other than its default, and what it changes in the
# default (Automatic) method's result on the noisy Fandisk (closed) or the paper's noisy mountain
# (open: the boundary rule). The paper's-method parameters leave the default method's result as it
# is (they belong to the methods their labels name; tests/unit/test_methods.cpp shows they act
# there).
PARAMETER_EFFECTS = [
    # name, value, mesh, what changes in the default method's result
    ("color", True, "fandisk", "colours"),
    ("placement", "Organic scan", "fandisk", "positions"),
    ("iterations", 6, "fandisk", "positions"),
    ("alpha_override", False, "fandisk", "positions"),
    ("alpha", 0.5, "fandisk", "positions"),
    ("boundary", "Fixed", "mountain", "positions"),
    ("preserve_volume", False, "fandisk", "positions"),
    ("selected_only", True, "fandisk", "positions"),
    ("quality", "Mean curvature", "fandisk", "quality"),
    ("saliency_scale", 1.0, "fandisk", "quality"),
    ("fold_handling", "Paper fallbacks", "fandisk", "nothing"),
    ("uniform_curvature", "Paper", "fandisk", "nothing"),
    ("newton_iterations", 5, "fandisk", "nothing"),
    ("newton_step_limit", 0.5, "fandisk", "nothing"),
]


def smoothed_state(pymeshlab, shared, mesh, **params):
    path = {"fandisk": shared / "data" / "benchmark" / "Fandisk0.3" / "noisy.ply",
            "mountain": shared / "data" / "paper" / "mountain_noisy0.2.ply"}[mesh]
    ms = load(pymeshlab, path)
    if params.get("selected_only"):
        ms.compute_selection_by_condition_per_vertex(condselect="x > 0")
    else:
        ms.set_selection_none()
    result = ms.apply_filter(SMOOTH, **params)
    m = ms.current_mesh()
    return {"positions": m.vertex_matrix().copy(), "quality": m.vertex_scalar_array().copy(),
            "colours": m.vertex_color_matrix().copy(), "result": result}


def test_every_dialog_parameter_is_covered():
    names = [name for name, *_ in PARAMETER_EFFECTS]
    mlx = ElementTree.parse(REPO / "examples" / "saliency_bezier_smooth.mlx")
    assert names == [p.get("name") for p in mlx.iter("Param")]


@pytest.mark.parametrize("name,value,mesh,effect", PARAMETER_EFFECTS,
                         ids=[p[0] for p in PARAMETER_EFFECTS])
def test_each_parameter_in_the_default_method(pymeshlab, shared, name, value, mesh, effect):
    default = smoothed_state(pymeshlab, shared, mesh)
    changed = smoothed_state(pymeshlab, shared, mesh, **{name: value})
    differs = {key: not np.array_equal(default[key], changed[key])
               for key in ("positions", "quality", "colours")}
    if effect == "nothing":
        assert not any(differs.values()), differs
    else:
        assert differs[effect], differs
    if name == "selected_only":  # only the selected half moved
        start = load(pymeshlab, shared / "data" / "benchmark" / "Fandisk0.3" / "noisy.ply")
        original = start.current_mesh().vertex_matrix()
        moved = np.any(changed["positions"] != original, axis=1)
        assert moved.any() and not moved[original[:, 0] <= 0].any()


def test_smoothing_returns_the_method_that_ran(pymeshlab, shared):
    """apply_filter returns the Method row that ran (the automatic one's choice), how far the mesh
    moved and the noise estimate (PyMeshLab converts numbers, not strings)."""
    state = smoothed_state(pymeshlab, shared, "fandisk")
    result = state["result"]
    assert result["method"] == 3  # Feature-preserving
    assert result["vertices_moved"] == 6475
    assert result["roughness"] == 1.0
    assert 0.1 < result["mean_displacement"] < 0.5
    assert smoothed_state(pymeshlab, shared, "fandisk", placement="Organic scan")["result"][
        "method"] == 4
    clean = load(pymeshlab, shared / "data" / "benchmark" / "Fandisk0.3" / "clean.ply")
    assert clean.apply_filter(SMOOTH) == {"method": -1, "vertices_moved": 0,
                                          "mean_displacement": 0.0, "roughness": 0.0}
    # The user insists (strength 2 = iterations 6): the clean-measured mesh is smoothed.
    insisted = clean.apply_filter(SMOOTH, iterations=6)
    assert insisted["method"] == 3 and insisted["vertices_moved"] > 1000, insisted
