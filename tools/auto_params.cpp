// auto_params: runs the automatic mode (vcg_ext/methods/automatic/auto_smooth.h), or one of its two drivers, with
// internal parameters set on the command line, to measure parameter choices (docs/studies/scanner-noise.md).
// The filter itself never reads these: its defaults are the structs' defaults.
//
//   auto_params <in> <out.ply> [mode=auto|feature|organic] [name=value ...]
//
// `auto_params --list` prints the names. Prints the mode that ran and the report's figures as one
// JSON line on stdout (the last line), the summary on stderr.
#include "tool_mesh.h"

#include <vcg_ext/methods/automatic/auto_smooth.h>
#include <vcg_ext/core/mesh_arrays.h>

#include <cstdio>
#include <functional>
#include <map>
#include <sstream>
#include <string>

using namespace vcg_ext;

namespace {

using Setter = std::function<void(double)>;

std::map<std::string, Setter> registry(AutoSmoothParams &p) {
  std::map<std::string, Setter> r;
  auto real = [&](const std::string &name, double &x) { r[name] = [&x](double v) { x = v; }; };
  auto integer = [&](const std::string &name, int &x) { r[name] = [&x](double v) { x = int(v); }; };
  FeatureSmoothParams &f = p.feature;
  OrganicSmoothParams &o = p.organic;
  r["strength"] = [&p](double v) { p.feature.strength = p.organic.strength = v; };
  real("o.strength", o.strength); // the organic mode's alone (the choice reads the feature's)
  integer("f.prepass_pairs", f.prepass_pairs);
  real("f.planar_extra", f.planar_extra);
  real("f.planar_share_from", f.planar_share_from);
  real("f.planar_correlated_shift", f.planar_correlated_shift);
  real("f.planar_share_full", f.planar_share_full);
  real("f.planar_normal_share", f.planar_normal_share);
  real("f.planar_vertex_share", f.planar_vertex_share);
  integer("f.correlated_bands", f.correlated_bands);
  real("f.clean_spread_deg", f.clean_spread_deg);
  real("f.noisy_spread_deg", f.noisy_spread_deg);
  r["f.bilateral"] = [&f](double v) {
    f.normals.kind = v != 0 ? NormalFilterKind::Bilateral : NormalFilterKind::Guided;
  };
  real("f.sigma_s", f.normals.sigma_s);
  real("f.sigma_r", f.normals.sigma_r);
  integer("f.normal_iterations", f.normals.iterations);
  integer("f.guidance_every", f.normals.guidance_every);
  integer("f.check_iterations", f.check_iterations);
  real("f.area_power", f.normals.area_power);
  integer("f.outer_iterations", f.outer_iterations);
  integer("f.vertex_iterations", f.vertex_iterations);
  integer("f.patch_iterations", f.patch_iterations);
  real("f.tangential", f.tangential);
  integer("f.relax_rings", f.relax_rings);
  real("f.fold_cos", f.fold_cos);
  real("o.clean_spread_deg", o.clean_spread_deg);
  real("o.noisy_spread_deg", o.noisy_spread_deg);
  real("o.full_noise_roughness", o.full_noise_roughness);
  integer("o.max_patch_updates", o.max_patch_updates);
  real("o.lambda", o.bands.lambda);
  real("o.mu", o.bands.mu);
  real("o.fixed_alpha", o.bands.fixed_alpha);
  real("o.max_alpha", o.bands.max_alpha);
  real("o.robust_quantile", o.bands.robust_quantile);
  real("o.chebyshev_tolerance", o.bands.chebyshev_tolerance);
  real("o.noise_for_any_alpha", o.bands.noise_for_any_alpha);
  real("o.noise_for_full_alpha", o.bands.noise_for_full_alpha);
  r["o.coloured"] = [&o](double v) { o.coloured_noise = v != 0; };
  real("o.max_octave_rise", o.colour.max_octave_rise);
  real("o.max_rise", o.colour.max_rise);
  real("o.colour_weight", o.colour.weight);
  real("o.level_white", o.colour.level_white);
  real("o.rise_white", o.colour.rise_white);
  real("o.rise_coloured", o.colour.rise_coloured);
  integer("o.robust_max_pairs", o.bands.robust_max_pairs);
  integer("o.local_window_steps", o.bands.local_window_steps);
  integer("o.local_first_band", o.bands.local_first_band);
  integer("o.local_last_band", o.bands.local_last_band);
  integer("o.fold_rounds", o.folds.max_rounds);
  real("o.fold_min_tail", o.fold_min_tail);
  real("o.fold_min_level", o.fold_min_level);
  real("o.heavy_share_power", o.heavy_share_power);
  real("o.unseen_strength", o.unseen_noise_strength);
  real("o.heavy_from", o.heavy.from);
  real("o.heavy_power", o.heavy.power);
  real("o.heavy_max", o.heavy.max_factor);
  real("flat_share_factor_power", p.flat_share_factor_power);
  real("f.heavy_from", f.heavy.from);
  real("f.heavy_power", f.heavy.power);
  real("f.heavy_max", f.heavy.max_factor);
  real("f.amplitude_need", f.heavy.need_weight);
  real("f.need_ratio_from", f.heavy.need_ratio_from);
  real("f.need_ratio_full", f.heavy.need_ratio_full);
  real("f.correlated_extra", f.correlated.extra);
  real("f.correlated_from", f.correlated.share_from);
  real("f.correlated_full", f.correlated.share_full);
  real("f.correlated_amp_from", f.correlated.amplitude_from);
  real("f.correlated_amp_full", f.correlated.amplitude_full);
  real("f.correlated_ratio_from", f.correlated.ratio_from);
  real("f.correlated_ratio_full", f.correlated.ratio_full);
  r["tail_power"] = [&p](double v) { p.feature.tails.power = p.organic.tails.power = v; };
  r["tail_max"] = [&p](double v) { p.feature.tails.max_factor = p.organic.tails.max_factor = v; };
  r["tail_from"] = [&p](double v) { p.feature.tails.level_from = p.organic.tails.level_from = v; };
  r["tail_full"] = [&p](double v) { p.feature.tails.level_full = p.organic.tails.level_full = v; };
  // Impulses: one setting for both modes (the automatic mode reads the feature mode's).
  r["imp.rounds"] = [&p](double v) { p.feature.impulses.rounds = p.organic.impulses.rounds = int(v); };
  r["imp.min_share"] = [&p](double v) { p.feature.impulses.min_share = p.organic.impulses.min_share = v; };
  r["imp.min_size"] = [&p](double v) { p.feature.impulses.min_size = p.organic.impulses.min_size = v; };
  r["imp.relative_size"] = [&p](double v) { p.feature.impulses.relative_size = p.organic.impulses.relative_size = v; };
  r["imp.isolation"] = [&p](double v) { p.feature.impulses.isolation = p.organic.impulses.isolation = v; };
  real("o.level_coloured", o.colour.level_coloured);
  real("o.noise_scale", o.bands.noise_scale);
  integer("o.sigma_normal_pairs", o.bands.sigma_normal_pairs);
  real("o.min_noise_edges", o.bands.min_noise_edges);
  integer("o.boundary_pairs", o.bands.boundary_pairs);
  real("o.alpha_whole_patch_step", o.bands.alpha_whole_patch_step);
  r["o.colour"] = [](double) {}; // a list: o.colour=c0,c1,... (energy multipliers per band)
  integer("reference_pairs", p.reference_pairs);
  real("feature_flat_share", p.feature_flat_share);
  real("feature_confirmed_share", p.feature_confirmed_share);
  real("min_crease_density", p.min_crease_density); // 0: the confirmed share always counts
  real("flat_deg", p.flat_deg);
  integer("max_windows", p.windows.max_windows); // 0: the evidence on the whole mesh
  integer("min_windows", p.windows.min_windows);
  integer("core_rings", p.windows.core_rings);
  real("window_errors", p.window_errors);
  real("window_face_share", p.windows.face_share);
  real("window_max_face_share", p.windows.max_face_share);
  return r;
}

// The command line's settings (argv[3...]: name=value, mode=auto|feature|organic) into `params`
// and `mode`; false, with a message, on one that is not a known name=value.
bool readSettings(int argc, char **argv, const std::map<std::string, Setter> &names,
                  AutoSmoothParams &params, std::string &mode) {
  for (int a = 3; a < argc; ++a) {
    const std::string arg = argv[a];
    const size_t eq = arg.find('=');
    const std::string name = arg.substr(0, eq);
    if (eq == std::string::npos) {
      std::fprintf(stderr, "auto_params: '%s' is not name=value\n", arg.c_str());
      return false;
    }
    if (name == "mode") {
      mode = arg.substr(eq + 1);
      continue;
    }
    auto it = names.find(name);
    if (it == names.end()) {
      std::fprintf(stderr, "auto_params: unknown parameter '%s' (auto_params --list)\n",
                   name.c_str());
      return false;
    }
    if (name == "o.colour") {
      std::stringstream list(arg.substr(eq + 1));
      params.organic.bands.noise_colour.clear();
      for (std::string x; std::getline(list, x, ',');)
        params.organic.bands.noise_colour.push_back(std::stod(x));
      continue;
    }
    it->second(std::stod(arg.substr(eq + 1)));
  }
  return true;
}

// What ran: the mode's letter (F, O, or C: measured clean) and the reports the figures come from.
struct Run {
  char ran = 'C';
  AutoSmoothReport a;
  FeatureSmoothReport f;
  OrganicSmoothReport o;
  const FeatureSmoothReport *feature = nullptr;
  const OrganicSmoothReport *organic = nullptr;
};

void runMode(const std::string &mode, const MeshArrays &arrays, const AutoSmoothParams &params,
             std::vector<Vec3> &result, VertexQuantities &quantities, Run &run) {
  if (mode == "feature") {
    run.f = featureSmoothMesh(arrays, params.feature, result, quantities);
    run.feature = &run.f;
    run.ran = run.f.amount > 0 ? 'F' : 'C';
  } else if (mode == "organic") {
    run.o = organicSmoothMesh(arrays, params.organic, result, quantities);
    run.organic = &run.o;
    run.ran = run.o.amount > 0 ? 'O' : 'C';
  } else {
    run.a = autoSmoothMesh(arrays, params, result, quantities);
    if (run.a.decided && !run.a.chose_feature) {
      run.ran = 'O';
      run.organic = &run.a.organic;
    } else {
      run.ran = run.a.decided ? 'F' : 'C';
      run.feature = &run.a.feature;
    }
  }
}

// The report's figures as one JSON line on stdout.
void printFigures(const Run &run, double seconds, int faces) {
  const FeatureSmoothReport *feature = run.feature;
  const OrganicSmoothReport *organic = run.organic;
  const AutoSmoothReport &a = run.a;
  const NoiseEstimate &noise = feature ? feature->noise : organic->noise;
  std::printf("{\"mode\": \"%c\", \"seconds\": %.4f, \"level\": %.4f, \"roughness\": %.4f, "
              "\"spectrum\": [",
              run.ran, seconds, noise.level, feature ? feature->roughness : organic->roughness);
  for (size_t b = 0; b < noise.spectrum.size(); ++b)
    std::printf("%s%.4f", b ? ", " : "", noise.spectrum[b]);
  std::printf("], \"flat_share\": %.4f, \"confirmed_share\": %.4f, \"crease_pairs\": %ld, "
              "\"crease_density\": %.3f",
              a.evidence.flat_share, a.evidence.confirmed_share, a.evidence.crease_pairs,
              a.evidence.crease_density);
  std::printf(", \"tail\": %.4f, \"tail_factor\": %.4f", noise.tail,
              feature ? feature->tail_factor : organic->tail_factor);
  std::printf(", \"amplitude\": %.4f, \"correlated_share\": %.3f", noise.amplitude,
              noise.correlated_share);
  const Impulses &impulses = feature == &run.f   ? run.f.impulses
                             : organic == &run.o ? run.o.impulses
                                                 : run.a.impulses;
  std::printf(", \"impulse_share\": %.5f, \"impulse_size\": %.4f, \"impulse_moves\": %ld",
              impulses.share, impulses.median_size, impulses.moved);
  if (a.windowed)
    std::printf(", \"windowed\": true, \"flat_error\": %.4f, \"confirmed_error\": %.4f, "
                "\"window_face_share\": %.3f",
                a.flat_error, a.confirmed_error, double(a.window_faces) / double(std::max(1, faces)));
  if (organic) {
    std::printf(", \"fine_snr\": %.3f, \"slope\": %.2f, \"coarse_snr\": %.2f",
                organic->bands.fine_snr, organic->bands.shape_slope, organic->bands.coarse_snr);
    std::printf(", \"fold_moves\": %ld, \"heavy_factor\": %.3f", organic->fold_moves,
                organic->heavy_factor);
    std::printf(", \"noise_edges\": %.4f, \"alpha\": %.3f, \"gains\": [",
                organic->bands.noise_edges, organic->bands.alpha);
    for (size_t b = 0; b < organic->bands.gains.size(); ++b)
      std::printf("%s%.3f", b ? ", " : "", organic->bands.gains[b]);
    std::printf("]");
  }
  if (feature)
    std::printf(", \"prepass_pairs\": %d, \"normal_iterations\": %d, \"vertex_iterations\": %d, "
                "\"heavy_factor\": %.3f, \"correlated_factor\": %.3f",
                feature->prepass_pairs, feature->normal_iterations, feature->vertex_iterations,
                feature->heavy_factor, feature->correlated_factor);
  std::printf("}\n");
}

} // namespace

int main(int argc, char **argv) {
  AutoSmoothParams params;
  const auto names = registry(params);
  if (argc == 2 && std::string(argv[1]) == "--list") {
    for (const auto &[name, set] : names) std::printf("%s\n", name.c_str());
    return 0;
  }
  if (argc < 3) {
    std::fprintf(stderr, "usage: auto_params <in> <out.ply> [mode=auto|feature|organic] "
                         "[name=value ...]  (auto_params --list)\n");
    return 1;
  }
  std::string mode = "auto";
  if (!readSettings(argc, argv, names, params, mode)) return 1;
  tool_mesh::Mesh mesh;
  if (!tool_mesh::load(mesh, argv[1], "auto_params")) return 2;
  const MeshArrays arrays = extractArrays(mesh);
  std::vector<Vec3> result;
  VertexQuantities quantities;
  const auto start = Clock::now();
  Run run;
  runMode(mode, arrays, params, result, quantities, run);
  const double seconds = secondsSince(start);
  if (result.size() != arrays.points.size()) result = arrays.points;
  writePositions(mesh, arrays, result);
  if (!tool_mesh::save(mesh, argv[2], "auto_params", false)) return 2;
  std::fprintf(stderr, "mode: %c\n", run.ran);
  printFigures(run, seconds, mesh.fn);
  return 0;
}
