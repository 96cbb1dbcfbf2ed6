// ManylightIntegrator: ManylightRenderer as an Integrator, with time budget, RMSE log and skip image.
#include "rayscout/manylight/manylight_integrator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "rayscout/core/file_extension.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/output_path.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/image/image.h"
#include "rayscout/manylight/manylight_renderer.h"

namespace rayscout {
namespace {

/// The summary's costs: where t_eval and t_skip came from, or that exact has none (it never
/// skips, so it neither calibrates nor reads given costs).
std::string cost_summary(VisibilityMode mode, const ManylightTimings& tm) {
  if (mode == VisibilityMode::Exact) return "no t_eval, t_skip (exact never skips a shadow ray)";
  const std::string costs = fmt::format("t_eval {:.3g} us, t_skip {:.3g} us", tm.t_eval * 1e6, tm.t_skip * 1e6);
  return tm.calibrated ? fmt::format("calibration {:.2f} s, {}", tm.calibration_ms * 1e-3, costs) : costs + " (given)";
}

class ManylightIntegrator final : public Integrator {
 public:
  explicit ManylightIntegrator(ManylightRunOptions o) : o_(std::move(o)) {}
  std::string name() const override { return "manylight"; }

  Image render(const Scene& scene, const Accelerator& accel, const RenderConfig& rc, RenderStats* stats) const override {
    const auto start = SteadyClock::now();
    ManylightConfig config = o_.config;
    config.width = rc.width;
    config.height = rc.height;
    config.spp = rc.spp;
    config.seed = rc.seed;
    Image reference;
    if (!o_.reference.empty()) {
      reference = read_image(o_.reference);
      if (reference.width != rc.width || reference.height != rc.height)
        throw InputError(fmt::format("--reference {}: {}x{} but rendering {}x{}", o_.reference, reference.width,
                                     reference.height, rc.width, rc.height));
    }
    ManylightRenderer r(scene, accel, config);
    if (o_.pass_seed) r.set_seed(*o_.pass_seed);
    if (config.mode != VisibilityMode::Exact) r.calibrate();
    if (const std::string w = skipping_saves_nothing_warning(config.mode, r.timings()); !w.empty())
      fmt::print(stderr, "manylight: warning: {}\n", w);
    const auto& tm = r.timings();
    // Progress per pass, timed from the first pass (the preprocess is done); with a time
    // budget the pass count is the one the time so far predicts.
    const size_t max_passes = o_.time_budget > 0 ? SIZE_MAX : std::max<size_t>(1, o_.passes);
    auto on_pass = [&](const ProgressRecord& rec) {
      RenderProgress p;
      p.pass = int(rec.passes) - 1;
      const double predicted = std::ceil(o_.time_budget * double(rec.passes) / std::max(rec.seconds, 1e-9));
      p.passes = o_.time_budget > 0 ? int(std::clamp(predicted, double(rec.passes), 1e9)) : int(max_passes);
      p.rays_traced = r.shadow_rays_traced();
      p.elapsed_s = rec.seconds;
      rc.on_progress(p);
    };
    const auto records = r.render_for(o_.time_budget > 0 ? o_.time_budget : 1e300, reference, max_passes,
                                      rc.on_progress ? std::function<void(const ProgressRecord&)>(on_pass) : nullptr);
    const Image image = r.image();
    if (!o_.skip_image.empty()) {
      write_image(skip_rate_image(r.skip_image(), rc.width, rc.height, o_.skip_image), o_.skip_image);
    }
    if (!o_.rmse_log.empty()) write_log(r, records);
    if (o_.verbose) {
      if (rc.on_progress) fmt::print(stderr, "\n");  // ends the progress line
      fmt::print(stderr,
                 "manylight: {} VPLs ({} light paths), {} shading clusters x {} VPL clusters; preprocess {:.2f} s "
                 "(VPLs {:.2f}, shading points {:.2f}, clustering {:.2f}, visibility {:.2f}, pmf {:.2f}); {}\n",
                 r.vpls().vpls.size(), r.vpls().light_paths, r.clusters().shading.size(),
                 r.clusters().vpl_cluster_count(), tm.preprocess_ms() * 1e-3, tm.vpl_ms * 1e-3,
                 tm.shading_points_ms * 1e-3, tm.cluster_ms * 1e-3, tm.visibility_ms * 1e-3, tm.pmf_ms * 1e-3,
                 cost_summary(config.mode, tm));
      fmt::print(stderr, "manylight: visibility {}, {} passes in {:.2f} s, mean skip rate {:.1f} %, {} shadow rays{}\n",
                 to_string(config.mode), r.passes(), records.back().seconds, 100 * r.skip_rate(),
                 r.shadow_rays_traced(),
                 records.back().rmse >= 0 ? fmt::format(", RMSE {:.6g}", records.back().rmse) : std::string());
    }
    if (stats) {
      stats->total_ms = ms_since(start);
      stats->shading_ms = stats->total_ms;
    }
    return image;
  }

 private:
  void write_log(const ManylightRenderer& r, const std::vector<ProgressRecord>& records) const {
    std::ostringstream f;
    const bool csv = rmse_log_format(o_.rmse_log) == RmseLogFormat::Csv;
    if (csv) {
      f << "seconds,passes,rmse,skip_rate\n";
      for (const auto& p : records) f << p.seconds << "," << p.passes << "," << p.rmse << "," << p.skip_rate << "\n";
    } else {
      nlohmann::json j;
      const auto& tm = r.timings();
      j["visibility"] = to_string(r.config().mode);
      j["vpls"] = r.vpls().vpls.size();
      j["preprocess_s"] = tm.preprocess_ms() * 1e-3;
      j["calibration_s"] = tm.calibration_ms * 1e-3;
      const bool has_costs = r.config().mode != VisibilityMode::Exact;  // null for exact (cost_summary)
      j["t_eval_us"] = has_costs ? nlohmann::json(tm.t_eval * 1e6) : nlohmann::json();
      j["t_skip_us"] = has_costs ? nlohmann::json(tm.t_skip * 1e6) : nlohmann::json();
      j["skip_rate"] = r.skip_rate();
      for (const auto& p : records)
        j["records"].push_back({{"seconds", p.seconds}, {"passes", p.passes}, {"rmse", p.rmse}, {"skip_rate", p.skip_rate}});
      f << j.dump(2) << "\n";
    }
    write_file(o_.rmse_log, f.str(), "--rmse-log");
  }

  ManylightRunOptions o_;
};

}  // namespace

std::optional<RmseLogFormat> rmse_log_format(const std::string& path) {
  // In any case, as image extensions are (.PNG is a PNG).
  const std::string ext = lower_extension(path);
  if (ext == ".json") return RmseLogFormat::Json;
  if (ext == ".csv") return RmseLogFormat::Csv;
  return std::nullopt;
}

Image skip_rate_image(std::span<const float> rates, int width, int height, const std::filesystem::path& path) {
  const bool srgb = writes_srgb(path);
  Image image(width, height);
  for (size_t i = 0; i < rates.size() && i < image.pixels.size(); ++i)
    image.pixels[i] = Vec3(srgb ? srgb_to_linear(rates[i]) : rates[i]);
  return image;
}

std::unique_ptr<Integrator> make_manylight_integrator(const ManylightRunOptions& options) {
  return std::make_unique<ManylightIntegrator>(options);
}

}  // namespace rayscout
