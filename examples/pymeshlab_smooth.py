#!/usr/bin/env python3
"""Saliency Bezier smoothing from PyMeshLab: smooth the noisy Fandisk with the default parameters,
read the per-vertex Saliency back into numpy and score the result against the clean mesh.

    .venv/bin/python examples/pymeshlab_smooth.py [noisy.ply clean.ply] [-o smoothed.ply]

The plugin is <build>/pymeshlab/libfilter_saliency_bezier_smooth.so (target
filter_saliency_bezier_smooth_pymeshlab; <build> is $SBS_BUILD_DIR or build/). The default meshes
are the Fandisk0.3 benchmark case of the shared data folder ($SBS_SHARED_DIR or ../shared).
"""
import argparse
import os
import pathlib

import numpy as np
import pymeshlab

REPO = pathlib.Path(__file__).resolve().parents[1]
BUILD = pathlib.Path(os.environ.get("SBS_BUILD_DIR", REPO / "build"))
SHARED = pathlib.Path(os.environ.get("SBS_SHARED_DIR", REPO.parent / "shared"))
CASE = SHARED / "data" / "benchmark" / "Fandisk0.3"


def face_normals(points, faces):
    return np.cross(points[faces[:, 1]] - points[faces[:, 0]],
                    points[faces[:, 2]] - points[faces[:, 0]])


def theta_deg(result, reference, faces):
    """Mean angle between corresponding face normals, in degrees (tools/mesh_compare's theta_deg)."""
    a, b = face_normals(result, faces), face_normals(reference, faces)
    angles = np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.sum(a * b, axis=1))
    return float(np.degrees(angles).mean())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("noisy", nargs="?", default=CASE / "noisy.ply")
    parser.add_argument("clean", nargs="?", default=CASE / "clean.ply")
    parser.add_argument("-o", "--output", help="where to save the smoothed mesh (PLY, OFF, ...)")
    parser.add_argument("--plugin", default=BUILD / "pymeshlab" / "libfilter_saliency_bezier_smooth.so")
    args = parser.parse_args()

    pymeshlab.load_plugin(str(args.plugin))
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(args.clean))
    clean = ms.current_mesh().vertex_matrix().copy()
    ms.load_new_mesh(str(args.noisy))  # becomes the current mesh
    noisy = ms.current_mesh().vertex_matrix().copy()
    faces = ms.current_mesh().face_matrix()

    # ms.apply_coord_saliency_bezier_smoothing() works too after
    # setattr(pymeshlab.MeshSet, name, pymeshlab.bind_function(name)): methods are bound at import.
    # The defaults: the Automatic method at the measured strength (iterations=3). It returns the
    # row of the Method choice that ran (-1: none, the mesh measured as clean), how many vertices
    # moved, their mean displacement in mean edge lengths and the noise estimate (0..1).
    result = ms.apply_filter("apply_coord_saliency_bezier_smoothing")
    methods = ["Ring barycentre", "Patch point", "Paper (Newton)", "Feature-preserving",
               "Organic scan", "Automatic"]
    print(f"method that ran: {methods[result['method']] if result['method'] >= 0 else 'none'}; "
          f"{result['vertices_moved']} vertices moved by {result['mean_displacement']:.3f} mean "
          f"edge lengths on average; noise estimate {result['roughness']:.2f}")
    mesh = ms.current_mesh()
    smoothed = mesh.vertex_matrix()
    saliency = mesh.vertex_custom_scalar_attribute_array("Saliency")  # float64, one per vertex
    displacement = mesh.vertex_custom_scalar_attribute_array("Displacement")
    diagonal = np.linalg.norm(noisy.max(axis=0) - noisy.min(axis=0))

    print(f"{mesh.vertex_number()} vertices, {mesh.face_number()} faces")
    print(f"saliency: min {saliency.min():.4f}, median {np.median(saliency):.4f}, "
          f"max {saliency.max():.4f}; {np.mean(saliency > 0.5):.1%} of the vertices above 0.5")
    print(f"mean displacement: {displacement.mean() / diagonal:.3e} of the bbox diagonal")
    print(f"theta (mean face-normal angle to the clean mesh): noisy {theta_deg(noisy, clean, faces):.2f}"
          f" deg -> smoothed {theta_deg(smoothed, clean, faces):.2f} deg")
    if args.output:
        ms.save_current_mesh(str(args.output))
        print(f"saved {args.output}")


if __name__ == "__main__":
    main()
