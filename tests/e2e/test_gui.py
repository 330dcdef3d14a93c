"""End-to-end: the real MeshLab 2020.09 GUI (private copy, its own Xvfb screen, driven by xdotool)
loads our plugin: its filters are found by MeshLab's filter search, their dialogs open under their
own names, and Apply runs them on the loaded mesh. A truncated plugin is the control: MeshLab
reports it and its filters are missing, so every check here can fail."""
import os
import pathlib
import re
import shutil
import time

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
        assert re.search(r"^LOG: \d+ Automatic: the mesh measures as clean .*: left as it is; "
                         r"set Iterations above 3", gui.log(), re.MULTILINE), gui.log()

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


COLORIZE = "Colorize by vertex Quality"  # MeshLab's own filter (filter_colorproc)
NOISY_FANDISK = pathlib.Path(__file__).resolve().parents[3] / "shared/data/benchmark/Fandisk0.3"


def coloured_share(pixels):
    """Share of pixels of a colour map's warm or green hues: MeshLab's grey mesh and its blue
    background have none."""
    rgb = pixels.astype(float)
    top = np.maximum(rgb[..., 0], rgb[..., 1])
    return float(np.mean((top > 120) & (rgb[..., 2] < 0.6 * top)))


def view_pixels(gui):
    """The 3-D view's pixels (the main window at the top left, 860 x 752, its view on the left;
    the open filter dialogs moved beside it, as a user would: there is no window manager)."""
    gui.xdotool("windowsize", "--sync", gui.main_window, 860, 752)
    for title in gui.dialog_titles():
        window = gui.find_titled(title)
        if window:
            gui.xdotool("windowmove", "--sync", window, 864, 0)
    gui.xdotool("mousemove", 1000, 700)
    time.sleep(1.0)  # let the view repaint
    return gui.grab(10, 90, 420, 520)


def save_for_docs(gui, name, width, height):
    """With SBS_DOC_SCREENSHOTS=<folder> (scripts/docs_screenshots.sh), the screen's top-left
    width x height pixels go there as <name>.png: the docs' screenshots come from these tests."""
    folder = os.environ.get("SBS_DOC_SCREENSHOTS")
    if folder:
        gui.screenshot(pathlib.Path(folder) / f"{name}.png", width, height)


def test_colorize_by_vertex_quality_works_after_smoothing(tmp_path, our_plugin):
    """The user's inspection path: our smoothing filter at its defaults (no colours of its own),
    then MeshLab's own Colorize by vertex Quality, which refused before ("Current mesh does not
    have Vertex Quality"); the view then shows the colour map."""
    plugins = system_plugins()
    plugins[OURS] = our_plugin
    with MeshLabGui(tmp_path / "gui", plugins, NOISY_FANDISK / "noisy.ply",
                    screen=(1366, 768)) as gui:
        assert gui.open_filter_dialog(SMOOTH) == SMOOTH
        assert f"Applied filter {SMOOTH} in" in gui.apply_open_dialog(SMOOTH), gui.log()
        before = coloured_share(view_pixels(gui))
        assert gui.open_filter_dialog(COLORIZE) == COLORIZE, gui.log()
        assert f"Applied filter {COLORIZE} in" in gui.apply_open_dialog(COLORIZE), gui.log()
        after = coloured_share(view_pixels(gui))
        save_for_docs(gui, "gui_smoothed_saliency", 1366, 768)
        assert before < 0.02 and after > 0.15, (before, after)


def test_analysis_colours_the_mesh_and_colorize_accepts_it(tmp_path, our_plugin):
    """The analysis filter colours the mesh by its quality at once (its "Colour the mesh" is on
    by default; before, it declared a colouring it did not do and the mesh turned white), and
    MeshLab's Colorize by vertex Quality accepts the quality it wrote."""
    plugins = system_plugins()
    plugins[OURS] = our_plugin
    with MeshLabGui(tmp_path / "gui", plugins, NOISY_FANDISK / "clean.ply",
                    screen=(1366, 768)) as gui:
        before = coloured_share(view_pixels(gui))
        assert gui.open_filter_dialog(ANALYSE) == ANALYSE
        assert f"Applied filter {ANALYSE} in" in gui.apply_open_dialog(ANALYSE), gui.log()
        after = coloured_share(view_pixels(gui))
        save_for_docs(gui, "gui_clean_fandisk_saliency", 1366, 768)
        assert before < 0.02 and after > 0.15, (before, after)
        assert gui.open_filter_dialog(COLORIZE) == COLORIZE, gui.log()
        assert f"Applied filter {COLORIZE} in" in gui.apply_open_dialog(COLORIZE), gui.log()


def test_smoothing_dialog_fits_a_1366_by_768_screen(tmp_path, our_plugin):
    """The dialog, with its description and every parameter, fits the screen with Apply on it."""
    plugins = system_plugins()
    plugins[OURS] = our_plugin
    with MeshLabGui(tmp_path / "gui", plugins, NOISY_FANDISK / "noisy.ply",
                    screen=(1366, 768)) as gui:
        assert gui.open_filter_dialog(SMOOTH) == SMOOTH
        dialog = gui.find_titled(SMOOTH)
        gui.xdotool("windowsize", "--sync", gui.main_window, 860, 752)
        gui.xdotool("windowmove", "--sync", dialog, 864, 0)
        box = gui.geometry(dialog)
        assert box["HEIGHT"] <= 768 - 40, box  # room for a desktop's panel
        assert box["X"] + box["WIDTH"] <= 1366, box
        gui.xdotool("mousemove", 0, 767)
        time.sleep(1.0)
        save_for_docs(gui, "filter_dialog", 1366, 768)
