// MeshLab 2020.09 plugin API (MeshFilterInterface): Debian's MeshLab GUI and meshlabserver.
#pragma once

#include <QObject>
#include <common/interfaces.h>

class SaliencyBezierSmoothPlugin : public QObject, public MeshFilterInterface {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
  Q_INTERFACES(MeshFilterInterface)

public:
  enum { FP_COMPUTE_SALIENCY_CURVATURE, FP_SALIENCY_BEZIER_SMOOTH };

  SaliencyBezierSmoothPlugin();
  QString pluginName() const override;
  QString filterName(FilterIDType filter) const override;
  QString filterInfo(FilterIDType filter) const override;
  FilterClass getClass(QAction *) override;
  int getRequirements(QAction *) override;
  int getPreConditions(QAction *) const override;
  int postCondition(QAction *) const override;
  FILTER_ARITY filterArity(QAction *) const override;
  void initParameterSet(QAction *, MeshDocument &, RichParameterList &) override;
  bool applyFilter(QAction *, MeshDocument &, const RichParameterList &,
                   vcg::CallBackPos *) override;
};
