"""Drives the real MeshLab 2020.09 GUI (a private copy of /usr/bin/meshlab) on its own Xvfb screen
with xdotool: opens a filter's dialog through MeshLab's filter search (Ctrl+F), applies it, and
takes screenshots of it.

MeshLab 2020.09 logs through qDebug to stderr: for a plugin that does not load, QPluginLoader's
error, which names the file's real path (PluginManager::loadPlugins), e.g. "'<path>' is an invalid
ELF object (...)" or "Cannot load library <path>: (...)"; and every line of its log window as
"LOG: <level> <text>" (GLLogStream), e.g. "LOG: 0 All files opened in 36 msec" and
"LOG: 0 Applied filter <name> in <n> msec". Nothing is logged for a plugin that loads.
A filter's parameter dialog (MeshlabStdDialog) is a floating top-level window titled with the
filter's name, and its Apply button has the keyboard focus when it opens.

Screenshots for the docs (needs imagemagick's `import`; SBS_BUILD_DIR as for the tests):
    .venv/bin/python tests/e2e/meshlab_gui.py --mesh M.ply --filter "Saliency Bezier Smooth" OUT.png
"""
import argparse
import os
import pathlib
import select
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from conftest import MESHLAB_LIB, PRIVATE_MESHLAB  # noqa: E402

MAIN_TITLE_PREFIX = "MeshLab 2020.09"
# Qt's helper windows and the main window's docks, toolbars and menus carry these names.
NOT_A_DIALOG = {"", "MeshLab_64bit_fp", "Qt Selection Owner for meshlab"}


def wait_for(condition, timeout, what, log=lambda: ""):
    """Polls condition() until it returns something truthy, which is returned."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise TimeoutError(f"timed out after {timeout} s waiting for {what}\n{log()}")
        time.sleep(0.1)


def plugin_folder(folder, plugins):
    """A plugins/ folder: plugins maps a file name to the file it links to, or to its bytes."""
    folder.mkdir(parents=True)
    for name, target in plugins.items():
        if isinstance(target, bytes):
            (folder / name).write_bytes(target)
        else:
            (folder / name).symlink_to(pathlib.Path(target).resolve())
    return folder


def system_plugins():
    """MeshLab's own plugins (the build links them next to the private meshlab), ours left out."""
    return {p.name: p for p in sorted((PRIVATE_MESHLAB / "plugins").glob("*.so"))
            if p.name != "libfilter_saliency_bezier_smooth.so"}


class MeshLabGui:
    """One MeshLab GUI on a fresh Xvfb screen, with a plugins/ folder and settings of its own.

    MeshLab looks for plugins/ next to its executable (after resolving links), so the executable
    is copied into workdir."""

    def __init__(self, workdir, plugins, mesh=None, screen=(1280, 1024), executable=None):
        """executable: run that MeshLab as it is (e.g. /usr/bin/meshlab, which loads the system
        plugin folder) instead of a private copy with `plugins` (then None)."""
        self.workdir = pathlib.Path(workdir)
        self.plugins, self.mesh, self.screen = plugins, mesh, screen
        self.executable = executable
        self.xvfb = self.meshlab = None
        self.env = None
        self.log_path = self.workdir / "meshlab.log"

    def __enter__(self):
        try:
            self.start()
        except BaseException:
            self.stop()
            raise
        return self

    def __exit__(self, *exc):
        self.stop()

    def start(self, timeout=60):
        if self.executable:
            program = pathlib.Path(self.executable)
        else:
            app = self.workdir / "meshlab"
            app.mkdir(parents=True)
            shutil.copy2(PRIVATE_MESHLAB / "meshlab", app / "meshlab")
            plugin_folder(app / "plugins", self.plugins)
            program = app / "meshlab"
        home = self.workdir / "home"
        (home / "runtime").mkdir(parents=True)
        (home / "runtime").chmod(0o700)

        # -displayfd: Xvfb picks a free display itself and writes its number to the pipe once it
        # accepts connections, so parallel sessions never race for a display number.
        read_end, write_end = os.pipe()
        xvfb_log = self.workdir / "xvfb.log"
        with open(xvfb_log, "wb") as errors:
            self.xvfb = subprocess.Popen(
                ["Xvfb", "-displayfd", str(write_end), "-nolisten", "tcp", "-screen", "0",
                 f"{self.screen[0]}x{self.screen[1]}x24"],
                pass_fds=(write_end,), stdout=subprocess.DEVNULL, stderr=errors)
        os.close(write_end)
        # Xvfb writes the number and the newline separately and dies if the pipe is closed between
        # the two writes: read up to the newline.
        number = b""
        try:
            deadline = time.monotonic() + timeout
            while not number.endswith(b"\n"):
                ready, _, _ = select.select([read_end], [], [], max(0, deadline - time.monotonic()))
                chunk = os.read(read_end, 64) if ready else b""
                if not chunk:
                    raise RuntimeError(f"Xvfb did not start\n{xvfb_log.read_text()}")
                number += chunk
        finally:
            os.close(read_end)
        number = number.decode().strip()

        self.env = dict(os.environ, DISPLAY=f":{number}", HOME=str(home),
                        XDG_RUNTIME_DIR=str(home / "runtime"),
                        LD_LIBRARY_PATH=MESHLAB_LIB + ":" + os.environ.get("LD_LIBRARY_PATH", ""))
        self.env.pop("XAUTHORITY", None)
        command = [str(program)] + ([str(self.mesh)] if self.mesh else [])
        with open(self.log_path, "wb") as log:
            self.meshlab = subprocess.Popen(command, env=self.env, stdout=log,
                                            stderr=subprocess.STDOUT, cwd=self.workdir)
        self.main_window = wait_for(lambda: self.find_window("^" + MAIN_TITLE_PREFIX) or
                                    self.check_alive(), timeout, "the MeshLab main window",
                                    self.log)
        if self.mesh:
            wait_for(lambda: "All files opened" in self.log() or self.check_alive(), timeout,
                     "the mesh to load", self.log)

    def stop(self):
        for process in (self.meshlab, self.xvfb):
            if process and process.poll() is None:
                process.terminate()
                try:
                    process.wait(10)
                except subprocess.TimeoutExpired:
                    process.kill()
                    process.wait()

    def log(self):
        return self.log_path.read_text(errors="replace") if self.log_path.exists() else ""

    def check_alive(self):
        """None while MeshLab runs (for wait_for conditions); raises once it has exited."""
        if self.meshlab.poll() is not None:
            raise RuntimeError(f"MeshLab exited with {self.meshlab.returncode}\n{self.log()}")
        return None

    def xdotool(self, *args):
        return subprocess.run(["xdotool", *map(str, args)], env=self.env, capture_output=True,
                              text=True, timeout=30).stdout

    def find_window(self, name_regex):
        """The first visible window whose name matches (a POSIX regular expression), or None."""
        ids = self.xdotool("search", "--onlyvisible", "--name", name_regex).split()
        return ids[0] if ids else None

    def find_titled(self, title):
        """The visible window named exactly title, or None."""
        return self.find_window("^" + "".join("\\" + c if c in ".^$*+?()[]{}|\\" else c
                                              for c in title) + "$")

    def dialog_titles(self):
        """Names of the visible windows that are neither the main window nor its parts."""
        titles = []
        for window in self.xdotool("search", "--onlyvisible", "--name", "").split():
            name = self.xdotool("getwindowname", window).strip()
            if name not in NOT_A_DIALOG and not name.startswith(MAIN_TITLE_PREFIX):
                titles.append(name)
        return titles

    def open_filter_dialog(self, query, timeout=30):
        """Types query into MeshLab's filter search (Ctrl+F), picks the first result and returns the
        title of the filter dialog that opens (it replaces any dialog open before). Qt handles the
        keys in order: the search menu opens on Ctrl+F and every later key goes to it, so no key
        needs a pause."""
        before = set(self.dialog_titles())
        self.xdotool("windowfocus", "--sync", self.main_window)
        self.xdotool("key", "ctrl+f", "ctrl+a")  # the search line keeps the last search
        self.xdotool("type", "--delay", 20, query)
        self.xdotool("key", "Down", "Return")
        return wait_for(lambda: next((t for t in self.dialog_titles() if t not in before), None)
                        or self.check_alive(),
                        timeout, f"a filter dialog after searching {query!r}", self.log)

    def apply_open_dialog(self, title, timeout=60):
        """Presses the focused Apply button of the dialog and waits for MeshLab's verdict."""
        self.xdotool("windowfocus", "--sync", self.find_titled(title))
        self.xdotool("key", "space")
        return wait_for(lambda: next((line for line in self.log().splitlines()
                                      if f"Applied filter {title} in" in line
                                      or "Filter failed" in line), None) or
                        self.check_alive(),
                        timeout, f"MeshLab to apply {title!r}", self.log)

    def geometry(self, window):
        """{'X', 'Y', 'WIDTH', 'HEIGHT'} of a window, in screen pixels."""
        shell = self.xdotool("getwindowgeometry", "--shell", window)
        return {key: int(value) for key, value in
                (line.split("=") for line in shell.split() if "=" in line) if key != "SCREEN"}

    def grab(self, x, y, width, height):
        """The screen's pixels in a rectangle as an (height, width, 3) uint8 array."""
        import numpy as np
        ppm = subprocess.run(["import", "-window", "root", "-crop", f"{width}x{height}+{x}+{y}",
                              "+repage", "ppm:-"], env=self.env, check=True, timeout=60,
                             capture_output=True).stdout
        # P6 header: magic, width, height, maxval, each followed by one whitespace byte.
        fields, start = [], 0
        while len(fields) < 4:
            end = start
            while ppm[end:end + 1].isspace():
                end += 1
            start = end
            while not ppm[end:end + 1].isspace():
                end += 1
            fields.append(ppm[start:end])
            start = end
        w, h = int(fields[1]), int(fields[2])
        return np.frombuffer(ppm[start + 1:start + 1 + w * h * 3], dtype=np.uint8).reshape(h, w, 3)

    def screenshot(self, path, width, height):
        """PNG of the screen's top-left width x height pixels, in 256 colours to stay small."""
        subprocess.run(["import", "-window", "root", "-crop", f"{width}x{height}+0+0", "+repage",
                        "-colors", "256", f"png8:{path}"], env=self.env, check=True, timeout=60)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output", type=pathlib.Path)
    parser.add_argument("--mesh", type=pathlib.Path, required=True)
    parser.add_argument("--filter", default="Saliency Bezier Smooth")
    parser.add_argument("--workdir", type=pathlib.Path, default=None)
    parser.add_argument("--screen", default="1366x768", help="WIDTHxHEIGHT of the screen")
    args = parser.parse_args()
    plugins = system_plugins()
    plugins["libfilter_saliency_bezier_smooth.so"] = (
        PRIVATE_MESHLAB / "plugins" / "libfilter_saliency_bezier_smooth.so")
    with tempfile.TemporaryDirectory() as tmp:
        workdir = args.workdir or pathlib.Path(tmp)
        screen = tuple(int(x) for x in args.screen.split("x"))
        with MeshLabGui(workdir, plugins, args.mesh.resolve(), screen=screen) as gui:
            title = gui.open_filter_dialog(args.filter)
            if title != args.filter:
                sys.exit(f"opened {title!r} instead of {args.filter!r}\n{gui.log()}")
            dialog = gui.find_titled(title)
            # No window manager: put the dialog beside the main window, as a user would.
            gui.xdotool("windowsize", "--sync", gui.main_window, 860, 752)
            main = gui.geometry(gui.main_window)
            gui.xdotool("windowmove", "--sync", dialog, main["WIDTH"] + 4, 0)
            gui.xdotool("mousemove", 0, gui.screen[1] - 1)
            time.sleep(1.0)  # let the GL view and the moved dialog repaint
            box = gui.geometry(dialog)
            gui.screenshot(args.output, box["X"] + box["WIDTH"],
                           max(box["Y"] + box["HEIGHT"], main["HEIGHT"]))
    print(args.output)


if __name__ == "__main__":
    main()
