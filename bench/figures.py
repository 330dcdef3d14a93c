"""The benchmark's pictures: before/after renderings, a saliency heat map, theta vs iterations and
time vs vertex count. PNGs are kept small (< 300 KB) so that they can live in the repository."""
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import meshio  # noqa: E402
import render  # noqa: E402

PEERS = ["Laplacian", "HC Laplacian", "Taubin", "TwoStep"]
# (case, azimuth, elevation, up axis) of the before/after figures; the first three that exist.
RENDER_CASES = [("Fandisk0.3", 215, 25, "z"), ("paper cow n0.2", 200, 15, "y"),
                ("armadillo r0.2", 200, 10, "y"), ("Block0.4", 30, 30, "z")]
PANEL = 330


def best_peer(r):
    """(label, scores) of the MeshLab filter+setting with the lowest theta on a case."""
    options = []
    for p in PEERS:
        for w in ("default", "best"):
            s = r[f"{p} {w}"]
            if "theta_deg" in s and s["theta_deg"] is not None and "path" in s:
                setting = s.get("setting") if w == "best" else "default"
                options.append((s["theta_deg"], f"{p} ({setting})", s))
    if not options:
        return None, None
    options.sort(key=lambda o: o[0])
    return options[0][1], options[0][2]


def save(fig, path):
    fig.savefig(path, dpi=100)
    plt.close(fig)
    size = pathlib.Path(path).stat().st_size
    if size > 300_000:  # quantise to a palette image when a figure comes out too large
        try:
            from PIL import Image
            Image.open(path).convert("P", palette=Image.ADAPTIVE, colors=128).save(path)
        except ImportError:
            pass


def before_after(case, r, rotation, path):
    clean_points, faces, _ = meshio.read_mesh(case["clean"])
    cam = clean_points @ rotation.T
    frame = render.camera_frame(cam)
    peer_label, peer = best_peer(r)
    panels = [("noisy", case["noisy"], r["noisy"])]
    for label, key in (("ours (automatic, default)", "ours automatic (default)"),
                       ("ours (ring barycentre)", "ours ring barycentre"),
                       ("ours (feature-preserving)", "ours feature-preserving"),
                       ("ours (organic)", "ours organic")):
        if "path" in r.get(key, {}):
            panels.append((label, r[key]["path"], r[key]))
    if peer is not None:
        panels.append((f"MeshLab {peer_label}", peer["path"], peer))
    sd = [(r[k]["theta_deg"], label, r[k]) for k, label in
          (("SD filter default", "defaults"), ("SD filter best", r.get("SD filter best", {}).get(
              "setting"))) if r.get(k, {}).get("theta_deg") is not None and "path" in r[k]]
    if sd:
        _, label, scores = min(sd, key=lambda o: o[0])
        panels.append((f"SD filter ({label})", scores["path"], scores))
    panels.append(("clean", case["clean"], None))
    fig, axes = plt.subplots(1, len(panels), figsize=(len(panels) * PANEL / 100, PANEL / 100 + 0.5))
    for ax, (title, mesh_path, scores) in zip(axes, panels):
        points, f, _ = meshio.read_mesh(mesh_path)
        ax.imshow(render.render(points, f, rotation, size=PANEL, frame=frame))
        if scores is not None:
            title += f"\nθ {scores['theta_deg']:.2f}°  Ev {scores['ev_1e3']:.2f}e-3"
        else:
            title += "\n "
        ax.set_title(title, fontsize=8)
        ax.axis("off")
    fig.suptitle(case["name"], fontsize=10)
    fig.tight_layout(pad=0.3, rect=(0, 0, 1, 0.88))
    save(fig, path)


def saliency_map(runner, cases, path, quick):
    """Saliency (the filter's quality output) on clean and noisy meshes."""
    wanted = [("Fandisk0.3", "clean", 215, 25, "z"), ("Fandisk0.3", "noisy", 215, 25, "z")]
    if not quick:
        wanted.append(("armadillo n0.1", "clean", 200, 10, "y"))
    by_name = {c["name"]: c for c in cases}
    panels = []
    for name, which, az, el, up in wanted:
        case = by_name.get(name)
        if case is None:
            continue
        src = case[which]
        out = case["dir"] / f"saliency_{which}.ply"
        runner.run([runner.tools / "smooth_mesh", "--filter", "saliency", src, out])
        points, faces, quality = meshio.read_mesh(out)
        if quality is None:
            continue
        label = name.split()[0].replace("0.3", "")
        panels.append((f"{label} ({which})", points, faces, quality,
                       render.view_rotation(az, el, up)))
    if not panels:
        return False
    fig, axes = plt.subplots(1, len(panels), figsize=(len(panels) * PANEL / 100 + 0.6,
                                                      PANEL / 100 + 0.4))
    axes = np.atleast_1d(axes)
    cmap = plt.get_cmap("YlOrRd")
    for ax, (title, points, faces, q, rot) in zip(axes, panels):
        lo, hi = np.percentile(q, 1), np.percentile(q, 99)
        fq = q[faces].mean(1)
        colors = cmap(np.clip((fq - lo) / max(hi - lo, 1e-300), 0, 1))[:, :3]
        ax.imshow(render.render(points, faces, rot, size=PANEL, face_colors=colors,
                                ambient=0.6))
        ax.set_title(title, fontsize=9)
        ax.axis("off")
    fig.suptitle("Multi-scale saliency (stage 3): pale = low, red = high (1st–99th percentile)",
                 fontsize=9)
    fig.tight_layout(pad=0.3, rect=(0, 0, 1, 0.92))
    save(fig, path)
    return True


def iterations_plot(curves, path):
    names = list(curves)
    cols = min(4, len(names))
    rows = (len(names) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.6 * rows), squeeze=False)
    for ax, name in zip(axes.flat, names):
        for label, style in (("ours ring barycentre", "o-"), ("Taubin", "s-"), ("Laplacian", "^-")):
            pts = [(n, t) for n, t in curves[name][label] if t is not None]
            if pts:
                x, y = zip(*pts)
                ax.plot(np.maximum(x, 0.5), y, style, ms=3, label=label)
        ax.set_xscale("log")
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("iterations (steps)", fontsize=8)
        ax.set_ylabel("θ (°)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(names):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=7)
    fig.suptitle("θ vs iterations (0 iterations = noisy input, drawn at 0.5)", fontsize=10)
    fig.tight_layout()
    save(fig, path)


def timing_plot(timing, path):
    methods = {}
    for label, t in timing.items():
        for method, m in t["methods"].items():
            if m.get("filter"):
                methods.setdefault(method, []).append((t["mesh"]["vertices"], m["filter"]))
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for method, pts in methods.items():
        pts.sort()
        x, y = zip(*pts)
        style = "o-" if method.startswith("ours") else "s--"
        ax.plot(x, y, style, ms=4, label=method)
    ref = sorted(methods.get("ours in-process, 1 thread", []))
    if len(ref) > 1:  # slope guide: time proportional to the vertex count
        x = np.array([ref[0][0], ref[-1][0]], dtype=float)
        ax.plot(x, ref[0][1] * x / x[0], ":", color="grey", label="∝ vertices")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("vertices")
    ax.set_ylabel("filter time (s)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title("Filter time vs vertex count (MeshLab: wall − load+save)", fontsize=10)
    fig.tight_layout()
    save(fig, path)


def make_all(runner, cases, quality, curves, timing, img_dir, quick):
    img_dir = pathlib.Path(img_dir)
    pictures = []
    by_name = {c["name"]: c for c in cases}
    done = 0
    for name, az, el, up in RENDER_CASES:
        if name not in by_name or done >= 3:
            continue
        file = "before_after_" + name.replace(" ", "_").replace(".", "") + ".png"
        before_after(by_name[name], quality[name], render.view_rotation(az, el, up),
                     img_dir / file)
        pictures.append((f"{name}: noisy, ours (default, ring barycentre, feature-preserving, "
                          "organic), best MeshLab filter, best SD filter setting, clean", file))
        done += 1
    if saliency_map(runner, cases, img_dir / "saliency.png", quick):
        pictures.append(("Saliency heat map", "saliency.png"))
    if curves:
        iterations_plot(curves, img_dir / "theta_vs_iterations.png")
        pictures.append(("θ vs iterations", "theta_vs_iterations.png"))
    if timing:
        timing_plot(timing, img_dir / "time_vs_vertices.png")
        pictures.append(("Time vs vertex count", "time_vs_vertices.png"))
    return pictures


def panel_row(panels, rotation, path, title, frame_points=None, size=PANEL):
    """One row of flat-shaded renderings in the same view and frame: panels = [(title, mesh path
    or (points, faces))]; the frame fits `frame_points` (default: the first panel's vertices)."""
    meshes = []
    for label, mesh in panels:
        points, faces = (mesh if isinstance(mesh, tuple) else meshio.read_mesh(mesh)[:2])
        meshes.append((label, points, faces))
    frame = render.camera_frame((meshes[0][1] if frame_points is None else frame_points)
                                @ rotation.T)
    fig, axes = plt.subplots(1, len(meshes), figsize=(len(meshes) * size / 100, size / 100 + 0.5))
    for ax, (label, points, faces) in zip(np.atleast_1d(axes), meshes):
        ax.imshow(render.render(points, faces, rotation, size=size, frame=frame))
        ax.set_title(label, fontsize=8)
        ax.axis("off")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(pad=0.3, rect=(0, 0, 1, 0.88))
    save(fig, path)
