"""Saliency Bezier Smooth for PyMeshLab.

Importing this package loads the plugin built into the wheel (lib/libfilter_saliency_bezier_smooth.so)
into pymeshlab and binds its two filters as MeshSet methods, as pymeshlab does at import for its own:

    import pymeshlab
    import pymeshlab_saliency_bezier  # noqa: F401

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh("scan.ply")
    ms.apply_coord_saliency_bezier_smoothing()              # automatic mode, default strength
    ms.compute_scalar_by_mesh_saliency_per_vertex()
    saliency = ms.current_mesh().vertex_custom_scalar_attribute_array("Saliency")

The plugin is compiled for pymeshlab==2025.7.post1 (MeshLab 2025.07, double precision) and uses
that wheel's own libmeshlab-common.so and Qt, which pymeshlab has loaded before this import.
"""
import pathlib

import pymeshlab

SMOOTH = "apply_coord_saliency_bezier_smoothing"
ANALYSE = "compute_scalar_by_mesh_saliency_per_vertex"
FILTERS = (SMOOTH, ANALYSE)
PLUGIN_PATH = pathlib.Path(__file__).resolve().parent / "lib" / "libfilter_saliency_bezier_smooth.so"

# The smoothing filter's `placement` enum: its indices are stable, its labels may change.
METHODS = {"ring": 0, "patch": 1, "newton": 2, "feature": 3, "organic": 4, "automatic": 5}
DEFAULT_ITERATIONS = 3  # strength 1: the amount the mesh's noise estimate asks for


def strength_to_iterations(strength):
    """`iterations` for a strength multiplier: round(3 * strength), halves rounded up (1.5 -> 5)."""
    if not strength >= 0:
        raise ValueError(f"strength must be a number >= 0, got {strength}")
    return int(DEFAULT_ITERATIONS * strength + 0.5)


def smoothing_parameters(method="automatic", strength=1.0, **params):
    """Keyword arguments for ms.apply_coord_saliency_bezier_smoothing(): method by name (METHODS),
    strength as a multiplier of the default amount, any other filter parameter as is."""
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}: one of {', '.join(METHODS)}")
    return {"placement": METHODS[method], "iterations": strength_to_iterations(strength), **params}


def _load():
    """Loads the plugin once per process (pymeshlab refuses a second load of the same file) and
    binds the methods, which pymeshlab itself binds only for plugins present at its import."""
    if not all(name in pymeshlab.filter_list() for name in FILTERS):
        if not PLUGIN_PATH.is_file():
            raise ImportError(f"the plugin is missing from the installed package: {PLUGIN_PATH}")
        pymeshlab.load_plugin(str(PLUGIN_PATH))
    for name in FILTERS:
        if not hasattr(pymeshlab.MeshSet, name):
            setattr(pymeshlab.MeshSet, name, pymeshlab.bind_function(name))


_load()

try:
    from importlib.metadata import PackageNotFoundError, version

    __version__ = version("pymeshlab-saliency-bezier")
except PackageNotFoundError:  # imported from a source tree
    __version__ = "unknown"
