// manylight_bench: the experiments of Nabata & Iwasaki 2019 (probabilistic visibility for
// many-light rendering): equal-time RMSE of exact / veach / conservative / proposed, the time
// each needs to reach exact's equal-time RMSE (Table 2) with and without the VisibilityCluster
// preprocess, mean skip rates (Table 3), t_skip / t_eval (Table 1), RMSE-over-time curves and
// skip-rate images (Fig. 3). Prints markdown tables and writes JSON + CSV for the plots.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "rayscout/accelerators.h"
#include "bench_support.h"
#include "rayscout/core/output_path.h"
#include "rayscout/image/image.h"
#include "rayscout/manylight/manylight_renderer.h"
#include "rayscout/scene/load_scene.h"

using namespace rayscout;

namespace {

struct BenchScene {
  std::string name, file;
  size_t vpls;
};

struct Options {
  std::vector<std::string> scenes{"sponza", "sibenik_glossy", "conference_large"};
  int width = 1280, height = 720;
  double budget = 4.0;        ///< CPU seconds of rendering per mode (the paper: 60 s wall on 36 threads)
  double ref_factor = 6.0;    ///< reference budget = ref_factor * budget
  double vpl_scale = 1.0;     ///< multiplies the paper's VPL counts
  int threads = 2;
  double clamp_fraction = 0;  ///< geometry-term clamp distance / scene diagonal (0 = off, the default)
  int equal_passes = 0;       ///< > 0: every mode renders this many passes instead of the budget
  int reps = 2;               ///< independent runs per mode (interleaved); MSE * t is averaged
  std::string accel = "bvh";
  // The committed results, wherever the bench is run from (a relative default wrote under the
  // current folder, e.g. build/docs/..., while --help said it was the committed results).
  std::string out_dir = RAYSCOUT_SOURCE_DIR "/docs/figures/manylight";
  std::string json = RAYSCOUT_SOURCE_DIR "/docs/figures/manylight/manylight_results.json";
};

const std::vector<BenchScene> kScenes = {
    {"sponza", "sponza.json", 100000},
    {"sibenik_glossy", "sibenik_glossy.json", 200000},
    {"conference_large", "conference_large.json", 200000},
};

Image to_image(const std::vector<Vec3>& px, int w, int h) {
  Image img(w, h);
  for (size_t i = 0; i < px.size(); ++i) img.pixels[i] = max(px[i], Vec3(0.0f));  // display clamp (sec. 4.3)
  return img;
}

Image skip_to_image(const std::vector<float>& s, int w, int h) {
  Image img(w, h);
  // Fig. 3 style: black = always traced, white = always skipped (linear; PNG encodes sRGB).
  for (size_t i = 0; i < s.size(); ++i) img.pixels[i] = Vec3(srgb_to_linear(std::clamp(s[i], 0.0f, 1.0f)));
  return img;
}

const std::vector<VisibilityMode> kModes = {VisibilityMode::Exact, VisibilityMode::Veach, VisibilityMode::Conservative,
                                            VisibilityMode::Proposed};

/// Per mode, the progress records of each repetition.
using Runs = std::map<VisibilityMode, std::vector<std::vector<ProgressRecord>>>;

/// The reference image and its own noise.
struct Reference {
  Image image;
  double mse = 0;  ///< per pixel and channel
};

/// Exact visibility, many passes, as two independent halves A and B (own seeds). The
/// reference's own noise is MSE_ref = E[(A - B)^2] / 4 per pixel and channel; every measured
/// MSE (against (A + B) / 2, independent of the run) is MSE_run + MSE_ref, so it is subtracted.
Reference render_reference(ManylightRenderer& r, const Options& o) {
  std::vector<Vec3> half[2];
  for (int h = 0; h < 2; ++h) {
    r.reset(VisibilityMode::Exact);
    r.set_seed(0xFEF0 + uint64_t(h));
    r.render_for(o.budget * o.ref_factor / 2, {});
    half[h] = r.image().pixels;
  }
  Reference ref{Image(o.width, o.height)};
  for (size_t i = 0; i < ref.image.pixels.size(); ++i) {
    ref.image.pixels[i] = (half[0][i] + half[1][i]) * 0.5f;
    const Vec3 d = half[0][i] - half[1][i];
    ref.mse += (double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z) / (4.0 * 3.0 * double(ref.image.pixels.size()));
  }
  return ref;
}

/// Every mode, o.reps times, modes interleaved within each repetition so that a change of
/// machine load hits all of them; the first repetition's images are written.
Runs render_modes(ManylightRenderer& r, const std::string& name, const Image& ref, const Options& o) {
  Runs runs;
  for (int rep = 0; rep < o.reps; ++rep)
    for (VisibilityMode mode : kModes) {
      r.reset(mode);
      // Common random numbers: all modes of a repetition draw the same VPL samples pass by
      // pass (the skip decisions use further numbers), so a rare huge sample (an unclamped
      // VPL next to a surface) hits every mode that reaches that pass, not one at random.
      r.set_seed(100 + 16 * uint64_t(rep));
      runs[mode].push_back(o.equal_passes > 0 ? r.render_for(1e300, ref, size_t(o.equal_passes))
                                              : r.render_for(o.budget, ref));
      if (rep > 0) continue;
      write_image(to_image(r.image().pixels, o.width, o.height), o.out_dir + "/" + name + "_" + to_string(mode) + ".png");
      if (mode != VisibilityMode::Exact)
        write_image(skip_to_image(r.skip_image(), o.width, o.height),
                    o.out_dir + "/" + name + "_skip_" + to_string(mode) + ".png");
    }
  return runs;
}

/// Table 2 and 3 of one scene, printed, and its JSON record. Unbiased progressive estimates
/// have MSE ~ 1 / t, so MSE * t is a mode's inverse efficiency and the time to reach exact's
/// equal-time MSE is T * (MSE t)_mode / (MSE t)_exact. This uses every sample of every run; the
/// first crossing of a single, firefly-noisy curve would not.
nlohmann::json summarise(const ManylightRenderer& r, const Runs& runs, const std::function<double(double)>& corrected,
                         const Options& o) {
  const auto& tm = r.timings();
  std::map<VisibilityMode, double> mse_t, mse, skip, passes;
  for (const auto& [mode, reps] : runs)
    for (const auto& rec : reps) {
      mse_t[mode] += corrected(rec.back().rmse) * rec.back().seconds / o.reps;
      mse[mode] += corrected(rec.back().rmse) / o.reps;
      skip[mode] += rec.back().skip_rate / o.reps;
      passes[mode] += double(rec.back().passes) / o.reps;
    }
  const double pre = tm.preprocess_ms() * 1e-3;
  const std::string passes_of = o.equal_passes > 0 ? "the same for every mode" : fmt::format("in {:g} CPU s", o.budget);
  fmt::print("\n| mode | passes ({}) | RMSE (ref-noise corrected) | mean skip rate | time to exact's RMSE | speed-up (exact's time / this) | the same with VisibilityCluster time | per-run MSE*t |\n", passes_of);
  fmt::print("| --- | --- | --- | --- | --- | --- | --- | --- |\n");
  nlohmann::json modes;
  // Exact's mean render time: the budget (slightly exceeded by the last pass), or the time of
  // its equal passes.
  double t_exact = 0;
  for (const auto& rec : runs.at(VisibilityMode::Exact)) t_exact += rec.back().seconds / o.reps;
  for (VisibilityMode mode : kModes) {
    const double t_reach = t_exact * mse_t[mode] / mse_t[VisibilityMode::Exact];
    // With the preprocess: every mode pays VisibilityCluster (exact samples with its pdf
    // too); the probabilistic modes also pay the calibration renders.
    const double extra = mode == VisibilityMode::Exact ? 0.0 : tm.calibration_ms * 1e-3;
    const double with = (t_exact + pre) / (t_reach + pre + extra);
    const double speed = t_exact / t_reach;
    std::string per_run;
    std::vector<double> per;
    for (const auto& rec : runs.at(mode)) {
      per.push_back(corrected(rec.back().rmse) * rec.back().seconds);
      per_run += fmt::format("{}{:.3g}", per_run.empty() ? "" : " ", per.back());
    }
    fmt::print("| {} | {:.1f} | {:.5g} | {:.1f} % | {:.2f} s | {:.2f}x | {:.2f}x | {} |\n", to_string(mode),
               passes[mode], std::sqrt(mse[mode]), 100 * skip[mode], t_reach, speed, with, per_run);
    modes[to_string(mode)] = {{"passes", passes[mode]}, {"rmse", std::sqrt(mse[mode])},
                              {"skip_rate", skip[mode]}, {"time_to_exact_rmse_s", t_reach},
                              {"speedup", speed}, {"speedup_with_preprocess", with}, {"mse_times_t", per}};
  }
  return modes;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "manylight_bench: the experiments of Nabata & Iwasaki 2019. Every mode renders for --budget seconds of "
      "process CPU time (or --equal-passes passes); the modes are interleaved within each of --reps repetitions, "
      "and the tables give the mean over the repetitions (MSE x time averaged), not a median."};
  app.add_option("--scenes", o.scenes, "sponza, sibenik_glossy, conference_large")->capture_default_str();
  app.add_option("--width", o.width)->capture_default_str()->check(CLI::Range(1, 32768));
  app.add_option("--height", o.height)->capture_default_str()->check(CLI::Range(1, 32768));
  app.add_option("--budget", o.budget, "process CPU seconds of rendering per mode (all threads summed)")->capture_default_str()->check(CLI::Range(1e-3, 1e6));
  app.add_option("--ref-factor", o.ref_factor, "reference budget / budget")->capture_default_str()->check(CLI::Range(1e-3, 1e6));
  app.add_option("--vpl-scale", o.vpl_scale, "multiplies the VPL counts (1 = the paper's)")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1e3));
  app.add_option("--threads", o.threads, "threads (the budgets are process CPU time, all threads summed)")
      ->capture_default_str()->check(CLI::Range(1, 4096));
  app.add_option("--reps", o.reps, "independent runs per mode, modes interleaved within each (the tables average them)")->capture_default_str()->check(CLI::Range(1, 1000000));
  app.add_option("--equal-passes", o.equal_passes,
                 "render this many passes per mode instead of --budget (paired comparison; 0 = use --budget); "
                 "the reference still takes --budget x --ref-factor")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  app.add_option("--clamp-fraction", o.clamp_fraction, "G clamp distance / scene diagonal (0 = off)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--accel", o.accel,
                 "accelerator of every ray: light paths, camera paths, cluster visibility and shadow rays "
                 "(rayscout accelerators lists them)")
      ->capture_default_str();
  app.add_option("--out-dir", o.out_dir, "folder for rmse_over_time.csv and the images (the default holds the committed results)")
      ->capture_default_str();
  app.add_option("--json", o.json, "results file for manylight_tables.py (the default is the committed results)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  return bench::run_bench("manylight_bench", [&] {
    // Every name is checked before the output folder and files are touched: a misspelt scene
    // must not truncate the committed results.
    std::vector<std::string> scene_names;
    for (const BenchScene& s : kScenes) scene_names.push_back(s.name);
    bench::check_names("--scenes", o.scenes, scene_names);
    check_accelerator(o.accel);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(o.threads));
    std::filesystem::create_directories(o.out_dir);
    check_output_path(o.json, "--json");

    nlohmann::json results = nlohmann::json::array();
    fmt::print("# machine: {}\n", bench::machine_description());
    std::ofstream csv;  // opened once a scene has loaded: a run that skips every scene writes nothing
    for (const std::string& name : o.scenes) {
      auto it = std::find_if(kScenes.begin(), kScenes.end(), [&](const BenchScene& s) { return s.name == name; });
      const std::optional<Scene> loaded =
          bench::load_or_skip("--scenes", std::string(RAYSCOUT_BENCH_DIR) + "/scenes/" + it->file, name);
      if (!loaded) continue;
      const Scene& scene = *loaded;
      if (!csv.is_open()) {
        csv.open(o.out_dir + "/rmse_over_time.csv");
        if (!csv) throw InputError(o.out_dir + "/rmse_over_time.csv: cannot open for writing");
        csv << "scene,mode,rep,seconds,passes,rmse_raw,rmse,skip_rate\n";
      }
      auto accel = make_accelerator(o.accel, scene);
      ManylightConfig config;
      config.width = o.width;
      config.height = o.height;
      config.vpl_count = size_t(double(it->vpls) * o.vpl_scale);
      config.cpu_clock = true;
      config.clamp_distance = float(o.clamp_fraction * length(scene.bounds().diagonal()));
      ManylightRenderer r(scene, *accel, config);
      const auto& tm = r.timings();
      fmt::print("\n## {} ({} triangles, {} VPLs from {} paths, {}x{}, accel {}, threads {}, G clamp {})\n", name,
                 scene.triangles.size(), r.vpls().vpls.size(), r.vpls().light_paths, o.width, o.height,
                 accel->name(), o.threads, o.clamp_fraction > 0 ? fmt::format("{} x diagonal", o.clamp_fraction) : "off");
      r.calibrate();
      fmt::print("preprocess (CPU s): VPLs {:.2f}, shading points {:.2f}, clustering {:.2f}, visibility {:.2f} "
                 "({} rays, {} refined pairs), pmf {:.2f}; calibration {:.2f}; t_eval {:.3g} us, t_skip {:.3g} us, "
                 "t_skip/t_eval {:.3f}\n",
                 tm.vpl_ms * 1e-3, tm.shading_points_ms * 1e-3, tm.cluster_ms * 1e-3, tm.visibility_ms * 1e-3,
                 r.clusters().shadow_rays, r.clusters().refined_pairs, tm.pmf_ms * 1e-3, tm.calibration_ms * 1e-3,
                 tm.t_eval * 1e6, tm.t_skip * 1e6, tm.t_skip / tm.t_eval);
      std::fflush(stdout);
      const Reference ref = render_reference(r, o);
      write_image(to_image(ref.image.pixels, o.width, o.height), o.out_dir + "/" + name + "_reference.png");
      write_image(to_image(ref.image.pixels, o.width, o.height), o.out_dir + "/" + name + "_reference.exr");
      const Runs runs = render_modes(r, name, ref.image, o);
      auto corrected = [&](double rmse) { return std::max(1e-30, rmse * rmse - ref.mse); };
      for (const auto& [mode, reps] : runs)
        for (size_t rep = 0; rep < reps.size(); ++rep)
          for (const auto& p : reps[rep])
            csv << name << "," << to_string(mode) << "," << rep << "," << p.seconds << "," << p.passes << "," << p.rmse
                << "," << std::sqrt(corrected(p.rmse)) << "," << p.skip_rate << "\n";
      nlohmann::json js = {{"scene", name}, {"triangles", scene.triangles.size()}, {"vpls", r.vpls().vpls.size()},
                           {"width", o.width}, {"height", o.height}, {"threads", o.threads}, {"accel", accel->name()},
                           {"budget_cpu_s", o.budget}, {"reference_cpu_s", o.budget * o.ref_factor},
                           {"preprocess_cpu_s", tm.preprocess_ms() * 1e-3}, {"reps", o.reps},
                           {"clamp_fraction", o.clamp_fraction},
                           {"vpl_s", tm.vpl_ms * 1e-3}, {"shading_points_s", tm.shading_points_ms * 1e-3},
                           {"cluster_s", tm.cluster_ms * 1e-3}, {"visibility_s", tm.visibility_ms * 1e-3},
                           {"pmf_s", tm.pmf_ms * 1e-3}, {"calibration_s", tm.calibration_ms * 1e-3},
                           {"t_eval_us", tm.t_eval * 1e6}, {"t_skip_us", tm.t_skip * 1e6},
                           {"t_skip_over_t_eval", tm.t_skip / tm.t_eval}, {"rmse_ref_noise", std::sqrt(ref.mse)},
                           {"shadow_rays_visibility_cluster", r.clusters().shadow_rays},
                           {"refined_pairs", r.clusters().refined_pairs}};
      js["modes"] = summarise(r, runs, corrected, o);
      std::fflush(stdout);
      results.push_back(js);
      write_file(o.json, results.dump(2) + "\n", "--json");
    }
    if (results.empty()) fmt::print("\nno scene rendered: nothing written\n");
    else fmt::print("\nwrote {} and {}/rmse_over_time.csv\n", o.json, o.out_dir);
    return 0;
  });
}
