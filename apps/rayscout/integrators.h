// The integrators `rayscout render --integrator` knows, by name.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "rayscout/render/renderer.h"

namespace rayscout::cli {

/// The integrator called `name`; throws InputError listing the known names.
std::unique_ptr<Integrator> make_integrator(const std::string& name);

/// The names, for --integrator's check when the command line is parsed.
std::vector<std::string> integrator_name_list();

/// One line per integrator, name and description (the footer of `rayscout render --help`).
std::string integrator_help();

}  // namespace rayscout::cli
