// Options of `rayscout render --integrator manylight` (VPLs, visibility mode, time budget, RMSE
// log): cmd_render.cpp adds them to its option group, integrators.cpp builds the integrator.
#pragma once

#include <memory>

#include <CLI/CLI.hpp>

#include "rayscout/manylight/manylight_integrator.h"

namespace rayscout::cli {

/// Adds the manylight options to `rayscout render` (called from cmd_render.cpp's hook).
void add_manylight_options(CLI::App& cmd);

/// The manylight options as parsed (width, height, spp and seed come from RenderConfig).
const ManylightRunOptions& manylight_cli_options();

/// Warns (stderr) about options of `group` (the one add_manylight_options filled) that the
/// parsed run does not read, an --rmse-log with no RMSE to log, and --costs under which
/// skipping saves nothing.
void warn_unread_manylight_options(const CLI::App& group);

/// The integrator of the table entry "manylight", configured by the parsed options; warns
/// (stderr) about a biased configuration (epsilon_bias_warning).
std::unique_ptr<Integrator> make_manylight_cli_integrator();

}  // namespace rayscout::cli
