// The rayscout CLI's subcommands; each file cmd_<name>.cpp adds one.
#pragma once

#include <CLI/CLI.hpp>

namespace rayscout::cli {

void add_accelerators_command(CLI::App& app);

}  // namespace rayscout::cli
