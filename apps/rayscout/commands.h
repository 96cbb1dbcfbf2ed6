// The rayscout CLI's subcommands. Each cmd_<name>.cpp registers one with a static
// CommandRegistration, so adding a command never edits main.cpp.
#pragma once

#include <functional>
#include <vector>

#include <CLI/CLI.hpp>

namespace rayscout::cli {

/// Adds one subcommand (with its callback) to the app.
using AddCommand = std::function<void(CLI::App&)>;

/// Every registered subcommand, in registration order.
std::vector<AddCommand>& command_registry();

/// `static CommandRegistration reg{[](CLI::App& app) { ... }};` in a cmd_*.cpp file.
struct CommandRegistration {
  explicit CommandRegistration(AddCommand add) { command_registry().push_back(std::move(add)); }
};

}  // namespace rayscout::cli
