// The integrators `rayscout render --integrator` knows, by name.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rayscout/render/renderer.h"

namespace rayscout::cli {

/// One integrator of the CLI: its name, a line of help and a factory.
struct IntegratorEntry {
  std::string name;
  std::string description;
  std::function<std::unique_ptr<Integrator>()> make;
};

/// Every integrator, in the order `rayscout render --help` lists them.
const std::vector<IntegratorEntry>& integrator_table();

/// The integrator called `name`; throws InputError listing the known names.
std::unique_ptr<Integrator> make_integrator(const std::string& name);

/// The names, comma-separated (for help texts).
std::string integrator_names();

/// The names, for --integrator's check when the command line is parsed.
std::vector<std::string> integrator_name_list();

/// One line per integrator, name and description (the footer of `rayscout render --help`).
std::string integrator_help();

}  // namespace rayscout::cli
