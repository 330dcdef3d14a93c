#include "plugin_meshlab2025.h"

#include "plugin_common.h"

using namespace saliency_bezier;

namespace {
FilterId filterOf(int id) { return saliency_bezier::filterOf<SaliencyBezierSmoothPlugin>(id); }
} // namespace

SaliencyBezierSmoothPlugin::SaliencyBezierSmoothPlugin() {
  typeList = {FP_COMPUTE_SALIENCY_CURVATURE, FP_SALIENCY_BEZIER_SMOOTH};
  for (ActionIDType id : types()) actionList.push_back(new QAction(filterName(id), this));
}

QString SaliencyBezierSmoothPlugin::pluginName() const { return "FilterSaliencyBezierSmooth"; }

QString SaliencyBezierSmoothPlugin::filterName(ActionIDType id) const {
  return q(saliency_bezier::filterName(filterOf(id)));
}

QString SaliencyBezierSmoothPlugin::pythonFilterName(ActionIDType id) const {
  return q(saliency_bezier::pythonFilterName(filterOf(id)));
}

QString SaliencyBezierSmoothPlugin::filterInfo(ActionIDType id) const {
  return q(filterDescription(filterOf(id)));
}

FilterPlugin::FilterClass SaliencyBezierSmoothPlugin::getClass(const QAction *a) const {
  return ID(a) == FP_SALIENCY_BEZIER_SMOOTH ? Smoothing : Quality;
}

int SaliencyBezierSmoothPlugin::getRequirements(const QAction *a) {
  return ID(a) == FP_COMPUTE_SALIENCY_CURVATURE
             ? int(MeshModel::MM_VERTCURVDIR | MeshModel::MM_VERTQUALITY)
             : int(MeshModel::MM_VERTQUALITY);
}

int SaliencyBezierSmoothPlugin::getPreConditions(const QAction *) const {
  return MeshModel::MM_FACENUMBER;
}

int SaliencyBezierSmoothPlugin::postCondition(const QAction *a) const {
  const int written = MeshModel::MM_VERTQUALITY;
  return ID(a) == FP_SALIENCY_BEZIER_SMOOTH
             ? written | MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL |
                   MeshModel::MM_FACENORMAL
             : written | MeshModel::MM_VERTCURV | MeshModel::MM_VERTCURVDIR;
}

FilterPlugin::FilterArity SaliencyBezierSmoothPlugin::filterArity(const QAction *) const {
  return SINGLE_MESH;
}

RichParameterList SaliencyBezierSmoothPlugin::initParameterList(const QAction *a,
                                                                const MeshDocument &md) {
  RichParameterList list;
  addParameters<Scalarm>(filterOf(ID(a)), md, list);
  return list;
}

std::map<std::string, QVariant>
SaliencyBezierSmoothPlugin::applyFilter(const QAction *a, const RichParameterList &list,
                                        MeshDocument &md, unsigned int &postConditionMask,
                                        vcg::CallBackPos *cb) {
  MeshModel *mm = md.mm();
  if (!mm) throw MLException("No current mesh.");
  const FilterId id = filterOf(ID(a));
  const FilterOutcome outcome = applyFilterById(id, mm->cm, readParameterValues(id, list), cb);
  for (const std::string &line : outcome.log) log(line);
  if (!outcome.ok) throw MLException(q(outcome.error));
  mm->updateDataMask(MeshModel::MM_VERTQUALITY);
  if (outcome.colored) {
    mm->updateDataMask(MeshModel::MM_VERTCOLOR);
    postConditionMask |= MeshModel::MM_VERTCOLOR;
  }
  // What PyMeshLab's apply_filter returns (it converts numbers, not strings): the row of the
  // Method choice that ran (-1: none, the mesh measured as clean), what moved, the noise estimate.
  if (id == FilterId::SaliencyBezierSmooth)
    return {{"method", QVariant(outcome.run.method_index)},
            {"vertices_moved", QVariant(int(outcome.run.vertices_moved))},
            {"mean_displacement", QVariant(outcome.run.mean_displacement_edges)},
            {"roughness", QVariant(outcome.run.roughness)}};
  return {};
}

MESHLAB_PLUGIN_NAME_EXPORTER(SaliencyBezierSmoothPlugin)
