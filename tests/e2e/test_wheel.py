"""End-to-end: the wheel a PyMeshLab user installs, and its batch command.

scripts/build_wheel.sh builds the wheel from this checkout (pip wheel: scikit-build-core in pip's
isolated build environment, with pymeshlab==2025.7.post1 as a build requirement; then auditwheel
for the platform tag). A fresh venv gets that wheel and, from PyPI, its dependencies (pymeshlab,
tqdm, Dask for the extra) and nothing of the checkout: every run below starts its Python with -I
(no PYTHONPATH, no current folder on sys.path) in a temporary folder.

The batch command smooths a generated folder of 20 meshes (noisy copies of five bundled meshes in
PLY, OFF and OBJ, one of them in a subfolder) plus two meshes the filter refuses, once with two
local processes (on a pseudo-terminal, to see its progress bars) and once on a Dask LocalCluster;
the outputs must be the same bytes.
"""
import filecmp
import json
import os
import pathlib
import re
import select
import subprocess
import sys
import zipfile

import numpy as np
import pytest

from conftest import BUILD, REPO, SHARED, mesh_compare, read_ply

SMOOTH = "apply_coord_saliency_bezier_smoothing"
PLUGIN_IN_WHEEL = "pymeshlab_saliency_bezier/lib/libfilter_saliency_bezier_smooth.so"


@pytest.fixture(scope="session")
def wheel(tmp_path_factory):
    out = tmp_path_factory.mktemp("dist")
    run = subprocess.run(["bash", str(REPO / "scripts" / "build_wheel.sh"), str(out)],
                         env=dict(os.environ, SBS_BUILD_DIR=str(BUILD)), capture_output=True,
                         text=True, timeout=3600)
    assert run.returncode == 0, run.stdout + run.stderr
    return pathlib.Path(run.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="session")
def venv(wheel, tmp_path_factory):
    """A new venv with the wheel (and its dask extra) installed from the file: python, bin dir."""
    root = tmp_path_factory.mktemp("venv")
    subprocess.run(["/usr/bin/python3", "-m", "venv", str(root)], check=True, timeout=300)
    install = subprocess.run([str(root / "bin" / "pip"), "install", "-q", f"{wheel}[dask]"],
                             capture_output=True, text=True, timeout=1800)
    assert install.returncode == 0, install.stdout + install.stderr
    return root / "bin" / "python", root / "bin"


def run_python(venv, code, cwd, timeout=600):
    """Runs code with the venv's Python in isolated mode from cwd; returns its JSON print."""
    python, _ = venv
    run = subprocess.run([str(python), "-I", "-c", code], cwd=cwd, capture_output=True, text=True,
                         timeout=timeout)
    assert run.returncode == 0, run.stdout + run.stderr
    return json.loads(run.stdout.strip().splitlines()[-1])


def max_glibc_needed(shared_object):
    """The newest GLIBC_2.N symbol version the shared object needs (readelf's version needs)."""
    text = subprocess.run(["readelf", "--version-info", "--wide", str(shared_object)],
                          check=True, capture_output=True, text=True).stdout
    return max(int(n) for n in re.findall(r"Name: GLIBC_2\.(\d+)", text))


def test_wheel_tag_contents_and_metadata(wheel, tmp_path):
    # The tag claims the glibc the plugin needs, which cannot be newer than the one it was built on.
    name = re.fullmatch(r"pymeshlab_saliency_bezier-([\d.]+)-py3-none-manylinux_2_(\d+)_x86_64\.whl",
                        wheel.name)
    assert name, wheel.name
    with zipfile.ZipFile(wheel) as archive:
        names = set(archive.namelist())
        archive.extract(PLUGIN_IN_WHEEL, tmp_path)
        metadata = archive.read(f"pymeshlab_saliency_bezier-{name.group(1)}.dist-info/METADATA").decode()
        entry_points = archive.read(
            f"pymeshlab_saliency_bezier-{name.group(1)}.dist-info/entry_points.txt").decode()
    plugin = tmp_path / PLUGIN_IN_WHEEL
    needed = max_glibc_needed(plugin)
    built_on = int(os.confstr("CS_GNU_LIBC_VERSION").split()[1].split(".")[1])
    assert int(name.group(2)) == needed <= built_on, (wheel.name, needed, built_on)

    # The plugin and the package, and none of pymeshlab's libraries (no <pkg>.libs/ folder).
    assert {n for n in names if not n.endswith("/")} == {
        "pymeshlab_saliency_bezier/__init__.py", "pymeshlab_saliency_bezier/__main__.py",
        "pymeshlab_saliency_bezier/batch.py", "pymeshlab_saliency_bezier/cli.py", PLUGIN_IN_WHEEL,
        *(f"pymeshlab_saliency_bezier-{name.group(1)}.dist-info/{f}"
          for f in ("METADATA", "WHEEL", "RECORD", "entry_points.txt"))}
    dynamic = subprocess.run(["readelf", "-d", str(plugin)], check=True, capture_output=True,
                             text=True).stdout
    assert "[libmeshlab-common.so]" in dynamic and "[libQt5Core.so.5]" in dynamic
    assert "RPATH" not in dynamic and "RUNPATH" not in dynamic  # resolved in pymeshlab's process
    assert "Requires-Dist: pymeshlab==2025.7.post1" in metadata
    assert "saliency-bezier-smooth = pymeshlab_saliency_bezier.cli:main" in entry_points


def test_both_filters_from_the_installed_wheel(venv, tmp_path, shared):
    case = shared / "data" / "benchmark" / "Fandisk0.3"
    out = tmp_path / "smoothed.ply"
    result = run_python(venv, f"""
import json, sys, numpy, pymeshlab
import pymeshlab_saliency_bezier as sbs
ms = pymeshlab.MeshSet()
ms.load_new_mesh({str(case / "noisy.ply")!r})
ms.apply_coord_saliency_bezier_smoothing()
ms.save_current_mesh({str(out)!r})
ms.compute_scalar_by_mesh_saliency_per_vertex()
saliency = ms.current_mesh().vertex_custom_scalar_attribute_array("Saliency")
print(json.dumps({{"module": sbs.__file__, "plugin": str(sbs.PLUGIN_PATH), "path": sys.path,
                  "n": len(saliency), "vertices": ms.current_mesh().vertex_number(),
                  "min": float(saliency.min()), "max": float(saliency.max()),
                  "finite": bool(numpy.isfinite(saliency).all())}}))
""", cwd=tmp_path)
    venv_root = venv[0].parent.parent
    assert pathlib.Path(result["module"]).is_relative_to(venv_root), result["module"]
    assert pathlib.Path(result["plugin"]).is_relative_to(venv_root)
    assert not any(str(REPO) in p for p in result["path"]), result["path"]
    noisy = mesh_compare(case / "noisy.ply", case / "clean.ply")
    smoothed = mesh_compare(out, case / "clean.ply")
    assert noisy["theta_deg"] == pytest.approx(28.42, abs=0.05)
    assert smoothed["theta_deg"] < 0.5 * noisy["theta_deg"], smoothed  # automatic mode: ~2.8
    assert smoothed["ev_1e3"] < noisy["ev_1e3"]
    assert result["n"] == result["vertices"] == 6475
    assert result["finite"] and 0.0 <= result["min"] and result["max"] == pytest.approx(1.0)


# ---- the batch command ----------------------------------------------------------------------------

def write_mesh(path, points, faces):
    """Binary PLY, ASCII OFF or OBJ by the file's extension."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.suffix == ".ply":
        header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(points)}\n"
                  "property float x\nproperty float y\nproperty float z\n"
                  f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        records = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", 3)])
        records["n"], records["i"] = 3, faces
        path.write_bytes(header.encode() + points.astype("<f4").tobytes() + records.tobytes())
    elif path.suffix == ".off":
        lines = ["OFF", f"{len(points)} {len(faces)} 0"]
        lines += ["%.7g %.7g %.7g" % tuple(p) for p in points]
        lines += ["3 %d %d %d" % tuple(f) for f in faces]
        path.write_text("\n".join(lines) + "\n")
    else:
        lines = ["v %.7g %.7g %.7g" % tuple(p) for p in points]
        lines += ["f %d %d %d" % tuple(f + 1) for f in faces]
        path.write_text("\n".join(lines) + "\n")


def mean_edge(points, faces):
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    return float(np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1).mean())


BASES = {"fandisk": "benchmark/Fandisk0.3/clean.ply", "block": "benchmark/Block0.4/clean.ply",
         "twelve": "benchmark/Twelve0.5Impulsive/clean.ply", "cow": "paper/cow.ply",
         "mountain": "paper/mountain_clean.ply"}


@pytest.fixture(scope="module")
def mesh_folder(tmp_path_factory):
    """20 noisy meshes (five bases, four noise draws each: 0.2-0.35 mean edge lengths in random 3-D
    directions; PLY, OFF, OBJ and a PLY in sub/), the clean bases, and two meshes to refuse:
    one too large for the filter, one without faces."""
    root = tmp_path_factory.mktemp("batch")
    folder, clean = root / "scans", {}
    for name, relative in BASES.items():
        vertices, faces = read_ply(SHARED / "data" / relative)
        points = np.stack([vertices["x"], vertices["y"], vertices["z"]], axis=1).astype(np.float64)
        clean[name] = (points, faces)
        for k, (where, sigma) in enumerate([("{}_0.ply", 0.2), ("{}_1.off", 0.25),
                                            ("{}_2.obj", 0.3), ("sub/{}_3.ply", 0.35)]):
            rng = np.random.default_rng(1000 * k + len(name))
            noisy = points + rng.normal(scale=sigma * mean_edge(points, faces), size=points.shape)
            write_mesh(folder / where.format(name), noisy, faces)
    # (A NaN coordinate would not do: PyMeshLab 2025.07's importer drops such a vertex and its
    # faces.) The filter refuses coordinates beyond 1e30.
    points, faces = clean["fandisk"]
    write_mesh(folder / "huge.ply", points * 1e32, faces)
    (folder / "points_only.ply").write_text(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n")
    (folder / "notes.txt").write_text("not a mesh: the folder search skips it\n")
    return root, folder, clean


def run_command(venv, args, cwd, tty=False, timeout=900):
    """(exit status, stdout, stderr) of saliency-bezier-smooth; with tty, on a pseudo-terminal of
    120 columns (stdout and stderr together in the second item)."""
    command = [str(venv[1] / "saliency-bezier-smooth"), *map(str, args)]
    if not tty:
        run = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=timeout)
        return run.returncode, run.stdout, run.stderr
    import fcntl
    import pty
    import struct
    import termios

    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 120, 0, 0))
    process = subprocess.Popen(command, cwd=cwd, stdin=slave, stdout=slave, stderr=slave)
    os.close(slave)
    output = b""
    while True:
        ready, _, _ = select.select([master], [], [], 1.0)
        chunk = b""
        if ready:
            try:
                chunk = os.read(master, 65536)
            except OSError:  # the terminal closed with the process
                chunk = b""
        output += chunk
        if not chunk and process.poll() is not None:
            break
    os.close(master)
    return process.wait(timeout=timeout), output.decode("utf-8", "replace"), ""


def outputs(folder):
    return sorted(p.relative_to(folder) for p in folder.rglob("*") if p.is_file())


def test_batch_folder_in_processes_and_on_dask(venv, mesh_folder):
    root, folder, clean = mesh_folder
    local, cluster = root / "out_local", root / "out_dask"
    status, screen, _ = run_command(
        venv, [folder, "-o", local, "-j", "2", "--report", root / "local.json"], root, tty=True)
    lines = screen.replace("\r", "\n")
    assert status == 1, screen  # two meshes refused
    # The overall bar ends at 22/22 (a bar's last state is drawn however fast the run; what it
    # drew in between depends on the machine's speed: the events are tested below).
    assert re.search(r"meshes: 100%.*22/22", lines), screen
    status_dask, stdout, stderr = run_command(
        venv, [folder, "-o", cluster, "--local-cluster", "2", "--report", root / "dask.json"], root)
    assert status_dask == 1, stdout + stderr

    expected = sorted(pathlib.Path(w.format(n)) for n in BASES
                      for w in ("{}_0.ply", "{}_1.off", "{}_2.obj", "sub/{}_3.ply"))
    assert outputs(local) == outputs(cluster) == expected  # no temporary or refused files left
    mismatch = filecmp.cmpfiles(local, cluster, [str(p) for p in expected], shallow=False)[1:]
    assert mismatch == ([], []), mismatch

    # One line per mesh: the refusals with the filter's / PyMeshLab's message, on stderr.
    assert re.search(r"REFUSED \S*huge\.ply: the mesh has vertex coordinates beyond 1e30", stderr), stderr
    assert re.search(r"REFUSED \S*points_only\.ply: .*(Faces|no faces)", stderr), stderr
    assert "smoothed, 2 refused, 0 failed" in stdout.splitlines()[-1], stdout
    assert "20 smoothed" in stdout.splitlines()[-1], stdout
    for path in expected:
        match = re.search(re.escape(str(folder / path)) + r" -> \S+: \d+ vertices, automatic -> "
                          r"([a-z-]+), [\d.]+ s \(filter [\d.]+ s\)", stdout)
        assert match, (path, stdout)
    for name in ("local", "dask"):
        report = {pathlib.Path(r["input"]).relative_to(folder): r
                  for r in json.loads((root / f"{name}.json").read_text())}
        assert len(report) == 22
        assert {str(p) for p, r in report.items() if r["status"] != "ok"} == {
            "huge.ply", "points_only.ply"}
        # The automatic mode's choice, as in docs/studies/feature-mode.md: CAD parts -> feature mode.
        for k in ("fandisk_0.ply", "block_1.off", "twelve_2.obj"):
            assert report[pathlib.Path(k)]["method"] == "feature-preserving", report[pathlib.Path(k)]
        assert report[pathlib.Path("cow_0.ply")]["method"] == "organic"

    # The smoothing is real: every PLY output is closer to its clean mesh than its input.
    for name, (points, faces) in clean.items():
        reference = root / f"clean_{name}.ply"
        write_mesh(reference, points, faces)
        for path in (pathlib.Path(f"{name}_0.ply"), pathlib.Path(f"sub/{name}_3.ply")):
            before = mesh_compare(folder / path, reference)["theta_deg"]
            after = mesh_compare(local / path, reference)["theta_deg"]
            assert after < 0.7 * before, (path, before, after)


def test_progress_events_follow_the_filter(venv, mesh_folder, tmp_path):
    """The events a mesh's bar is drawn from: load, the filter's own percentages, save, done; at
    least one every 10 points of the whole job whatever the machine's speed (the sequence comes
    from what the filter reports; only extra events depend on the clock)."""
    _, folder, _ = mesh_folder
    events = run_python(venv, f"""
import json
from pymeshlab_saliency_bezier import batch
events = []
result = batch.smooth_file({{"index": 7, "input": {str(folder / "fandisk_0.ply")!r},
                            "output": {str(tmp_path / "out.ply")!r}, "params": {{}}}},
                           emit=events.append)
assert result["status"] == "ok", result
print(json.dumps(events))
""", cwd=tmp_path)
    assert {e["index"] for e in events} == {7}
    stages = [e["stage"] for e in events]
    percents = [e["percent"] for e in events]
    assert (stages[0], percents[0]) == ("loading", 0), events
    assert (stages[-1], percents[-1]) == ("done", 100), events
    assert stages.index("saving") > stages.index("smoothing"), events
    assert percents == sorted(percents), events
    within = [p for s, p in zip(stages, percents) if s == "smoothing" and 5 < p < 95]
    assert len(within) >= 5, events  # the filter's own percentages, not just its start and end
    # No gap wider than 10 points plus the filter's own largest step (it reports every few
    # percent; its normal filter's stage is one step of about 17 % of the filter, 15 of the job).
    assert max(b - a for a, b in zip(percents, percents[1:])) <= 25, events


def test_batch_options_are_the_filter_parameters(venv, mesh_folder, tmp_path):
    """--method ring --strength 2 is placement=0, iterations=6 (the same bytes as the Python call);
    --iterations 6 is the same; a misspelt --param stops before any mesh is touched."""
    root, folder, _ = mesh_folder
    source = folder / "fandisk_0.ply"
    for name, args in (("strength", ["--strength", "2"]), ("iterations", ["--iterations", "6"])):
        status, stdout, stderr = run_command(
            venv, [source, "-o", tmp_path / name, "--method", "ring", *args], tmp_path)
        assert status == 0, stdout + stderr
        assert re.search(r"vertices, ring[ a-z-]*, ", stdout, re.IGNORECASE), stdout
    direct = tmp_path / "direct.ply"
    run_python(venv, f"""
import json, pymeshlab, pymeshlab_saliency_bezier
ms = pymeshlab.MeshSet()
ms.load_new_mesh({str(source)!r})
ms.apply_coord_saliency_bezier_smoothing(placement=0, iterations=6)
ms.save_current_mesh({str(direct)!r})
print(json.dumps(0))
""", cwd=tmp_path)
    assert direct.read_bytes() == (tmp_path / "strength" / "fandisk_0.ply").read_bytes()
    assert direct.read_bytes() == (tmp_path / "iterations" / "fandisk_0.ply").read_bytes()
    assert direct.read_bytes() != source.read_bytes()

    status, stdout, stderr = run_command(
        venv, [source, "-o", tmp_path / "bad", "--param", "preserve_volumes=false"], tmp_path)
    assert status == 2 and "preserve_volume=True" in stderr, stdout + stderr
    assert not (tmp_path / "bad").exists()
