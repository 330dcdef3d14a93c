// stage_bench: per-stage timings of the smoothing filter's core on one mesh (docs/studies/performance.md).
//
//   stage_bench <mesh> [repeat=3] [stages=rings,curvature,saliency,fit,paperfit,smooth]
//               [save=<prefix>] [compare=<prefix>] [exact_saliency=0|1]
//
// Each stage runs `repeat` times; prints the median wall and process-CPU seconds (CPU time is the
// sum over threads: the stable figure on a machine shared with other jobs). "fit" is one Jacobi
// sweep of patch fit + placement in the default mode (ring barycentre, α = 1), "paperfit" one in
// the paper's mode (α rule + Newton), "smooth" the whole driver at default parameters.
// save= writes the smoothed positions (default and paper mode, 3 iterations) and the final
// saliency as raw doubles; compare= reads such files and prints the largest differences, which is
// how the before/after identity of each optimisation is checked.
#include "tool_mesh.h"

#include <vcg_ext/methods/paper/paper_smooth.h>

#include <algorithm>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>

using namespace vcg_ext;

namespace {

double cpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

struct Timing {
  std::vector<double> wall, cpu;
  void add(double w, double c) { wall.push_back(w), cpu.push_back(c); }
  static double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[v.size() / 2];
  }
};

template <class F> Timing timeIt(int repeat, F &&f) {
  Timing t;
  for (int r = 0; r < repeat; ++r) {
    const auto w0 = Clock::now();
    const double c0 = cpuSeconds();
    f();
    t.add(secondsSince(w0), cpuSeconds() - c0);
  }
  return t;
}

void report(const char *name, const Timing &t, int n) {
  const double w = Timing::median(t.wall), c = Timing::median(t.cpu);
  std::printf("%-10s wall %8.4f s  cpu %8.4f s  (%.3f us cpu/vertex, %.2f M vertices/s wall)\n",
              name, w, c, 1e6 * c / n, n / w / 1e6);
}

// One Jacobi sweep of stages 4-7 (the driver's inner loop without boundary handling).
void fitSweep(const MeshArrays &mesh, const Rings &rings, const SurfaceAnalysis &analysis,
              const SmoothParams &params, double mean_edge, std::vector<Vec3> &next) {
  const int n = int(mesh.points.size());
  double max_saliency = 0;
  for (double s : analysis.saliency) max_saliency = std::max(max_saliency, s);
  next.resize(n);
#pragma omp parallel
  {
    NeighbourhoodScratch scratch;
    scratch.reserve(64);
    detail::Counters counters;
    double alpha;
#pragma omp for schedule(dynamic, 512)
    for (int i = 0; i < n; ++i)
      next[i] = placeVertex(i, mesh, rings, mesh.points, analysis, params, mean_edge,
                            max_saliency, scratch, alpha, counters);
  }
}

void writeDoubles(const std::string &path, const double *data, size_t count) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char *>(data), std::streamsize(count * sizeof(double)));
}

std::vector<double> readDoubles(const std::string &path) {
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  std::vector<double> v(size_t(f.tellg()) / sizeof(double));
  f.seekg(0);
  f.read(reinterpret_cast<char *>(v.data()), std::streamsize(v.size() * sizeof(double)));
  return v;
}

// stage_bench's options: name=value (a bare name is name=1), over the defaults.
std::map<std::string, std::string> readOptions(int argc, char **argv) {
  std::map<std::string, std::string> opt = {
      {"repeat", "3"}, {"stages", "rings,curvature,saliency,fit,paperfit,smooth"}};
  for (int k = 2; k < argc; ++k) {
    const std::string a = argv[k];
    const size_t eq = a.find('=');
    opt[a.substr(0, eq)] = eq == std::string::npos ? "1" : a.substr(eq + 1);
  }
  return opt;
}

// The paper driver's parameters for "paperfit" and the saved paper positions: its placement and
// α rule.
SmoothParams paperParams() {
  SmoothParams paper;
  paper.placement = PlacementMode::Paper;
  paper.alpha_override = false;
  return paper;
}

// Times the stages `wants` names, `repeat` times each, and prints their medians.
template <class Wants>
void timeStages(const MeshArrays &mesh, Rings &rings, const EdgeStatistics &stats, int repeat,
                Wants wants, bool load_only) {
  const int n = int(mesh.points.size());
  const SmoothParams defaults;
  const double epsilon = defaults.saliency_scale * stats.bbox_diagonal;
  if (wants("rings")) report("rings", timeIt(repeat, [&] { rings = computeRings(n, mesh.faces); }), n);
  SurfaceAnalysis analysis;
  if (!load_only) computeCurvature(mesh.points, mesh.faces, rings, analysis.curvature);
  if (wants("normals"))
    report("normals", timeIt(repeat, [&] {
             computeVertexNormals(mesh.points, mesh.faces, rings, analysis.curvature.normal);
           }), n);
  if (wants("curvature"))
    report("curvature", timeIt(repeat, [&] {
             computeCurvature(mesh.points, mesh.faces, rings, analysis.curvature);
           }), n);
  if (wants("saliency"))
    report("saliency", timeIt(repeat, [&] {
             computeSaliency(mesh.points, rings, analysis.curvature.k2, epsilon, analysis.saliency);
           }), n);
  // Only the paper's mode reads the saliency inside the iterations.
  if (analysis.saliency.empty()) {
    if (wants("paperfit"))
      computeSaliency(mesh.points, rings, analysis.curvature.k2, epsilon, analysis.saliency);
    else
      analysis.saliency.assign(n, 0.0);
  }
  std::vector<Vec3> next;
  if (wants("fit"))
    report("fit", timeIt(repeat, [&] {
             fitSweep(mesh, rings, analysis, defaults, stats.mean_edge_length, next);
           }), n);
  if (wants("paperfit"))
    report("paperfit", timeIt(repeat, [&] {
             fitSweep(mesh, rings, analysis, paperParams(), stats.mean_edge_length, next);
           }), n);
  if (wants("smooth")) {
    VertexQuantities q;
    SmoothReport r;
    const Timing t = timeIt(repeat, [&] { r = smoothMesh(mesh, defaults, next, q); });
    report("smooth", t, n);
    std::printf("           last run's stages (wall): topology %.4f, curvature %.4f, saliency "
                "%.4f, fit %.4f; %.2f M vertex-iterations/s\n",
                r.seconds_topology, r.seconds_curvature, r.seconds_saliency, r.seconds_fit,
                defaults.iterations * n / Timing::median(t.wall) / 1e6);
  }
}

// Prints how far `data` is from the reference `ref` (largest and mean absolute difference).
void compareDoubles(const char *suffix, const std::vector<double> &ref,
                    const std::vector<double> &data) {
  if (ref.size() != data.size()) {
    std::printf("compare %s: size %zu vs %zu\n", suffix, ref.size(), data.size());
    return;
  }
  double max_abs = 0, sum_abs = 0, max_ref = 0;
  for (size_t k = 0; k < ref.size(); ++k) {
    max_abs = std::max(max_abs, std::abs(ref[k] - data[k]));
    sum_abs += std::abs(ref[k] - data[k]);
    max_ref = std::max(max_ref, std::abs(ref[k]));
  }
  std::printf("compare %-9s max |diff| %.3g (relative to max |value| %.3g), mean %.3g\n", suffix,
              max_abs, max_abs / std::max(max_ref, 1e-300), sum_abs / std::max<size_t>(ref.size(), 1));
}

// save= / compare=: the smoothed positions (default and paper mode) and the default's saliency,
// written as raw doubles or compared with such files.
void saveOrCompare(const MeshArrays &mesh, std::map<std::string, std::string> &opt) {
  std::vector<double> sal_default, pos_default, pos_paper;
  VertexQuantities q;
  std::vector<Vec3> out;
  const SmoothParams defaults;
  smoothMesh(mesh, defaults, out, q);
  for (const Vec3 &p : out) pos_default.insert(pos_default.end(), {p.x(), p.y(), p.z()});
  sal_default = q.saliency;
  SmoothParams paper = paperParams();
  paper.newton_step_limit = defaults.newton_step_limit;
  smoothMesh(mesh, paper, out, q);
  for (const Vec3 &p : out) pos_paper.insert(pos_paper.end(), {p.x(), p.y(), p.z()});
  const std::pair<const char *, std::vector<double> *> files[] = {
      {".pos", &pos_default}, {".sal", &sal_default}, {".paperpos", &pos_paper}};
  for (const auto &[suffix, data] : files) {
    if (opt.count("save")) writeDoubles(opt["save"] + suffix, data->data(), data->size());
    if (opt.count("compare")) compareDoubles(suffix, readDoubles(opt["compare"] + suffix), *data);
  }
}

} // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: stage_bench <mesh> [repeat=3] [stages=...] [save=p] [compare=p]\n");
    return 1;
  }
  std::map<std::string, std::string> opt = readOptions(argc, argv);
  const int repeat = std::stoi(opt["repeat"]);
  auto wants = [&](const char *stage) {
    return ("," + opt["stages"] + ",").find(std::string(",") + stage + ",") != std::string::npos;
  };
  tool_mesh::Mesh vmesh;
  if (!tool_mesh::load(vmesh, argv[1], "stage_bench")) return 2;
  const MeshArrays mesh = extractArrays(vmesh);
  const int n = int(mesh.points.size());
  Rings rings = computeRings(n, mesh.faces);
  const EdgeStatistics stats = edgeStatistics(mesh.points, rings);
  const double epsilon = SmoothParams().saliency_scale * stats.bbox_diagonal;
  std::printf("%s: %d vertices, %zu faces, mean edge %.4g, bbox diagonal %.4g, epsilon %.4g "
              "(= %.2f mean edges)\n",
              argv[1], n, mesh.faces.size(), stats.mean_edge_length, stats.bbox_diagonal, epsilon,
              epsilon / stats.mean_edge_length);
  timeStages(mesh, rings, stats, repeat, wants, opt["stages"] == "load");
  if (opt.count("save") || opt.count("compare")) saveOrCompare(mesh, opt);
  return 0;
}
