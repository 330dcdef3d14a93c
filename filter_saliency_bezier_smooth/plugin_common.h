// What the adapters of both MeshLab API generations (plugin_meshlab2020.cpp,
// plugin_meshlab2025.cpp) share: Qt strings, the filter behind an action, the dialog's parameters
// and their values. Each adapter keeps only what its generation's interface differs in. Include it
// after the generation's own MeshLab headers: it names their RichParameter classes, which both
// generations spell alike.
#pragma once

#include "apply_filters.h"

#include <QString>
#include <QStringList>

namespace saliency_bezier {

inline QString q(const std::string &s) { return QString::fromStdString(s); }

// The filter behind a plugin's action id (Plugin: either generation's class; both number their
// actions FP_COMPUTE_SALIENCY_CURVATURE and FP_SALIENCY_BEZIER_SMOOTH).
template <class Plugin>
FilterId filterOf(int id) {
  return id == Plugin::FP_COMPUTE_SALIENCY_CURVATURE ? FilterId::ComputeSaliencyCurvature
                                                      : FilterId::SaliencyBezierSmooth;
}

// Filter `id`'s parameters added to MeshLab's list with their defaults, labels and tooltips;
// "Affect only selected vertices" starts on when the current mesh has a selection. `Float`: the
// generation's scalar of RichFloat.
template <class Float, class Document, class ParameterList>
void addParameters(FilterId id, Document &md, ParameterList &list) {
  for (const ParamSpec &s : parameterSpecs(id)) {
    double value = s.default_value;
    if (s.name == "selected_only" && md.mm()) value = md.mm()->cm.svn > 0;
    switch (s.kind) {
    case ParamKind::Int: list.addParam(RichInt(q(s.name), int(value), q(s.label), q(s.tooltip))); break;
    case ParamKind::Float: list.addParam(RichFloat(q(s.name), Float(value), q(s.label), q(s.tooltip))); break;
    case ParamKind::Bool: list.addParam(RichBool(q(s.name), value != 0, q(s.label), q(s.tooltip))); break;
    case ParamKind::Enum: {
      QStringList choices;
      for (const auto &c : s.choices) choices << q(c);
      list.addParam(RichEnum(q(s.name), int(value), choices, q(s.label), q(s.tooltip)));
      break;
    }
    }
  }
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
