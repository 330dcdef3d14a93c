#!/usr/bin/env python3
"""Writes a copy of a mesh with its vertices in Morton (Z-curve) order of their positions, so that
neighbouring vertices are close in memory: measures how much of a driver's time is cache misses
(docs/studies/performance.md). The mesh's shape and connectivity are
unchanged; only the vertex numbering differs.

    python3 bench/studies/morton_order.py <in.ply|off> <out.ply>
"""
import pathlib
import sys

import numpy as np

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import meshio  # noqa: E402
(pathlib.Path(__file__).resolve().parents[1] / "out" / "studies").mkdir(parents=True, exist_ok=True)


def spread_bits(x):
    """The low 10 bits of x, two zero bits between each (for a 30-bit 3-D Morton code)."""
    x = x & 0x3FF
    x = (x | (x << 16)) & 0x30000FF
    x = (x | (x << 8)) & 0x300F00F
    x = (x | (x << 4)) & 0x30C30C3
    return (x | (x << 2)) & 0x9249249


def main():
    points, faces, _ = meshio.read_mesh(sys.argv[1])
    extent = (points.max(0) - points.min(0)).max()
    cells = ((points - points.min(0)) / extent * 1023).astype(np.int64)
    code = spread_bits(cells[:, 0]) | (spread_bits(cells[:, 1]) << 1) | (spread_bits(cells[:, 2]) << 2)
    order = np.argsort(code, kind="stable")
    new_index = np.empty_like(order)
    new_index[order] = np.arange(len(order))
    meshio.write_ply(sys.argv[2], points[order], new_index[faces])
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    print(f"mean index distance along edges: {np.abs(edges[:, 0] - edges[:, 1]).mean():.0f} -> "
          f"{np.abs(new_index[edges[:, 0]] - new_index[edges[:, 1]]).mean():.0f}")


if __name__ == "__main__":
    main()
