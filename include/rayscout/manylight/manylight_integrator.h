// The many-light renderer behind the render module's Integrator interface (`--integrator manylight`).
#pragma once

#include <memory>
#include <string>

#include "rayscout/manylight/config.h"
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
};

/// An Integrator running ManylightRenderer with the given options (copied).
std::unique_ptr<Integrator> make_manylight_integrator(const ManylightRunOptions& options);

}  // namespace rayscout
