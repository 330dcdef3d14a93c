// What the adapters of both MeshLab API generations (plugin_meshlab2020.cpp,
// plugin_meshlab2025.cpp) share: Qt strings, the filter behind an action, and the dialog's (or
// script's) values. Each adapter keeps only what its generation's interface differs in.
#pragma once

#include "apply_filters.h"

#include <QString>

namespace saliency_bezier {

inline QString q(const std::string &s) { return QString::fromStdString(s); }

// The filter behind a plugin's action id (Plugin: either generation's class; both number their
// actions FP_COMPUTE_SALIENCY_CURVATURE and FP_SALIENCY_BEZIER_SMOOTH).
template <class Plugin>
FilterId filterOf(int id) {
  return id == Plugin::FP_COMPUTE_SALIENCY_CURVATURE ? FilterId::ComputeSaliencyCurvature
                                                      : FilterId::SaliencyBezierSmooth;
}

// Filter `id`'s parameter values from MeshLab's list (RichParameterList of either generation).
template <class ParameterList>
ParameterValues readParameterValues(FilterId id, const ParameterList &list) {
  ParameterValues values;
  for (const ParamSpec &s : parameterSpecs(id)) {
    const QString name = q(s.name);
    switch (s.kind) {
    case ParamKind::Int: values[s.name] = list.getInt(name); break;
    case ParamKind::Float: values[s.name] = list.getFloat(name); break;
    case ParamKind::Bool: values[s.name] = list.getBool(name); break;
    case ParamKind::Enum: values[s.name] = list.getEnum(name); break;
    }
  }
  return values;
}

} // namespace saliency_bezier
