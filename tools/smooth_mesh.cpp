// smooth_mesh: runs one of the plugin's filters in-process (the same core as the MeshLab plugin,
// without Qt), for benchmarks and parameter sweeps.
//
//   smooth_mesh [--filter smooth|saliency] <in> <out.ply> [name=value ...]
//
// Parameters as in the .mlx scripts (enums by index, label or method key; see write_mlx). Prints the filter's log, then one JSON line
// with the wall time and the process's memory (MB) before the filter and at its peak (resident
// set and mapped address space, from /proc/self/status: what the filter's memory estimate is
// measured from). Exit code 2 when the filter refuses the mesh (the reason on stderr).
#include "tool_mesh.h"

#include <filter_saliency_bezier_smooth/apply_filters.h>

#include <cstring>

using namespace saliency_bezier;

int main(int argc, char **argv) {
  int a = 1;
  FilterId id = FilterId::SaliencyBezierSmooth;
  if (a + 1 < argc && std::strcmp(argv[a], "--filter") == 0) {
    id = std::strcmp(argv[a + 1], "saliency") == 0 ? FilterId::ComputeSaliencyCurvature
                                                   : FilterId::SaliencyBezierSmooth;
    a += 2;
  }
  if (argc - a < 2) {
    std::fprintf(stderr, "usage: smooth_mesh [--filter smooth|saliency] <in> <out.ply> "
                         "[name=value ...]\n");
    return 1;
  }
  const std::string in = argv[a], out = argv[a + 1];
  ParameterValues values = defaultParameters(id);
  for (int k = a + 2; k < argc; ++k) {
    const std::string arg = argv[k];
    const size_t eq = arg.find('=');
    const std::string name = arg.substr(0, eq);
    const ParamSpec *spec = nullptr;
    for (const ParamSpec &s : parameterSpecs(id))
      if (s.name == name) spec = &s;
    if (eq == std::string::npos || !spec) {
      std::fprintf(stderr, "smooth_mesh: '%s' is not name=value with a parameter of the filter; "
                           "they are:\n%s", arg.c_str(), parameterUsage(id).c_str());
      return 1;
    }
    const std::string error = parseParameter(*spec, arg.substr(eq + 1), values[name]);
    if (!error.empty()) {
      std::fprintf(stderr, "smooth_mesh: %s\n", error.c_str());
      return 1;
    }
  }
  tool_mesh::Mesh mesh;
  if (!tool_mesh::load(mesh, in, "smooth_mesh")) return 2;
  const double rss_before = detail::procField("/proc/self/status", "VmRSS"),
               vm_before = detail::procField("/proc/self/status", "VmSize");
  const auto start = vcg_ext::Clock::now();
  const FilterOutcome outcome = applyFilterById(id, mesh, values, nullptr);
  const double seconds = vcg_ext::secondsSince(start);
  for (const std::string &line : outcome.log) std::fprintf(stderr, "%s\n", line.c_str());
  if (!outcome.ok) {
    std::fprintf(stderr, "smooth_mesh: %s\n", outcome.error.c_str());
    return 2;
  }
  if (!tool_mesh::save(mesh, out, "smooth_mesh", true)) return 2;
  std::printf("{\"seconds\": %.6f, \"vertices\": %d, \"rss_before_mb\": %.1f, "
              "\"peak_rss_mb\": %.1f, \"vm_before_mb\": %.1f, \"peak_vm_mb\": %.1f}\n",
              seconds, mesh.vn, rss_before / 1e6,
              detail::procField("/proc/self/status", "VmHWM") / 1e6, vm_before / 1e6,
              detail::procField("/proc/self/status", "VmPeak") / 1e6);
  return 0;
}
