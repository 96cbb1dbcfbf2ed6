// `rayscout accelerators`: lists the accelerators of this build.
#include <fmt/core.h>

#include "commands.h"
#include "rayscout/accelerators.h"

namespace rayscout::cli {
namespace {

CommandRegistration registration{[](CLI::App& app) {
  auto* cmd = app.add_subcommand("accelerators", "List the accelerators of this build");
  cmd->callback([] {
    for (const auto& a : accelerators()) fmt::print("{:<12} {}\n", a.name, a.description);
  });
}};

}  // namespace
}  // namespace rayscout::cli
