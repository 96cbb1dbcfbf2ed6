// The many-light renderer behind the render module's Integrator interface (`--integrator manylight`).
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "rayscout/image/image.h"
#include "rayscout/manylight/manylight_config.h"
#include "rayscout/render/renderer.h"

namespace rayscout {

/// What `rayscout render --integrator manylight` does beyond RenderConfig.
struct ManylightRunOptions {
  ManylightConfig config;     ///< width, height, spp and seed are taken from RenderConfig
  double time_budget = 0;     ///< seconds of progressive rendering (after the preprocess); 0 = use passes
  size_t passes = 16;         ///< passes when time_budget = 0 (each: samples_per_pass VPLs per point)
  std::string reference;      ///< image (.exr/.pfm) to record RMSE against after every pass
  std::string rmse_log;       ///< where to write the RMSE-over-time records: .json or .csv
  std::string skip_image;     ///< where to write the per-pixel skip rate (grey: white = skipped)
  bool verbose = true;        ///< summary lines on stderr
  /// Seed of the render passes only (unset: the render seed). VPLs and shading points keep the
  /// render seed, so a reference rendered with another pass seed sums the same eq. (1) with
  /// noise independent of the run measured against it.
  std::optional<uint64_t> pass_seed;
};

/// How an RMSE log is written, by the end of its file name: ".json" or ".csv" in any case;
/// nullopt for any other name.
enum class RmseLogFormat { Json, Csv };
std::optional<RmseLogFormat> rmse_log_format(const std::string& path);

/// The width x height grey picture of per-pixel skip rates (ManylightRenderer::skip_image) to
/// hand to write_image(path), so that the file holds the rate as its reader sees it: .exr and
/// .pfm store the rate itself; .png stores 8-bit pixel values rate * 255 (write_image
/// sRGB-encodes, so the linear value handed to it is srgb_to_linear(rate)).
Image skip_rate_image(std::span<const float> rates, int width, int height, const std::filesystem::path& path);

/// An Integrator running ManylightRenderer with the given options (copied).
std::unique_ptr<Integrator> make_manylight_integrator(const ManylightRunOptions& options);

}  // namespace rayscout
