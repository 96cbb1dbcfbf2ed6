// The integrators `rayscout render --integrator` knows: one table that --help, the option
// checks, the unread-options warning and the memory check all read.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "rayscout/render/renderer.h"

namespace rayscout::cli {

/// Memory an integrator needs beyond a pass's camera rays, film and image (its bytes, and the
/// words that explain them in the error; "" when there are none).
struct IntegratorMemory {
  double bytes = 0;
  std::string explained;
};

/// Options of one integrator alone, added to `rayscout render` as an option group.
struct IntegratorOptionGroup {
  /// Adds the options to the group.
  std::function<void(CLI::App& group)> add;
  /// Warns (stderr) about options of the group that the parsed run does not read.
  std::function<void(const CLI::App& group)> warn_unread;
};

/// One integrator of the CLI. Adding an integrator is one entry of the table (integrators.cpp).
struct IntegratorEntry {
  std::string name;
  /// Its line in `rayscout render --help`.
  std::string description;
  /// The options of `rayscout render` that only some integrators read, and this one does (any
  /// other of them given is warned about as ignored).
  std::vector<std::string> reads = {};
  /// Its own options (an option group named after it), if any.
  const IntegratorOptionGroup* option_group = nullptr;
  /// Renders the camera's thin lens (depth of field); a pinhole otherwise (warned about).
  bool thin_lens = true;
  /// Lit by point lights only (a scene without them is warned about).
  bool point_lights_only = false;
  /// Occlusion rays each camera ray's hit sends in the same batch (~100 bytes each), given the
  /// scene's point lights (0 before the scene is loaded).
  std::function<double(const RenderConfig&, size_t point_lights)> occlusion_rays_per_hit = {};
  /// Memory of its own (nothing when not given), e.g. manylight's VPLs and clusters.
  std::function<IntegratorMemory(const RenderConfig&)> own_memory = {};
  /// What the progress line says before the first batch.
  std::string first_progress = "render: the first batch";
  /// Creates the integrator for a run.
  std::function<std::unique_ptr<Integrator>()> make = {};
};

/// Every integrator, in the order `rayscout render --help` lists them.
const std::vector<IntegratorEntry>& integrator_table();

/// The entry called `name`; throws InputError listing the known names.
const IntegratorEntry& integrator_entry(const std::string& name);

/// The names, for --integrator's check when the command line is parsed.
std::vector<std::string> integrator_name_list();

/// One line per integrator, name and description (the footer of `rayscout render --help`).
std::string integrator_help();

/// Whether any integrator reads `option` of the `reads` lists (the options some integrators ignore).
bool read_by_some_integrators(const std::string& option);

}  // namespace rayscout::cli
