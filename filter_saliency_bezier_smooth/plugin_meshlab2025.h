// MeshLab 2025.07 plugin API (FilterPlugin), double precision: PyMeshLab 2025.7 and MeshLab 2025.07.
// A thin adapter like plugin_meshlab2020.h: names, parameters and the work come from
// filter_parameters.h and apply_filters.h.
#pragma once

#include <QObject>
#include <common/plugins/interfaces/filter_plugin.h>

class SaliencyBezierSmoothPlugin : public QObject, public FilterPlugin {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
  Q_INTERFACES(FilterPlugin)

public:
  enum { FP_COMPUTE_SALIENCY_CURVATURE, FP_SALIENCY_BEZIER_SMOOTH };

  SaliencyBezierSmoothPlugin();
  QString pluginName() const override;
  QString filterName(ActionIDType filter) const override;
  QString pythonFilterName(ActionIDType filter) const override;
  QString filterInfo(ActionIDType filter) const override;
  FilterClass getClass(const QAction *) const override;
  int getRequirements(const QAction *) override;
  int getPreConditions(const QAction *) const override;
  int postCondition(const QAction *) const override;
  FilterArity filterArity(const QAction *) const override;
  // The MeshDocument overload: the default of 'selected_only' depends on the current mesh, and
  // PyMeshLab lists the parameters on a document that may have none.
  using FilterPlugin::initParameterList;
  RichParameterList initParameterList(const QAction *, const MeshDocument &) override;
  std::map<std::string, QVariant> applyFilter(const QAction *, const RichParameterList &,
                                              MeshDocument &, unsigned int &postConditionMask,
                                              vcg::CallBackPos *) override;
};
