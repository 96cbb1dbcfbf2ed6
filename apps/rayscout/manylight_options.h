// Options of `rayscout render --integrator manylight` (VPLs, visibility mode, time budget, RMSE
// log): cmd_render.cpp adds them to its option group, integrators.cpp builds the integrator.
#pragma once

#include <memory>

#include <CLI/CLI.hpp>

#include "integrators.h"
#include "rayscout/manylight/manylight_integrator.h"

namespace rayscout::cli {

/// Adds the manylight options to `rayscout render` (through kManylightOptions).
void add_manylight_options(CLI::App& cmd);

/// The manylight options as parsed (width, height, spp and seed come from RenderConfig).
const ManylightRunOptions& manylight_cli_options();

/// Warns (stderr) about options of `group` (the one add_manylight_options filled) that the
/// parsed run does not read, an --rmse-log with no RMSE to log, and --costs under which
/// skipping saves nothing.
void warn_unread_manylight_options(const CLI::App& group);

/// The option group of the integrator table's entry "manylight".
extern const IntegratorOptionGroup kManylightOptions;

/// The memory of the parsed manylight run at c's size (VPLs, cluster pairs, a round's samples,
/// the shading points), for render's memory check.
IntegratorMemory manylight_memory(const RenderConfig& c);

/// The integrator of the table entry "manylight", configured by the parsed options; warns
/// (stderr) about a biased configuration (epsilon_bias_warning).
std::unique_ptr<Integrator> make_manylight_cli_integrator();

}  // namespace rayscout::cli
