#include "plugin_meshlab2020.h"

#include "plugin_common.h"

using namespace saliency_bezier;

namespace {
FilterId filterOf(int id) { return saliency_bezier::filterOf<SaliencyBezierSmoothPlugin>(id); }
} // namespace

SaliencyBezierSmoothPlugin::SaliencyBezierSmoothPlugin() {
  typeList << FP_COMPUTE_SALIENCY_CURVATURE << FP_SALIENCY_BEZIER_SMOOTH;
  for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString SaliencyBezierSmoothPlugin::pluginName() const { return "FilterSaliencyBezierSmooth"; }

QString SaliencyBezierSmoothPlugin::filterName(FilterIDType id) const {
  return q(saliency_bezier::filterName(filterOf(id)));
}

QString SaliencyBezierSmoothPlugin::filterInfo(FilterIDType id) const {
  return q(filterDescription(filterOf(id)));
}

// No VertexColoring class: the GUI would show the vertex colours after every run, white where the
// filter did not paint them; applyFilter turns them on when it paints (the "color" parameter).
MeshFilterInterface::FilterClass SaliencyBezierSmoothPlugin::getClass(QAction *a) {
  return ID(a) == FP_SALIENCY_BEZIER_SMOOTH ? Smoothing : Quality;
}

// Vertex quality is written by both filters: asking for it makes MeshLab mark it as present, so
// that "Colorize by vertex Quality" and the other quality filters accept the result at once.
int SaliencyBezierSmoothPlugin::getRequirements(QAction *a) {
  return ID(a) == FP_COMPUTE_SALIENCY_CURVATURE
             ? int(MeshModel::MM_VERTCURVDIR | MeshModel::MM_VERTQUALITY)
             : int(MeshModel::MM_VERTQUALITY);
}

int SaliencyBezierSmoothPlugin::getPreConditions(QAction *) const {
  return MeshModel::MM_FACENUMBER;
}

int SaliencyBezierSmoothPlugin::postCondition(QAction *a) const {
  const int written = MeshModel::MM_VERTQUALITY;
  return ID(a) == FP_SALIENCY_BEZIER_SMOOTH
             ? written | MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL |
                   MeshModel::MM_FACENORMAL | MeshModel::MM_VERTCOLOR
             : written | MeshModel::MM_VERTCURV | MeshModel::MM_VERTCURVDIR |
                   MeshModel::MM_VERTCOLOR;
}

MeshFilterInterface::FILTER_ARITY SaliencyBezierSmoothPlugin::filterArity(QAction *) const {
  return SINGLE_MESH;
}

void SaliencyBezierSmoothPlugin::initParameterSet(QAction *a, MeshDocument &md,
                                                  RichParameterList &list) {
  addParameters<float>(filterOf(ID(a)), md, list);
}

bool SaliencyBezierSmoothPlugin::applyFilter(QAction *a, MeshDocument &md,
                                             const RichParameterList &list,
                                             vcg::CallBackPos *cb) {
  MeshModel *mm = md.mm();
  if (!mm) {
    errorMessage = "No current mesh.";
    return false;
  }
  const FilterId id = filterOf(ID(a));
  const FilterOutcome outcome = applyFilterById(id, mm->cm, readParameterValues(id, list), cb);
  for (const std::string &line : outcome.log) Log(line);
  if (outcome.ok) mm->updateDataMask(MeshModel::MM_VERTQUALITY);
  if (outcome.colored) mm->updateDataMask(MeshModel::MM_VERTCOLOR);
  if (!outcome.ok) {
    errorMessage = q(outcome.error);
    Log(std::string("Error: ") + outcome.error);
    return false;
  }
  return true;
}

MESHLAB_PLUGIN_NAME_EXPORTER(SaliencyBezierSmoothPlugin)
