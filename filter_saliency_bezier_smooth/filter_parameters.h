// The filters' names, descriptions and parameters, independent of MeshLab's plugin API generation:
// each API adapter turns these specs into its RichParameterList and reads the values back into a
// ParameterValues map, so both generations show the same dialog and accept the same scripts.
#pragma once

#include <vcg_ext/methods.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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
    return "Computes per-vertex principal curvatures (Meyer et al. 2003) and mesh saliency (Lee, "
           "Varshney, Jacobs 2005) for inspection. All are stored as attributes <b>Saliency</b>, "
           "<b>MeanCurvature</b>, <b>GaussianCurvature</b>, <b>K1</b>, <b>K2</b>; the chosen "
           "one also goes to vertex quality on a display scale (saliency up to its 99th "
           "percentile, curvatures on a signed log scale) and, if asked, to the vertex colours. "
           "Positions are not changed.";
  return "Removes noise while keeping sharp edges and volume. <i>Automatic</i> (default) "
         "measures the noise and whether the mesh has sharp features, then runs the "
         "<i>Feature-preserving</i> or the <i>Organic scan</i> method; the paper's method (\"A "
         "new feature-preserving mesh-smoothing algorithm\", The Visual Computer 2009) is there "
         "by name. <i>Iterations</i> sets the strength: 3 = as measured, 6 = twice. The log "
         "says what was measured and done; <b>Saliency</b>, curvatures and <b>Displacement</b> "
         "are stored as attributes, one in vertex quality.";
}

// The Method choice: the table's labels in its order (the script value is the row's index).
inline std::vector<std::string> methodChoices() {
  std::vector<std::string> labels;
  for (const vcg_ext::MethodRow &row : vcg_ext::methodTable()) labels.push_back(row.label);
  return labels;
}

inline const std::vector<ParamSpec> &parameterSpecs(FilterId id) {
  static const ParamSpec saliency_scale{
      ParamKind::Float, "saliency_scale", 0.3, "Saliency scale (% of bbox diagonal)",
      "The paper's epsilon: saliency compares Gaussian-weighted mean curvature at 2..6 epsilon "
      "and twice those. In percent of the bounding-box diagonal."};
  // New parameters go first: meshlabserver 2020.09 fills in one missing parameter of an older
  // script only when it is the first of the list (and aborts otherwise).
  static const std::vector<ParamSpec> analysis = {
      {ParamKind::Bool, "color", 1, "Colour the mesh",
       "Also colour the vertices by the quantity in vertex quality (red: low, blue: high), as "
       "Colorize by vertex Quality does."},
      saliency_scale,
      {ParamKind::Enum, "quality", 0, "Store in vertex quality",
       "Which quantity goes to vertex quality (all are stored as attributes).",
       qualityChoices(FilterId::ComputeSaliencyCurvature)},
  };
  static const std::vector<ParamSpec> smoothing = {
      {ParamKind::Bool, "color", 0, "Colour the mesh",
       "Also colour the vertices by the quantity in vertex quality (red: low, blue: high), as "
       "Colorize by vertex Quality does."},
      {ParamKind::Enum, "placement", vcg_ext::kDefaultMethod, "Method",
       "Automatic: Feature-preserving on meshes with sharp features, Organic scan on the others. "
       "Feature-preserving: guided normal filtering and face patches (CAD parts, machined or "
       "architectural scans). Organic scan: frequency bands kept by their measured "
       "shape-to-noise energy (bodies, statues, terrain). The paper's: Ring barycentre (a light "
       "clean-up), Patch point, Paper (Newton, as printed; distorts meshes).",
       methodChoices()},
      {ParamKind::Int, "iterations", 3, "Iterations (strength)",
       "Automatic, Feature-preserving, Organic scan: how much of the measured noise to remove, "
       "in thirds: 3 = as measured, 6 = twice, 1 = a third, 0 = none; above 3 a mesh measured "
       "as clean is smoothed too, and Organic scan reaches coarser scales with each doubling (at "
       "most 30). The paper's methods: the number of iterations."},
      {ParamKind::Bool, "alpha_override", 1, "Override alpha",
       "On: every patch fit uses Alpha below. Off: the paper's rule, alpha = Saliency_min / "
       "Saliency_max of the fit's vertices. Every method: the 2-ring patches of the paper's "
       "methods, the face patches of the others."},
      {ParamKind::Float, "alpha", 1.0, "Alpha",
       "The patch fits' weight of the data against their smoothness (the paper's alpha, 0..1): "
       "1 follows the data; lower values fit flatter patches and smooth more. Every method."},
      {ParamKind::Enum, "boundary", 3, "Boundary vertices",
       "How vertices on open boundaries move, in every method: like the others (the boundary "
       "shrinks), fixed, only along the boundary, or along the boundary and the normal but never "
       "inward (default). Boundary corners stay.",
       {"Paper", "Fixed", "Along boundary", "Along boundary and normal"}},
      {ParamKind::Bool, "preserve_volume", 1, "Preserve volume",
       "Closed meshes keep the volume they had: the moved vertices are offset along their "
       "normals. Every method."},
      {ParamKind::Bool, "selected_only", 0, "Affect only selected vertices",
       "Only selected vertices move; the others still serve as neighbours. Every method."},
      {ParamKind::Enum, "quality", 0, "Store in vertex quality",
       "Which quantity of the result goes to vertex quality (all are stored as attributes).",
       qualityChoices(FilterId::SaliencyBezierSmooth)},
      saliency_scale,
      {ParamKind::Enum, "fold_handling", 0, "Paper: folded neighbourhoods",
       "The paper's methods only: fit anyway (least squares needs no one-to-one projection), or "
       "the paper's fallbacks (refit with the vertex's own normal, then its 1-ring, else keep it).",
       {"Fit anyway", "Paper fallbacks"}},
      {ParamKind::Enum, "uniform_curvature", 1, "Newton: uniform curvature",
       "Paper (Newton) only: the paper's formula (the vertex's own curvatures in the neighbours' "
       "directions) or Euler's formula with the neighbours' curvatures.",
       {"Paper", "Neighbour"}},
      {ParamKind::Int, "newton_iterations", 2, "Newton: iterations",
       "Paper (Newton) only: Newton steps on (u,v) (the paper uses 2)."},
      {ParamKind::Float, "newton_step_limit", 1.0, "Newton: step limit (edge lengths)",
       "Paper (Newton) only: a Newton step moving the vertex further than this many mean edge "
       "lengths is halved; 0: no limit (as printed)."},
  };
  return id == FilterId::ComputeSaliencyCurvature ? analysis : smoothing;
}

namespace detail {
inline std::string lowered(std::string text) {
  for (char &c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
  return text;
}
} // namespace detail

// Reads a parameter's value as scripts, tools and command lines write it: numbers; booleans as
// true/false, yes/no, on/off or 1/0; enum choices by index, by label or (Method) by the method's
// short key, case-insensitive. Returns an error message, empty when `value` was set.
inline std::string parseParameter(const ParamSpec &s, const std::string &text, double &value) {
  const std::string word = detail::lowered(text);
  if (s.kind == ParamKind::Bool) {
    if (word == "true" || word == "yes" || word == "on" || word == "1") return value = 1, "";
    if (word == "false" || word == "no" || word == "off" || word == "0") return value = 0, "";
    return "'" + s.name + "' is on or off (true/false, yes/no, on/off, 1/0), not '" + text + "'";
  }
  if (s.kind == ParamKind::Enum) {
    for (size_t c = 0; c < s.choices.size(); ++c)
      if (word == detail::lowered(s.choices[c]) || word == std::to_string(c) ||
          (s.name == "placement" && word == vcg_ext::methodTable()[c].key))
        return value = double(c), "";
    std::string known;
    for (size_t c = 0; c < s.choices.size(); ++c)
      known += (c ? ", " : "") + std::to_string(c) + " = '" + s.choices[c] + "'" +
               (s.name == "placement" ? std::string(" (") + vcg_ext::methodTable()[c].key + ")"
                                      : std::string());
    return "'" + s.name + "' is one of " + known + "; not '" + text + "'";
  }
  char *end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(number) ||
      (s.kind == ParamKind::Int && number != std::floor(number)))
    return "'" + s.name + "' takes " + (s.kind == ParamKind::Int ? "a whole number" : "a number") +
           ", not '" + text + "'";
  return value = number, "";
}

// One line per parameter: its name, kind, default and choices, for the tools' usage texts.
inline std::string parameterUsage(FilterId id) {
  std::string out;
  for (const ParamSpec &s : parameterSpecs(id)) {
    static const char *kinds[] = {"whole number", "number", "on/off", "choice"};
    char value[32];
    std::snprintf(value, sizeof value, "%g", s.default_value);
    std::string line = "  " + s.name + " (" + kinds[int(s.kind)] + ", default " +
                       (s.kind == ParamKind::Bool ? std::string(s.default_value ? "on" : "off")
                        : s.kind == ParamKind::Enum ? s.choices[size_t(s.default_value)]
                                                   : std::string(value)) +
                       "): " + s.label;
    if (s.kind == ParamKind::Enum) {
      line += " [";
      for (size_t c = 0; c < s.choices.size(); ++c)
        line += (c ? " | " : "") + std::to_string(c) + " " + s.choices[c];
      line += "]";
    }
    out += line + "\n";
  }
  return out;
}


} // namespace saliency_bezier
