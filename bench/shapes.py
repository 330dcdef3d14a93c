#!/usr/bin/env python3
"""Clean meshes of the objects people scan with depth cameras, made from analytic shapes at a
scanner-like resolution: near-uniform edge lengths (isotropic, like a depth scan's mesh) with
vertices exactly on the sharp creases and corners, so that the creases stay sharp in the clean
mesh. Each mesh is closed, 2-manifold, oriented outward, without degenerate faces or duplicate
vertices. Units are arbitrary (about 1); every shape stands on the z = 0 plane, centred in x y.

  box             1.0 x 0.7 x 0.45 (not a cube, so that the three face sizes differ)
  prism3          triangular prism lying on a face: equilateral triangle of side 0.5 (y z),
                  1.0 long (x)
  prism6          upright hexagonal prism: circumradius 0.35, height 0.8
  cylinder        radius 0.35, height 0.9 (a can)
  cone            base radius 0.45, height 0.9, and a small flat top of radius 0.08 instead of a
                  point: the remesher does not keep a point apex where no creases meet (tried:
                  the tip ends up 1 to 3 mean edges low), and scanned cones (traffic cones,
                  funnels) end flat anyway
  pyramid         square base of side 0.8, height 0.6, a point apex (where four creases meet)
  stacked_blocks  three boxes stacked, each smaller one offset from the centre of the one below:
                  1.0 x 0.8 x 0.3, then 0.6 x 0.5 x 0.25 at (+0.15, +0.1), then 0.3 x 0.3 x 0.2 at
                  (+0.2, +0.12); one closed surface (the union), concave creases where they meet
  bracket         an L-shaped angle bracket: legs 0.9 (x) and 0.7 (z) long, 0.1 thick, 0.5 wide
                  (y), a 45-degree chamfer of 0.12 in the inner corner and one through hole of
                  radius 0.08 in each leg (genus 2)

How they are meshed (PyMeshLab, numpy for the rest):
  - a shape is a union of convex pieces minus holes, each piece the convex hull of its analytic
    corners (circles as 256-gons; generate_convex_hull), joined by exact booleans
    (generate_boolean_union / _difference, libigl). Upper blocks reach into the block below and
    holes past their leg's faces rather than just touch them (the bracket's three pieces do
    share coplanar faces, which the exact booleans resolve). The booleans return the same
    surface in varying vertex orders, so it is put in a canonical order.
  - feature-preserving isotropic remeshing (meshing_isotropic_explicit_remeshing, crease angle 30
    degrees) splits, collapses, flips and smooths towards a target edge length, moving crease
    vertices only along their crease and keeping the corners: on flat faces, creases and corners
    stay exact (to 1e-16). The target comes from the surface area and the vertex count asked; a
    first pass to 0.6 of it, then 20 passes at it, make the count a smooth function of it
    (within ~6 % of the target at 2k to 80k).
  - every 5 passes, the vertices of round surfaces (cylinder, cone, the holes; their rims
    included) are moved radially onto the analytic surface: the remesher only knows the 256-gons,
    and it pulls rim vertices inward.
  - coordinates are rounded to float32 (the PLY's type), so make() and the file agree to the bit.
Below 2000 vertices the bracket's holes get too few edges around to keep their rims as the only
creases (at 1000: spurious ones), and make() refuses.

    .venv/bin/python bench/shapes.py OUT_DIR [--vertices 20000] [--shapes box,cone,...] [--force]
    .venv/bin/python bench/shapes.py OUT_DIR --vertices 5000,20000,80000

writes OUT_DIR/<shape>_<N>.ply (binary little-endian, float x y z, triangles; N the target, so
the name is a cache key: an existing file is kept unless --force) and prints one line per mesh:
vertices, faces, mean edge, min and max edge over the mean, closed, manifold, Euler
characteristic, duplicate vertices, smallest triangle angle, volume error against the analytic
volume, the largest distance of a vertex from the analytic surface and of a crease vertex from a
second surface, and the crease chains (runs of edges sharper than 35 degrees between corners: 12
on the box).

make(name, vertices) -> (points float64 (n,3), faces int32 (m,3)) needs pymeshlab, so it runs
under the .venv python only; other bench scripts run the command and read the files (meshio).
Deterministic, nothing random: the same bytes on every run. Time per shape on a busy 2-core
machine: ~3 s at 5k vertices, ~13 s at 20k, ~70 s at 80k (0.7 GB).
"""
import argparse
import math
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import meshio  # noqa: E402

RING = 256            # polygon sides of the coarse circles: 1.4-degree facets, far below the
                      # crease angle (720 makes remeshing 2x slower for nothing)
FEATURE_DEG = 30.0    # remesher's crease angle: below every real crease here (45 at the chamfer)
ITERATIONS = 20       # remeshing passes: 10 leaves a few 2x edges, 40 gains little
SNAP_EVERY = 5        # passes between two snaps onto the round surfaces (snap())
MIN_VERTICES = 2000   # at 1000 the facets around the bracket's holes bend by about the crease
                      # angle and some become creases (1500 passes; 2000 leaves a margin)
PRE, PRE_ITERATIONS = 0.6, 10   # the refining pass before (make()): edge PRE x h, enough passes
                                # to halve a 1.0 edge down to it at 80k vertices
SHARP_DEG = 35.0      # a crease edge, for snap() and the checks (round surfaces bend by up to
                      # 26 degrees per edge here, at 2000 vertices)
FILL = 0.97           # target edge = FILL x that of an ideal equilateral mesh (measured: the
                      # remeshed count is ~ (0.97 / FILL)^2 x the target on every shape)


# ---- analytic pieces: hull points for the coarse mesh, surfaces for snapping and checks ----

class Plane:
    def __init__(self, normal, offset):
        self.n, self.d = np.asarray(normal, float), float(offset)

    def dist(self, p):
        """Signed distance, positive outside."""
        return p @ self.n - self.d

    def project(self, p):
        return p - self.dist(p)[:, None] * self.n


class Round:
    """Surface of revolution about the axis through `o` along `a`: radius r0 at axial coordinate
    s0 to r1 at s1, linear in between (cylinder: r0 == r1; cone frustum otherwise)."""

    def __init__(self, o, a, s0, s1, r0, r1):
        self.o, self.a = np.asarray(o, float), np.asarray(a, float)
        self.s0, self.s1, self.r0, self.r1 = s0, s1, r0, r1

    def split(self, p):
        """(axial coordinate, radial vector, radius) of points p."""
        s = (p - self.o) @ self.a
        radial = p - self.o - s[:, None] * self.a
        return s, radial, np.linalg.norm(radial, axis=1)

    def radius(self, s):
        return self.r0 + (self.r1 - self.r0) * (s - self.s0) / (self.s1 - self.s0)

    def dist(self, p):
        """Radial distance to the surface, positive outside (the zero set is what matters)."""
        s, _, rho = self.split(p)
        return rho - self.radius(s)

    def project(self, p):
        """Radially onto the surface: the axial coordinate is kept, so a rim vertex stays on its
        cap plane."""
        s, radial, rho = self.split(p)
        return self.o + s[:, None] * self.a + radial * (self.radius(s) / rho)[:, None]


class Piece:
    """A convex solid: the hull of `points`, bounded by `surfaces`."""

    def __init__(self, points, surfaces):
        self.points, self.surfaces = np.asarray(points, float), surfaces

    def sdf(self, p):
        """Positive outside, negative inside, zero exactly on the boundary (not a Euclidean
        distance: a max of the surfaces' signed distances)."""
        return np.max([s.dist(p) for s in self.surfaces], axis=0)


def frame(axis):
    """Rotation whose columns are the world directions of local x, y, z; local z = `axis`."""
    return {"z": np.eye(3), "x": np.array([[0., 0, 1], [1, 0, 0], [0, 1, 0]]),
            "y": np.array([[0., 1, 0], [0, 0, 1], [1, 0, 0]])}[axis]


def prism(polygon, z0, z1, axis="z", origin=(0, 0, 0)):
    """A convex polygon (counter-clockwise, local x y) extruded from z0 to z1 along `axis`."""
    rot, o = frame(axis), np.asarray(origin, float)
    poly = np.asarray(polygon, float)
    local = np.concatenate([np.c_[poly, np.full(len(poly), z)] for z in (z0, z1)])
    edges = np.roll(poly, -1, axis=0) - poly
    normals = np.c_[edges[:, 1], -edges[:, 0], np.zeros(len(poly))]
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    planes = [(n, n[:2] @ q) for n, q in zip(normals, poly)] + [((0, 0, -1), -z0), ((0, 0, 1), z1)]
    surfaces = [Plane(rot @ n, d + (rot @ n) @ o) for n, d in planes]
    return Piece(o + local @ rot.T, surfaces)


def box(size, centre_xy=(0, 0), z0=0.0):
    sx, sy, sz = size
    x, y = centre_xy
    square = [(-sx / 2, -sy / 2), (sx / 2, -sy / 2), (sx / 2, sy / 2), (-sx / 2, sy / 2)]
    return prism(square, z0, z0 + sz, origin=(x, y, 0))


def regular_polygon(k, radius, phase=0.0):
    t = phase + 2 * np.pi * np.arange(k) / k
    return np.c_[radius * np.cos(t), radius * np.sin(t)]


def frustum(r0, r1, z0, z1, axis="z", origin=(0, 0, 0)):
    """A solid cone frustum (cylinder if r0 == r1) along `axis`, radius r0 at z0, r1 at z1."""
    rot, o = frame(axis), np.asarray(origin, float)
    ring = regular_polygon(RING, 1.0)
    local = np.concatenate([np.c_[r * ring, np.full(RING, z)] for r, z in ((r0, z0), (r1, z1))])
    a = rot[:, 2]
    surfaces = [Plane(-a, -z0 - a @ o), Plane(a, z1 + a @ o), Round(o, a, z0, z1, r0, r1)]
    return Piece(o + local @ rot.T, surfaces)


def pyramid(side, height):
    h = side / 2
    base = np.array([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], float)
    apex = np.array([0, 0, height], float)
    surfaces = [Plane((0, 0, -1), 0)]
    for q0, q1 in zip(base, np.roll(base, -1, axis=0)):
        n = np.cross(q1 - q0, apex - q0)
        n /= np.linalg.norm(n)
        surfaces.append(Plane(n, n @ q0))
    return Piece(np.vstack([base, apex]), surfaces)


class Shape:
    """The union of `pieces` minus the union of `holes`, and its analytic volume."""

    def __init__(self, pieces, volume, holes=()):
        self.pieces, self.holes, self.volume = pieces, list(holes), volume

    def surfaces(self):
        return [s for piece in self.pieces + self.holes for s in piece.surfaces]

    def sdf(self, p):
        d = np.min([piece.sdf(p) for piece in self.pieces], axis=0)
        for hole in self.holes:
            d = np.maximum(d, -hole.sdf(p))
        return d

    def distances(self, p, reach):
        """|distance| of points p to each surface (rows, in surfaces() order), inf where p is
        farther than `reach` outside the surface's own piece: a hole's end cap, say, or the bottom
        of a stacked block bounds nothing out there, though its plane passes by."""
        rows = []
        for piece in self.pieces + self.holes:
            inside = piece.sdf(p) <= reach
            rows += [np.where(inside, np.abs(s.dist(p)), np.inf) for s in piece.surfaces]
        return np.array(rows)


def _stacked_blocks():
    # each upper block reaches 0.05 down into the one below rather than just touching it; the
    # visible blocks are as in the docstring
    blocks = [((1.0, 0.8, 0.3), (0, 0), 0.0), ((0.6, 0.5, 0.25), (0.15, 0.1), 0.3),
              ((0.3, 0.3, 0.2), (0.2, 0.12), 0.55)]
    pieces = [box((sx, sy, sz + (z0 > 0) * 0.05), xy, z0 - (z0 > 0) * 0.05)
              for (sx, sy, sz), xy, z0 in blocks]
    return Shape(pieces, sum(sx * sy * sz for (sx, sy, sz), _, _ in blocks))


def _bracket():
    leg_x, leg_z, t, width, chamfer, r = 0.9, 0.7, 0.1, 0.5, 0.12, 0.08
    # the L profile in x z, extruded along y (prism axis "y": local x, y = world z, x): the two
    # legs and a convex corner piece that carries the chamfer face
    def along_y(poly_xz):
        return prism([(z, x) for x, z in poly_xz][::-1], 0.0, width, axis="y")
    horizontal = along_y([(0, 0), (leg_x, 0), (leg_x, t), (0, t)])
    vertical = along_y([(0, 0), (t, 0), (t, leg_z), (0, leg_z)])
    corner = along_y([(0, 0), (t + chamfer, 0), (t + chamfer, t), (t, t + chamfer),
                      (0, t + chamfer)])
    # the holes reach past both faces of their leg rather than end on them
    hx, hz = (t + chamfer + leg_x) / 2, (t + chamfer + leg_z) / 2
    holes = [frustum(r, r, -t, 2 * t, "z", (hx, width / 2, 0)),
             frustum(r, r, -t, 2 * t, "x", (0, width / 2, hz))]
    area = leg_x * t + (leg_z - t) * t + chamfer ** 2 / 2
    return Shape([horizontal, vertical, corner], area * width - 2 * math.pi * r * r * t, holes)


def _shapes():
    tri = regular_polygon(3, 0.5 / math.sqrt(3), -math.pi / 6)   # side 0.5, a flat side down
    tri[:, 1] -= tri[:, 1].min()
    hexagon = regular_polygon(6, 0.35)
    return {
        "box": lambda: Shape([box((1.0, 0.7, 0.45))], 1.0 * 0.7 * 0.45),
        "prism3": lambda: Shape([prism(tri, -0.5, 0.5, axis="x")], math.sqrt(3) / 4 * 0.25),
        "prism6": lambda: Shape([prism(hexagon, 0, 0.8)], 1.5 * math.sqrt(3) * 0.35 ** 2 * 0.8),
        "cylinder": lambda: Shape([frustum(0.35, 0.35, 0, 0.9)], math.pi * 0.35 ** 2 * 0.9),
        "cone": lambda: Shape([frustum(0.45, 0.08, 0, 0.9)],
                              math.pi * 0.9 / 3 * (0.45 ** 2 + 0.45 * 0.08 + 0.08 ** 2)),
        "pyramid": lambda: Shape([pyramid(0.8, 0.6)], 0.8 ** 2 * 0.6 / 3),
        "stacked_blocks": _stacked_blocks,
        "bracket": _bracket,
    }


SHAPES = _shapes()


# ---- meshing (PyMeshLab) ----

def coarse(shape):
    """(points, faces): the shape's exact polyhedral surface (circles as RING-gons), canonical."""
    import pymeshlab

    ms = pymeshlab.MeshSet()

    def add_hull(piece):
        ms.add_mesh(pymeshlab.Mesh(vertex_matrix=piece.points))
        ms.generate_convex_hull()
        return ms.current_mesh_id()

    def combine(ids, op):
        result = ids[0]
        for other in ids[1:]:
            op(first_mesh=result, second_mesh=other)
            result = ms.current_mesh_id()
        return result

    solid = combine([add_hull(p) for p in shape.pieces], ms.generate_boolean_union)
    if shape.holes:
        holes = combine([add_hull(p) for p in shape.holes], ms.generate_boolean_union)
        ms.generate_boolean_difference(first_mesh=solid, second_mesh=holes)
    mesh = ms.current_mesh()
    return canonical(mesh.vertex_matrix(), mesh.face_matrix())


def canonical(points, faces):
    """Vertices sorted by coordinates, each face starting at its smallest index, faces sorted:
    the booleans return the same surface in a different order now and then (measured: 7 orders
    in 12 runs of the bracket), and the remesher's result depends on the order."""
    order = np.lexsort(points.T[::-1])
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    faces = rank[faces]
    first = np.argmin(faces, axis=1)
    faces = np.take_along_axis(faces, (first[:, None] + np.arange(3)) % 3, axis=1)
    return points[order], faces[np.lexsort(faces.T[::-1])]


def surface_area(points, faces):
    a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()


def remesh(points, faces, h, iterations):
    """Feature-preserving isotropic remeshing to edge length h: (points, faces)."""
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=points, face_matrix=faces))
    # checksurfdist off: it cost 4x the time on 720-gon circles, and the vertices are projected
    # onto the input anyway (check() measures the distance to the analytic surface)
    ms.meshing_isotropic_explicit_remeshing(iterations=iterations, targetlen=pymeshlab.PureValue(h),
                                            featuredeg=FEATURE_DEG, checksurfdist=False)
    mesh = ms.current_mesh()
    mesh.compact()
    return mesh.vertex_matrix().astype(np.float64), mesh.face_matrix().astype(np.int32)


def make(name, vertices=20000):
    """(points float64 (n,3), faces int32 (m,3)) of shape `name` with about `vertices` vertices;
    points already rounded to float32 (what the PLY stores). Needs pymeshlab (.venv python)."""
    if vertices < MIN_VERTICES:
        raise ValueError(f"{vertices} vertices: below {MIN_VERTICES} the cone's top and the "
                         "bracket's holes are too coarse to keep their creases")
    shape = SHAPES[name]()
    points, faces = coarse(shape)
    # equilateral mesh: faces ~ 2 x vertices on a closed surface, each sqrt(3)/4 h^2
    h = FILL * math.sqrt(2 * surface_area(points, faces) / (math.sqrt(3) * vertices))
    # The remesher leaves any edge in [4/5, 4/3] x h alone, so on a few long input edges the
    # count depends on where their repeated halving lands (the pyramid: -25 % or +19 %, nothing
    # between). Refining first to 0.6 h and then coarsening to h makes the count a smooth
    # function of h: within 6 % of the target on every shape (measured). The snaps in between
    # give each pass an exact round surface to project onto (see snap()).
    passes = [(PRE * h, PRE_ITERATIONS)] + [(h, SNAP_EVERY)] * (ITERATIONS // SNAP_EVERY)
    for length, iterations in passes:
        points, faces = remesh(points, faces, length, iterations)
        points = snap(shape, points, faces, h)
    return points.astype(np.float32).astype(np.float64), faces


def crease_vertices(points, faces):
    edges, pairs, _ = edge_faces(faces)
    on_crease = np.zeros(len(points), bool)
    on_crease[edges[dihedral_deg(points, faces, pairs) > SHARP_DEG]] = True
    return on_crease


def snap(shape, points, faces, h):
    """Moves the vertices of round surfaces exactly onto them. The remesher projects onto its
    polygonal input, so they sit on chords, and it smooths rim vertices along their round crease,
    which pulls them inward: by up to 0.45 h over 20 passes on the bracket's holes, leaving a 10
    degree triangle once snapped. Snapped every 5 passes, the first snap may still move one by
    0.45 h but the later passes even out the triangles around it; the last snap moves < 0.1 h
    (measured). Vertices of flat faces near a rim stay (on a plane, on no crease); rim vertices
    also go onto the planes they are within 0.01 h of (a hole's rim vertex was left 1e-5 above
    its face)."""
    surfaces = shape.surfaces()
    dist = shape.distances(points, 0.5 * h)
    is_round = np.array([isinstance(s, Round) for s in surfaces])
    if not is_round.any():
        return points     # polyhedra: the remesher keeps vertices on the planes (to 1e-16)
    on_plane = np.min(dist[~is_round], axis=0) < 1e-9
    moving = (crease_vertices(points, faces) | ~on_plane) & \
        np.any(dist[is_round] < 0.5 * h, axis=0)
    for _ in range(4):   # alternating projections; exact after one pass here (radial moves keep
        for surface, d, rnd in zip(surfaces, dist, is_round):   # the axial coordinate, and
            near = moving & (d < (0.5 if rnd else 0.01) * h)    # caps are normal to the axis)
            points[near] = surface.project(points[near])
    return points


# ---- checks (numpy only) ----

def edge_faces(faces):
    """(undirected edges (k,2), the two faces of each (k,2), closed): closed when every directed
    edge occurs once and its reverse once, i.e. every edge in two faces, oriented consistently."""
    a, b = faces.reshape(-1), faces[:, [1, 2, 0]].reshape(-1)
    n = int(faces.max()) + 1
    forward, backward = a.astype(np.int64) * n + b, b.astype(np.int64) * n + a
    order = np.argsort(forward)
    twin = np.minimum(np.searchsorted(forward[order], backward), len(a) - 1)
    closed = bool(np.all(forward[order][twin] == backward)) and \
        len(np.unique(forward)) == len(forward)
    if not closed:
        return np.unique(np.sort(np.c_[a, b], axis=1), axis=0), np.zeros((0, 2), int), False
    half = np.flatnonzero(a < b)
    return np.c_[a[half], b[half]], np.c_[half // 3, order[twin[half]] // 3], True


def fans(faces):
    """Number of face fans around the vertices (= vertex count on a 2-manifold: one disc each).
    Corner (f, v) steps to the corner at v of the face across v's incoming edge; the cycles of that
    permutation are the fans, counted by pointer jumping on the smallest corner id in each."""
    a, b, c = faces.reshape(-1), faces[:, [1, 2, 0]].reshape(-1), faces[:, [2, 0, 1]].reshape(-1)
    n = int(faces.max()) + 1
    out_key = a.astype(np.int64) * n + b          # corner's outgoing edge a -> b
    order = np.argsort(out_key)
    step = order[np.searchsorted(out_key[order], a.astype(np.int64) * n + c)]  # edge a -> c
    label, jump = np.arange(len(a)), step
    for _ in range(int(np.ceil(np.log2(len(a)))) + 1):
        label = np.minimum(label, label[jump])
        jump = jump[jump]
    return int(np.sum(label == np.arange(len(a))))


def dihedral_deg(points, faces, pairs):
    """Angle between the normals of the two faces of each edge (0 = flat)."""
    normals = np.cross(points[faces[:, 1]] - points[faces[:, 0]],
                       points[faces[:, 2]] - points[faces[:, 0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    cos = np.einsum("ij,ij->i", normals[pairs[:, 0]], normals[pairs[:, 1]])
    return np.degrees(np.arccos(np.clip(cos, -1, 1)))


def chains(edges):
    """Crease chains: connected sets of sharp edges, cut at corners (vertices with other than two
    sharp edges), so a box has 12 and a cylinder 2 (closed loops)."""
    degree = np.bincount(edges.ravel())
    parent = list(range(len(edges)))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    first = {}
    for i, edge in enumerate(edges.tolist()):
        for v in edge:
            if degree[v] == 2:
                j = first.setdefault(v, i)
                parent[root(i)] = root(j)
    return len({root(i) for i in range(len(edges))})


def min_angle_deg(points, faces):
    corners = points[faces]
    worst = 180.0
    for k in range(3):
        u = corners[:, (k + 1) % 3] - corners[:, k]
        w = corners[:, (k + 2) % 3] - corners[:, k]
        cos = np.einsum("ij,ij->i", u, w) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1)
        worst = min(worst, float(np.degrees(np.arccos(np.clip(cos, -1, 1))).min()))
    return worst


def volume(points, faces):
    a, b, c = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)


def check(name, points, faces):
    """The figures of the report: a dict."""
    shape = SHAPES[name]()
    edges, pairs, closed = edge_faces(faces)
    length = np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1)
    sharp = dihedral_deg(points, faces, pairs) > SHARP_DEG if closed else np.zeros(0, bool)
    # crease vertices lie on two analytic surfaces at once: the second-smallest distance
    dist = np.sort(shape.distances(points, 1e-6), axis=0)
    on_crease = np.unique(edges[sharp])
    return dict(
        name=name, vertices=len(points), faces=len(faces), mean_edge=float(length.mean()),
        min_edge=float(length.min() / length.mean()), max_edge=float(length.max() / length.mean()),
        closed=closed, manifold=closed and fans(faces) == len(points) == len(np.unique(faces)),
        euler=len(points) - len(edges) + len(faces),
        duplicates=len(points) - len(np.unique(points, axis=0)),
        min_angle=min_angle_deg(points, faces), volume=volume(points, faces) / shape.volume - 1,
        surface_err=float(np.abs(shape.sdf(points)).max()),
        crease_err=float(dist[1, on_crease].max()), chains=chains(edges[sharp]))


ROW = ("{name:<15} {vertices:>7} {faces:>7} {mean_edge:>9.5f} {min_edge:>5.2f} {max_edge:>5.2f}"
       " {closed!s:>6} {manifold!s:>8} {euler:>3} {duplicates:>3} {min_angle:>6.1f}"
       " {volume:>+8.4%} {surface_err:>8.1e} {crease_err:>8.1e} {chains:>6}")
HEADER = ("shape           vertices   faces mean_edge   min   max closed manifold chi dup"
          " min_ang  vol_err surf_err crease_e chains")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out_dir", type=pathlib.Path)
    parser.add_argument("--vertices", default="20000",
                        help="target vertex count, or several separated by commas")
    parser.add_argument("--shapes", default=",".join(SHAPES), help="comma-separated names")
    parser.add_argument("--force", action="store_true", help="remake files that exist")
    args = parser.parse_args()
    names = args.shapes.split(",")
    unknown = [n for n in names if n not in SHAPES]
    if unknown:
        parser.error(f"unknown shapes {unknown}; known: {', '.join(SHAPES)}")
    counts = [int(v) for v in args.vertices.split(",")]
    if min(counts) < MIN_VERTICES:
        parser.error(f"--vertices: at least {MIN_VERTICES}")
    args.out_dir.mkdir(parents=True, exist_ok=True)
    print(HEADER)
    for count in counts:
        for name in names:
            path = args.out_dir / f"{name}_{count}.ply"
            if args.force or not path.exists():
                partial = path.with_suffix(".part")   # an interrupted run leaves no cached file
                meshio.write_ply(partial, *make(name, count))
                partial.replace(path)
            points, faces, _ = meshio.read_mesh(path)
            print(ROW.format(**check(name, points, faces)), flush=True)


if __name__ == "__main__":
    main()
