"""Flat-shaded z-buffer rendering of triangle meshes (numpy only) for the benchmark's
before/after pictures: orthographic view, one grey level per face so that noise and facets show."""
import numpy as np


def view_rotation(azimuth_deg, elevation_deg, up="z"):
    """Rotation taking world coordinates to camera coordinates (x right, y up, z towards viewer)
    for a camera on a sphere around the object whose world up axis is `up` ("z" or "y")."""
    az, el = np.radians(azimuth_deg), np.radians(elevation_deg)
    rz = np.array([[np.cos(az), -np.sin(az), 0], [np.sin(az), np.cos(az), 0], [0, 0, 1]])
    # after rz, look along +y towards the object: camera x = world x, camera y = world z,
    # camera z = -world y; then tilt by the elevation
    to_cam = np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]], dtype=float)
    rx = np.array([[1, 0, 0], [0, np.cos(el), np.sin(el)], [0, -np.sin(el), np.cos(el)]])
    y_up = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], dtype=float)  # world y -> z
    return rx @ to_cam @ rz @ (y_up if up == "y" else np.eye(3))


def render(points, faces, rotation, size=400, frame=None, face_colors=None,
           light=(0.35, 0.45, 1.0), ambient=0.18):
    """RGB uint8 image (size x size). `frame` = (centre, half extent) in camera coordinates,
    shared by the panels of one figure so that they line up; `face_colors` (m,3) in [0,1] are
    multiplied by the shading (default light grey); `ambient` is the shade of a face seen edge-on
    (raise it for colour maps so that the colours, not the facets, carry the picture)."""
    cam = np.asarray(points, dtype=np.float64) @ rotation.T
    faces = np.asarray(faces, dtype=np.int64)
    if frame is None:
        frame = camera_frame(cam)
    centre, half = frame
    scale = (size / 2 - 4) / half
    px = (cam[:, 0] - centre[0]) * scale + size / 2
    py = size / 2 - (cam[:, 1] - centre[1]) * scale
    pz = cam[:, 2]

    a, b, c = cam[faces[:, 0]], cam[faces[:, 1]], cam[faces[:, 2]]
    normals = np.cross(b - a, c - a)
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    light = np.asarray(light, dtype=float) / np.linalg.norm(light)
    lambert = normals @ light
    # two-sided: back faces (holes, folds) show darker and tinted so that they stand out
    back = normals[:, 2] < 0
    shade = ambient + (1 - ambient) * np.abs(lambert)
    if face_colors is None:
        face_colors = np.tile([0.85, 0.85, 0.82], (len(faces), 1))
    colors = face_colors * shade[:, None]
    colors[back] = colors[back] * np.array([0.75, 0.55, 0.55])

    depth = np.full((size, size), -np.inf)
    image = np.ones((size, size, 3))
    fx, fy, fz = px[faces], py[faces], pz[faces]
    xmin = np.clip(np.floor(fx.min(1)).astype(int), 0, size - 1)
    xmax = np.clip(np.ceil(fx.max(1)).astype(int), 0, size - 1)
    ymin = np.clip(np.floor(fy.min(1)).astype(int), 0, size - 1)
    ymax = np.clip(np.ceil(fy.max(1)).astype(int), 0, size - 1)
    for f in range(len(faces)):
        xs = np.arange(xmin[f], xmax[f] + 1)
        ys = np.arange(ymin[f], ymax[f] + 1)
        if len(xs) == 0 or len(ys) == 0:
            continue
        gx, gy = np.meshgrid(xs + 0.5, ys + 0.5)
        x0, x1, x2 = fx[f]
        y0, y1, y2 = fy[f]
        det = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2)
        if abs(det) < 1e-12:
            continue
        l0 = ((y1 - y2) * (gx - x2) + (x2 - x1) * (gy - y2)) / det
        l1 = ((y2 - y0) * (gx - x2) + (x0 - x2) * (gy - y2)) / det
        l2 = 1 - l0 - l1
        inside = (l0 >= -1e-9) & (l1 >= -1e-9) & (l2 >= -1e-9)
        if not inside.any():
            continue
        z = l0 * fz[f, 0] + l1 * fz[f, 1] + l2 * fz[f, 2]
        iy = (gy - 0.5).astype(int)
        ix = (gx - 0.5).astype(int)
        closer = inside & (z > depth[iy, ix])
        depth[iy[closer], ix[closer]] = z[closer]
        image[iy[closer], ix[closer]] = colors[f]
    return (np.clip(image, 0, 1) * 255).astype(np.uint8)


def camera_frame(cam_points, margin=1.02):
    lo, hi = cam_points.min(0), cam_points.max(0)
    centre = 0.5 * (lo + hi)
    half = 0.5 * max(hi[0] - lo[0], hi[1] - lo[1]) * margin
    return centre[:2], half


def crop_frame(points, rotation, centre_world, half_extent):
    """A frame showing the neighbourhood of `centre_world` (close-ups of features)."""
    c = np.asarray(centre_world, dtype=float) @ rotation.T
    return c[:2], half_extent
