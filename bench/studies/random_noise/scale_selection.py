#!/usr/bin/env python3
"""Prototype (issue 8): can the amount of smoothing for noise in random 3-D directions be chosen from
the mesh alone, well enough to beat Taubin at its best (oracle) step count?  Two ideas, measured
against that oracle on Debian's libcgal-demo meshes (add_noise 0.25 random 1):

- ICI: per face, Taubin snapshots at K = 2 … 128 and the intersection-of-confidence-intervals rule
  (Katkovnik) on the face normals, the normals' noise at each K from a smoothed random probe;
  then Sun et al. 2007 vertex updates (10) toward the chosen normals.
- Wiener: the snapshots' differences as frequency bands, each band shrunk by
  max(0, 1 - alpha * noise energy / band energy) (normal components; the noise energy of each band
  from the same probe), either per vertex (energies averaged over two 1-ring means) or per mesh.

The noise level is the MAD of the normal component of the uniform-Laplacian residual.
numpy only; the uniform Taubin (0.5 / -0.53) is the repository's (boundary vertices follow their
boundary neighbours), so its oracle can differ from MeshLab's on meshes with holes.

    python3 bench/studies/random_noise/scale_selection.py --build build [meshes...]
    python3 bench/studies/random_noise/scale_selection.py --build build --decompose [meshes...]

--decompose splits Taubin's error at its oracle step count instead: θ of Taubin applied to the
*clean* mesh (the smoothing's own bias), and of the clean mesh plus only the normal (or only the
tangential) part of the oracle result's displacement from it.
"""
import argparse
import pathlib
import subprocess
import sys
import tarfile
import tempfile

import numpy as np

CGAL_DATA = pathlib.Path("/usr/share/doc/libcgal-demo/data.tar.gz")
MESHES = ["armadillo", "lion-head", "elephant-with-holes", "three_peaks", "cow", "elk", "bull",
          "fandisk"]
BANDS = [0, 1, 2, 4, 8, 16, 32, 64, 128, 256]
ICI_STEPS = [2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64, 90, 128]


def read_off(path):
    tokens = open(path).read().split()
    nv, nf = int(tokens[1]), int(tokens[2])
    v = np.array(tokens[4:4 + 3 * nv], float).reshape(nv, 3)
    f = np.array(tokens[4 + 3 * nv:4 + 3 * nv + 4 * nf], int).reshape(nf, 4)[:, 1:]
    return v, f


class Mesh:
    def __init__(self, v, f):
        self.f, self.nv = f, len(v)
        e = np.r_[f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]
        key = np.minimum(e[:, 0], e[:, 1]) * self.nv + np.maximum(e[:, 0], e[:, 1])
        uniq, count = np.unique(key, return_counts=True)
        a, b = uniq // self.nv, uniq % self.nv
        boundary = np.zeros(self.nv, bool)
        boundary[a[count == 1]] = boundary[b[count == 1]] = True
        # Boundary vertices average their boundary neighbours only (they stay on the boundary curve).
        keep_ab = ~boundary[a] | (count == 1)  # a's neighbour b
        keep_ba = ~boundary[b] | (count == 1)
        self.src = np.r_[a[keep_ab], b[keep_ba]]
        self.dst = np.r_[b[keep_ab], a[keep_ba]]
        self.deg = np.maximum(np.bincount(self.src, minlength=self.nv), 1).astype(float)
        self.boundary = boundary

    def ring_mean(self, x):
        acc = np.zeros_like(x)
        np.add.at(acc, self.src, x[self.dst])
        return acc / (self.deg if x.ndim == 1 else self.deg[:, None])

    def taubin(self, x, steps):
        """Snapshots of uniform Taubin smoothing (lambda 0.5, mu -0.53) after each count in steps."""
        out, k = {}, 0
        for target in sorted(steps):
            while k < target:
                x = x + 0.5 * (self.ring_mean(x) - x)
                x = x - 0.53 * (self.ring_mean(x) - x)
                k += 1
            out[target] = x.copy()
        return out

    def face_normals(self, v):
        n = np.cross(v[self.f[:, 1]] - v[self.f[:, 0]], v[self.f[:, 2]] - v[self.f[:, 0]])
        area2 = np.linalg.norm(n, axis=1)
        return n / np.maximum(area2, 1e-300)[:, None], area2

    def vertex_normals(self, v):
        n, area2 = self.face_normals(v)
        acc = np.zeros_like(v)
        for i in range(3):
            np.add.at(acc, self.f[:, i], n * area2[:, None])
        return acc / np.maximum(np.linalg.norm(acc, axis=1), 1e-300)[:, None]

    def face_neighbour_mean(self, g):
        """Mean of a per-face value over the faces around the face's corners (with multiplicity)."""
        acc, cnt = np.zeros(self.nv), np.zeros(self.nv)
        for i in range(3):
            np.add.at(acc, self.f[:, i], g)
            np.add.at(cnt, self.f[:, i], 1)
        return acc[self.f].sum(1) / cnt[self.f].sum(1)

    def gradient_norm2(self, v, phi):
        """|grad phi|^2 per face of the piecewise-linear scalar phi: the tilt phi gives a face."""
        p = v[self.f]
        n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        area2 = np.maximum(np.linalg.norm(n, axis=1), 1e-300)
        u = n / area2[:, None]
        g = np.zeros_like(u)
        for i, edge in enumerate([p[:, 2] - p[:, 1], p[:, 0] - p[:, 2], p[:, 1] - p[:, 0]]):
            g += phi[self.f[:, i]][:, None] * np.cross(u, edge) / area2[:, None]
        return (g * g).sum(1)


def theta(mesh, v, clean):
    n, _ = mesh.face_normals(v)
    c, _ = mesh.face_normals(clean)
    return float(np.degrees(np.arccos(np.clip((n * c).sum(1), -1, 1))).mean())


def noise_sigma(mesh, v):
    r = ((v - mesh.ring_mean(v)) * mesh.vertex_normals(v)).sum(1)[~mesh.boundary]
    d = mesh.deg[~mesh.boundary]
    return np.median(np.abs(r)) / 0.6745 / np.sqrt(np.mean(1 + 1 / d))


def sun_update(mesh, x, normals, iterations):
    cnt = np.bincount(mesh.f.ravel(), minlength=mesh.nv).astype(float)
    for _ in range(iterations):
        centroid = x[mesh.f].mean(1)
        acc = np.zeros_like(x)
        for i in range(3):
            dist = ((centroid - x[mesh.f[:, i]]) * normals).sum(1)
            np.add.at(acc, mesh.f[:, i], normals * dist[:, None])
        x = x + acc / cnt[:, None]
    return x


def ici(mesh, v, gamma, sigma, rng):
    snaps = mesh.taubin(v, ICI_STEPS)
    normals = np.stack([mesh.face_normals(snaps[k])[0] for k in ICI_STEPS])
    probe = mesh.taubin(rng.normal(0, sigma, mesh.nv), ICI_STEPS)
    spread = np.stack([np.sqrt(mesh.face_neighbour_mean(mesh.gradient_norm2(snaps[k], probe[k])))
                       for k in ICI_STEPS])
    alive = np.ones(len(mesh.f), bool)
    choice = np.zeros(len(mesh.f), int)
    for j in range(1, len(ICI_STEPS)):
        for i in range(j):
            alive &= np.linalg.norm(normals[i] - normals[j], axis=1) <= gamma * (spread[i] + spread[j])
        choice[alive] = j
    chosen = normals[choice, np.arange(len(mesh.f))]
    # Start every vertex from the smallest step count chosen around it.
    start = np.full(mesh.nv, len(ICI_STEPS) - 1)
    np.minimum.at(start, mesh.f.ravel(), np.repeat(choice, 3))
    x = np.stack([snaps[k] for k in ICI_STEPS])[start, np.arange(mesh.nv)]
    return sun_update(mesh, x, chosen, 10)


def band_energies(mesh, v, sigma, rng):
    snaps = mesh.taubin(v, BANDS)
    n = mesh.vertex_normals(snaps[8])
    probe = mesh.taubin(rng.normal(0, sigma, mesh.nv), BANDS)
    bands = []
    for a, b in zip(BANDS[:-1], BANDS[1:]):
        d = snaps[a] - snaps[b]
        bands.append((d, ((d * n).sum(1)) ** 2, (probe[a] - probe[b]) ** 2))
    return snaps[BANDS[-1]], bands


def wiener(mesh, coarse, bands, alpha, local):
    x = coarse.copy()
    for d, energy, noise in bands:
        if local:
            energy = mesh.ring_mean(mesh.ring_mean(energy))
            noise = mesh.ring_mean(mesh.ring_mean(noise))
        else:
            energy, noise = energy.mean(), noise.mean()
        gain = np.clip(1 - alpha * noise / np.maximum(energy, 1e-300), 0, 1)
        x += (gain[:, None] if local else gain) * d
    return x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--decompose", action="store_true")
    ap.add_argument("meshes", nargs="*", default=MESHES)
    args = ap.parse_args()
    if args.decompose:
        print("| mesh | oracle K | Taubin θ | Taubin on the clean mesh θ | normal part θ | tangential part θ |")
        print("|---|---|---|---|---|---|")
    add_noise = pathlib.Path(args.build).resolve() / "tools" / "add_noise"
    alphas = [1, 1.3, 1.6, 2, 3]
    if not args.decompose:
        print("| mesh | σ̂ / mean edge | Taubin oracle K (θ) | ICI Γ 0.7 / 1.0 / 1.5 | local Wiener α 1 / 2 | "
          "global Wiener α " + " / ".join(map(str, alphas)) + " | band SNR 4–8 / 8–16 |")
        print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp, tarfile.open(CGAL_DATA) as tar:
        tmp = pathlib.Path(tmp)
        for name in args.meshes:
            member = next(m for m in tar.getmembers() if m.name.endswith(f"meshes/{name}.off"))
            tar.extract(member, tmp)
            src = tmp / member.name
            subprocess.run([add_noise, src, tmp / "clean.off", "0", "random", "1"], check=True,
                           capture_output=True)
            subprocess.run([add_noise, src, tmp / "noisy.off", "0.25", "random", "1"], check=True,
                           capture_output=True)
            clean, f = read_off(tmp / "clean.off")
            noisy, _ = read_off(tmp / "noisy.off")
            mesh = Mesh(noisy, f)
            edge = np.linalg.norm(clean[f] - clean[np.roll(f, 1, axis=1)], axis=2).mean()
            sigma = noise_sigma(mesh, noisy)
            snaps = mesh.taubin(noisy, range(1, 121))
            oracle = min(snaps, key=lambda k: theta(mesh, snaps[k], clean))
            if args.decompose:
                n = mesh.vertex_normals(clean)
                err = snaps[oracle] - clean
                along = (err * n).sum(1)[:, None] * n
                print(f"| {name} | {oracle} | {theta(mesh, snaps[oracle], clean):.2f} | "
                      f"{theta(mesh, mesh.taubin(clean, [oracle])[oracle], clean):.2f} | "
                      f"{theta(mesh, clean + along, clean):.2f} | "
                      f"{theta(mesh, clean + err - along, clean):.2f} |", flush=True)
                continue
            icis = [theta(mesh, ici(mesh, noisy, g, sigma, np.random.default_rng(1)), clean)
                    for g in (0.7, 1.0, 1.5)]
            coarse, bands = band_energies(mesh, noisy, sigma, np.random.default_rng(1))
            local = [theta(mesh, wiener(mesh, coarse, bands, a, True), clean) for a in (1, 2)]
            glob = [theta(mesh, wiener(mesh, coarse, bands, a, False), clean) for a in alphas]
            snr = [max(e.mean() - n.mean(), 0) / n.mean() for _, e, n in bands[3:5]]
            print(f"| {name} | {sigma / edge:.3f} | {oracle} ({theta(mesh, snaps[oracle], clean):.2f}) | "
                  + " / ".join(f"{t:.2f}" for t in icis) + " | "
                  + " / ".join(f"{t:.2f}" for t in local) + " | "
                  + " / ".join(f"{t:.2f}" for t in glob) + " | "
                  + " / ".join(f"{s:.2f}" for s in snr) + " |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
