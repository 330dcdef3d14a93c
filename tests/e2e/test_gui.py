"""End-to-end: the real MeshLab 2020.09 GUI (private copy, its own Xvfb screen, driven by xdotool)
loads our plugin: its filters are found by MeshLab's filter search, their dialogs open under their
own names, and Apply runs them on the loaded mesh. A truncated plugin is the control: MeshLab
reports it and its filters are missing, so every check here can fail."""
import re
import shutil

import numpy as np
import pytest

from conftest import PRIVATE_MESHLAB
from meshlab_gui import MeshLabGui, system_plugins

OURS = "libfilter_saliency_bezier_smooth.so"
SMOOTH = "Saliency Bezier Smooth"
ANALYSE = "Compute Mesh Saliency and Principal Curvatures"


def write_icosphere(path):
    """A once-subdivided icosahedron: 42 vertices, 80 triangles, as ASCII PLY."""
    t = (1 + 5 ** 0.5) / 2
    points = [np.array(p, dtype=float) for p in
              [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
               (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    midpoints = {}

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in midpoints:
            midpoints[key] = len(points)
            points.append((points[a] + points[b]) / 2)
        return midpoints[key]

    subdivided = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        subdivided += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    lines = ["ply", "format ascii 1.0", f"element vertex {len(points)}", "property float x",
             "property float y", "property float z", f"element face {len(subdivided)}",
             "property list uchar int vertex_indices", "end_header"]
    lines += ["%.7f %.7f %.7f" % tuple(p / np.linalg.norm(p)) for p in points]
    lines += ["3 %d %d %d" % f for f in subdivided]
    path.write_text("\n".join(lines) + "\n")
    return path


def lines_naming(log, file_name):
    """MeshLab logs nothing about a plugin that loads; a loader error names the plugin's file."""
    return [line for line in log.splitlines() if file_name in line]


@pytest.fixture
def our_plugin():
    plugin = PRIVATE_MESHLAB / "plugins" / OURS
    if not plugin.exists():
        pytest.fail(f"{plugin} not built (make filter_saliency_bezier_smooth)")
    if not (PRIVATE_MESHLAB / "meshlab").exists():
        pytest.fail("no private copy of the meshlab GUI in the build folder")
    for tool in ("Xvfb", "xdotool"):
        if shutil.which(tool) is None:
            pytest.fail(f"{tool} is not installed (apt-get install xvfb xdotool)")
    return plugin


def test_gui_opens_and_applies_our_filters(tmp_path, our_plugin):
    plugins = system_plugins()
    plugins[OURS] = our_plugin
    plugins["libfilter_broken.so"] = our_plugin.read_bytes()[:4096]
    mesh = write_icosphere(tmp_path / "icosphere.ply")
    with MeshLabGui(tmp_path / "gui", plugins, mesh) as gui:
        log = gui.log()
        assert lines_naming(log, "libfilter_broken.so"), log  # the loader reports a broken plugin,
        assert not lines_naming(log, OURS), log               # but not ours

        # The dialog is a window titled with the filter's name: only our plugin defines it.
        assert gui.open_filter_dialog(SMOOTH) == SMOOTH
        verdict = gui.apply_open_dialog(SMOOTH)
        assert f"Applied filter {SMOOTH} in" in verdict, gui.log()
        # Our plugin's own log lines, for the dialog's default (automatic) mode on this mesh.
        assert re.search(r"^LOG: \d+ Automatic mode: ", gui.log(), re.MULTILINE), gui.log()
        assert re.search(r"^LOG: \d+ .*: \d+ of 42 vertices moved", gui.log(),
                         re.MULTILINE), gui.log()

        assert gui.open_filter_dialog(ANALYSE) == ANALYSE
        verdict = gui.apply_open_dialog(ANALYSE)
        assert f"Applied filter {ANALYSE} in" in verdict, gui.log()
        assert re.search(r"^LOG: \d+ Vertices with saliency > 0\.5: \d+", gui.log(),
                         re.MULTILINE), gui.log()


def test_gui_reports_a_broken_copy_of_our_plugin(tmp_path, our_plugin):
    plugins = system_plugins()
    plugins[OURS] = our_plugin.read_bytes()[:4096]
    mesh = write_icosphere(tmp_path / "icosphere.ply")
    with MeshLabGui(tmp_path / "gui", plugins, mesh) as gui:
        errors = lines_naming(gui.log(), OURS)
        assert len(errors) == 1 and "invalid ELF" in errors[0], gui.log()
        # The same search now ends in some other filter whose name has "Smooth" in it.
        title = gui.open_filter_dialog(SMOOTH)
        assert title != SMOOTH
