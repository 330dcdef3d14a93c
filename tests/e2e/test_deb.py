"""End-to-end: the Debian package of the MeshLab 2020.09 plugin (CPack's DEB generator), as a
Debian MeshLab user installs it: `apt-get install ./<deb>` puts the plugin into the system plugin
folder, where the system's own /usr/bin/meshlabserver and /usr/bin/meshlab load it, and
`apt-get remove` takes it out.

This is the only test that touches the system: it runs as root, one at a time on the machine (a
lock file), and leaves the plugin folder as it found it: the package is removed in a `finally`,
a copy installed by `cmake --install` before the test is put back byte for byte, and a package
left behind by a killed run of this test (a marker file says so) is purged first. Every other
test runs private copies of meshlab/meshlabserver with their own plugins/ folder, which never
read the system folder, so they cannot load this package's copy even while it is installed.
"""
import contextlib
import fcntl
import hashlib
import os
import pathlib
import re
import subprocess

import pytest

from conftest import BUILD, REPO, mesh_compare, run_meshlabserver
from meshlab_gui import MeshLabGui
from test_gui import write_icosphere

PACKAGE = "meshlab-plugin-saliency-bezier"
PLUGIN_FOLDER = pathlib.Path("/usr/lib/x86_64-linux-gnu/meshlab/plugins")
SYSTEM_PLUGIN = PLUGIN_FOLDER / "libfilter_saliency_bezier_smooth.so"
LOCK = pathlib.Path("/tmp/meshlab-plugin-saliency-bezier-test.lock")
MARKER = pathlib.Path("/var/tmp/meshlab-plugin-saliency-bezier-test.installed")
SMOOTH = "Saliency Bezier Smooth"
APT = ["apt-get", "-y", "-q", "-o", "DPkg::Lock::Timeout=600"]


def run(command, timeout=900, **kwargs):
    return subprocess.run([str(c) for c in command], capture_output=True, text=True,
                          timeout=timeout, **kwargs)


def installed():
    status = run(["dpkg-query", "-W", "-f=${Status}", PACKAGE]).stdout
    return status.strip() == "install ok installed"


def folder_state():
    """name -> sha256 of every file in the system plugin folder."""
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(PLUGIN_FOLDER.iterdir()) if p.is_file()}


def system_meshlabserver(args):
    """The system's own meshlabserver (system plugin folder), under Xvfb, as a user runs it."""
    return run(["xvfb-run", "-a", "/usr/bin/meshlabserver", *args], timeout=600)


@pytest.fixture(scope="module")
def deb(tmp_path_factory):
    out = tmp_path_factory.mktemp("deb")
    config = BUILD / "CPackConfig.cmake"
    if not config.exists():
        pytest.fail(f"{config} missing: configure the build with BUILD_PLUGIN=ON (scripts/build.sh)")
    made = run(["cpack", "-G", "DEB", "-B", out, "--config", config], cwd=out)
    assert made.returncode == 0, made.stdout + made.stderr
    debs = list(out.glob(f"{PACKAGE}_*_amd64.deb"))
    assert len(debs) == 1, made.stdout
    return debs[0]


@contextlib.contextmanager
def system_plugin_folder_restored():
    """Holds the machine-wide lock; afterwards the package is gone and the folder as before."""
    if os.geteuid() != 0:
        pytest.fail("installing a .deb needs root (the test suite runs as root)")
    with open(LOCK, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if installed():
            if not MARKER.exists():
                pytest.fail(f"{PACKAGE} is installed on this machine (not by this test): "
                            f"`apt remove {PACKAGE}` first; the test will not replace it")
            purge = run(APT + ["purge", PACKAGE], env=dict(os.environ, DEBIAN_FRONTEND="noninteractive"))
            assert purge.returncode == 0, purge.stdout + purge.stderr  # a killed run's leftover
        before = folder_state()
        # A copy that `cmake --install` put there (no package owns it) is set aside for the test.
        unowned = ((SYSTEM_PLUGIN.read_bytes(), SYSTEM_PLUGIN.stat().st_mode)
                   if SYSTEM_PLUGIN.exists() else None)
        MARKER.write_text(f"installed by tests/e2e/test_deb.py, pid {os.getpid()}\n")
        try:
            SYSTEM_PLUGIN.unlink(missing_ok=True)
            yield before
        finally:
            if installed():
                run(APT + ["purge", PACKAGE], env=dict(os.environ, DEBIAN_FRONTEND="noninteractive"))
            if unowned is not None:
                SYSTEM_PLUGIN.write_bytes(unowned[0])
                SYSTEM_PLUGIN.chmod(unowned[1])
            if not installed():
                MARKER.unlink(missing_ok=True)


def test_deb_fields_and_contents(deb):
    fields = {k: run(["dpkg-deb", "-f", deb, k]).stdout.strip()
              for k in ("Package", "Version", "Architecture", "Depends")}
    version = re.search(r"project\(saliency_bezier_smooth VERSION ([0-9.]+)",
                        (REPO / "CMakeLists.txt").read_text()).group(1)
    assert fields["Package"] == PACKAGE
    assert fields["Version"] == version + "-1", fields
    assert fields["Architecture"] == "amd64"
    depends = [d.strip() for d in fields["Depends"].split(",")]
    assert depends[:2] == ["meshlab (>= 2020.09)", "meshlab (<< 2020.10~)"], depends
    assert any(d.startswith("libqt5core5a") for d in depends), depends  # from dpkg-shlibdeps
    # The constraint takes Debian 12's meshlab and its later Debian revisions, no other upstream.
    for candidate, accepted in (("2020.09+dfsg1-2", True), ("2020.09+dfsg1-2+deb12u1", True),
                                ("2020.09+dfsg1-3", True), ("2020.07-1", False),
                                ("2022.02+dfsg1-1", False), ("2025.07~dfsg-4", False)):
        ok = (run(["dpkg", "--compare-versions", candidate, "ge", "2020.09"]).returncode == 0 and
              run(["dpkg", "--compare-versions", candidate, "lt", "2020.10~"]).returncode == 0)
        assert ok == accepted, candidate
    files = [line.split() for line in run(["dpkg-deb", "-c", deb]).stdout.splitlines()]
    regular = [(f[0], f[-1]) for f in files if not f[0].startswith("d")]
    assert regular == [("-rw-r--r--", "./" + str(SYSTEM_PLUGIN).lstrip("/"))], files


def test_apt_install_meshlabserver_gui_and_remove(deb, tmp_path, shared):
    case = shared / "data" / "benchmark" / "Fandisk0.3"
    script = REPO / "examples" / "saliency_bezier_smooth.mlx"
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    with system_plugin_folder_restored() as before:
        # Control: without the package the system meshlabserver does not know the filter.
        control = tmp_path / "control.ply"
        system_meshlabserver(["-i", case / "noisy.ply", "-o", control, "-s", script])
        assert not control.exists()

        install = run(APT + ["install", deb.resolve()], env=env)
        assert install.returncode == 0, install.stdout + install.stderr
        assert installed()
        owner = run(["dpkg", "-S", SYSTEM_PLUGIN]).stdout
        assert owner.startswith(PACKAGE + ":"), owner

        # The system meshlabserver now runs the example script, as the private copy does.
        out = tmp_path / "smoothed.ply"
        smoothed = system_meshlabserver(["-i", case / "noisy.ply", "-o", out, "-m", "vq",
                                         "-s", script])
        assert smoothed.returncode == 0 and out.exists(), smoothed.stdout + smoothed.stderr
        noisy_score, score = (mesh_compare(case / "noisy.ply", case / "clean.ply"),
                              mesh_compare(out, case / "clean.ply"))
        assert score["theta_deg"] < 0.5 * noisy_score["theta_deg"], score
        assert abs(score["volume_ratio"] - 1.0) < 0.01, score
        private = tmp_path / "private.ply"
        reference = run_meshlabserver(["-i", case / "noisy.ply", "-o", private, "-m", "vq",
                                       "-s", script])
        assert reference.returncode == 0, reference.stdout + reference.stderr
        assert out.read_bytes() == private.read_bytes()

        # The system GUI lists it: MeshLab's filter search opens its dialog, Apply runs it.
        mesh = write_icosphere(tmp_path / "icosphere.ply")
        with MeshLabGui(tmp_path / "gui", None, mesh, executable="/usr/bin/meshlab") as gui:
            assert gui.open_filter_dialog(SMOOTH) == SMOOTH, gui.log()
            verdict = gui.apply_open_dialog(SMOOTH)
            assert f"Applied filter {SMOOTH} in" in verdict, gui.log()

        remove = run(APT + ["remove", PACKAGE], env=env)
        assert remove.returncode == 0, remove.stdout + remove.stderr
        assert not installed()
        assert not SYSTEM_PLUGIN.exists()
    assert folder_state() == before  # as it was (a set-aside unowned copy is back)
