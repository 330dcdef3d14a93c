// The filters' names, descriptions and parameters, independent of MeshLab's plugin API generation:
// each API adapter turns these specs into its RichParameterList and reads the values back into a
// ParameterValues map, so both generations show the same dialog and accept the same scripts.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace saliency_bezier {

enum class FilterId { ComputeSaliencyCurvature, SaliencyBezierSmooth };

enum class ParamKind { Int, Float, Bool, Enum };

struct ParamSpec {
  ParamKind kind;
  std::string name;  // script / Python name
  double default_value;
  std::string label; // dialog label
  std::string tooltip;
  std::vector<std::string> choices; // Enum only
};

using ParameterValues = std::map<std::string, double>;

inline const std::vector<std::string> &qualityChoices(FilterId id) {
  static const std::vector<std::string> analysis = {"Saliency", "Mean curvature",
                                                    "Gaussian curvature", "K1", "K2"};
  static const std::vector<std::string> smoothing = {"Saliency", "Mean curvature",
                                                     "Gaussian curvature", "K1", "K2",
                                                     "Alpha", "Displacement"};
  return id == FilterId::ComputeSaliencyCurvature ? analysis : smoothing;
}

inline std::string filterName(FilterId id) {
  return id == FilterId::ComputeSaliencyCurvature ? "Compute Mesh Saliency and Principal Curvatures"
                                                  : "Saliency Bezier Smooth";
}

inline std::string pythonFilterName(FilterId id) {
  return id == FilterId::ComputeSaliencyCurvature
             ? "compute_scalar_by_mesh_saliency_per_vertex"
             : "apply_coord_saliency_bezier_smoothing";
}

inline std::string filterDescription(FilterId id) {
  if (id == FilterId::ComputeSaliencyCurvature)
    return "Computes per-vertex principal curvatures with the discrete operators of "
           "Meyer, Desbrun, Schr&ouml;der, Barr, \"Discrete Differential-Geometry Operators for "
           "Triangulated 2-Manifolds\" (2003) and mesh saliency with Lee, Varshney, Jacobs, "
           "\"Mesh Saliency\" (SIGGRAPH 2005) on the minimum principal curvature, as used by "
           "\"A new feature-preserving mesh-smoothing algorithm\" (The Visual Computer, 2009)."
           "<br>The chosen quantity goes to vertex quality (saliency is rescaled to [0,1]); all of "
           "them are stored as per-vertex attributes <b>Saliency</b>, <b>MeanCurvature</b>, "
           "<b>GaussianCurvature</b>, <b>K1</b>, <b>K2</b>, and the principal directions in the "
           "per-vertex curvature directions. Boundary vertices take the mean of their interior "
           "neighbours' curvatures. The mesh's positions are not changed.";
  return "Feature-preserving smoothing after \"A new feature-preserving mesh-smoothing "
         "algorithm\" (The Visual Computer, 2009) and beyond it. The paper's method (placements "
         "Ring barycentre, Patch point, Paper): per vertex, principal curvatures (Meyer et al. "
         "2003) and mesh saliency (Lee et al. 2005), a weighted bi-quadratic B&eacute;zier patch "
         "least-squares fitted to the vertex's 2-ring, and a new position on that patch."
         "<br><b>Placement</b>: <i>Automatic</i> (default) measures whether the noisy mesh has "
         "sharp features (after a few iterations of guided normal filtering: how much of it is "
         "exactly flat, and whether its creases survive plain Taubin smoothing) and runs the "
         "<i>Feature-preserving</i> mode on CAD-like meshes, the <i>Organic scan</i> mode on "
         "the others; the log says which and why. A clean mesh is left as it is. "
         "<i>Feature-preserving (face patches)</i> keeps sharp edges: a short Taubin pre-pass "
         "(scaled by the measured noise), guided normal filtering (Zhang et al. 2015) and each "
         "vertex moved onto bi-quadratic patches of its faces (Sun et al. 2007's update). "
         "<i>Organic scan (band shrinkage)</i> is for organic shapes with noise in all directions "
         "(body scans, photogrammetry): the differences of Taubin results at 0, 1, 2, 4 ... 128 "
         "steps are frequency bands, each kept in proportion to how much of it is shape rather "
         "than noise (the noise level is measured from the mesh), then one face-patch update. "
         "<i>Ring barycentre</i> moves the vertex to the patch point above its 1-ring "
         "barycentre (the paper's patch, a light Taubin-class smoothing); <i>Patch point</i> "
         "projects the vertex onto its patch; <i>Paper (Newton)</i> is the paper's method as "
         "printed: Newton on (u,v) toward the saliency-weighted uniform principal curvature. "
         "Measured, the paper's method distorts meshes (its curvature target usually does not "
         "exist on the patch); the step limit keeps it local."
         "<br>All vertices of an iteration move at once; non-manifold and isolated vertices and "
         "those of degenerate faces are not moved. Per-vertex attributes <b>Saliency</b>, "
         "<b>K1</b>, <b>K2</b>, <b>MeanCurvature</b>, <b>GaussianCurvature</b>, <b>Alpha</b>, "
         "<b>Displacement</b> describe the result; one of them goes to vertex quality.";
}

inline const std::vector<ParamSpec> &parameterSpecs(FilterId id) {
  static const ParamSpec saliency_scale{
      ParamKind::Float, "saliency_scale", 0.3, "Saliency scale (% of bbox diagonal)",
      "The paper's epsilon: saliency compares Gaussian-weighted mean curvature at the scales "
      "2..6 epsilon and twice those. In percent of the bounding-box diagonal."};
  static const std::vector<ParamSpec> analysis = {
      saliency_scale,
      {ParamKind::Enum, "quality", 0, "Store in vertex quality",
       "Which per-vertex quantity goes to vertex quality (all are stored as attributes).",
       qualityChoices(FilterId::ComputeSaliencyCurvature)},
  };
  static const std::vector<ParamSpec> smoothing = {
      {ParamKind::Int, "iterations", 3, "Iterations",
       "Number of smoothing iterations (Ring barycentre, Patch point and Paper placements; the "
       "other modes measure how much smoothing the mesh needs)."},
      {ParamKind::Enum, "placement", 5, "Placement",
       "Automatic (default): the feature-preserving mode on meshes with sharp features, the "
       "organic mode on the others, decided from the mesh. Feature-preserving: guided normal "
       "filtering and per-face patches (keeps sharp edges: CAD parts). Organic scan: Taubin's "
       "frequency bands, each kept in proportion to its measured shape-to-noise energy (organic "
       "shapes with noise in all directions). These three use only 'Affect only selected "
       "vertices', 'Preserve volume' and 'Store in vertex quality'. Ring barycentre, Patch point "
       "and Paper (Newton): where each vertex goes on the paper's patch fitted to its 2-ring (the "
       "patch point at its 1-ring barycentre's parameter, its own patch point, or the paper's "
       "Newton solve for the uniform principal curvature).",
       {"Ring barycentre", "Patch point", "Paper (Newton)", "Feature-preserving (face patches)",
        "Organic scan (band shrinkage)", "Automatic (feature-preserving or organic)"}},
      {ParamKind::Bool, "alpha_override", 1, "Override alpha",
       "Use the fixed alpha below everywhere instead of the paper's Saliency_min/Saliency_max "
       "over the neighbourhood (measured: the paper's rule degenerates near zero saliency)."},
      {ParamKind::Float, "alpha", 1.0, "Alpha",
       "Weight of the data term against the parallelogram term of the patch fit, in [0,1]; "
       "1 is the plain least-squares fit."},
      {ParamKind::Enum, "uniform_curvature", 1, "Uniform curvature",
       "Paper (Newton) placement only: the paper's formula (the vertex's own curvatures in the "
       "neighbours' directions) or Euler's formula with the neighbours' curvatures.",
       {"Paper", "Neighbour"}},
      {ParamKind::Enum, "boundary", 3, "Boundary vertices",
       "Treat boundary vertices like the others (paper: the boundary shrinks), keep them fixed, "
       "let them move only along the boundary, or along the boundary and the surface normal but "
       "never inward (smooths the boundary without pulling it in). Boundary corners (turning more "
       "than 45 degrees) stay in place except in the paper mode.",
       {"Paper", "Fixed", "Along boundary", "Along boundary and normal"}},
      {ParamKind::Bool, "preserve_volume", 1, "Preserve volume",
       "Closed meshes: after each iteration (feature-preserving mode: once at the end), offset "
       "the moved vertices along their normals so that the enclosed volume stays that of the "
       "input."},
      {ParamKind::Enum, "fold_handling", 0, "Folded neighbourhoods",
       "Fit anyway (least squares needs no one-to-one projection), or the paper's fallbacks: "
       "refit with the vertex's own normal, then with its 1-ring, else keep the vertex.",
       {"Fit anyway", "Paper fallbacks"}},
      {ParamKind::Int, "newton_iterations", 2, "Newton iterations",
       "Paper (Newton) placement only: Newton steps on (u,v) (the paper uses 2)."},
      {ParamKind::Float, "newton_step_limit", 1.0, "Newton step limit (edge lengths)",
       "Paper (Newton) only: a Newton step moving the vertex further than this many mean "
       "edge lengths is halved; 0: no limit (as printed)."},
      saliency_scale,
      {ParamKind::Bool, "selected_only", 0, "Affect only selected vertices",
       "Only selected vertices move; the others still serve as neighbours."},
      {ParamKind::Enum, "quality", 0, "Store in vertex quality",
       "Which per-vertex quantity of the result goes to vertex quality (all are stored as "
       "attributes).",
       qualityChoices(FilterId::SaliencyBezierSmooth)},
  };
  return id == FilterId::ComputeSaliencyCurvature ? analysis : smoothing;
}

} // namespace saliency_bezier
