// rayscout: the command-line front end. Parses options, wires modules, prints results.
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "commands.h"
#include "rayscout/core/input_error.h"

namespace rayscout::cli {
std::vector<AddCommand>& command_registry() {
  static std::vector<AddCommand> commands;
  return commands;
}
}  // namespace rayscout::cli

int main(int argc, char** argv) {
  CLI::App app{"rayscout: a ray tracing engine that looks at the rays before tracing them"};
  app.set_version_flag("--version", "rayscout " RAYSCOUT_VERSION);
  app.require_subcommand(1);
  for (const auto& add : rayscout::cli::command_registry()) add(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // a command's own verdict, e.g. compare-hits above tolerance: 1
  } catch (const CLI::ParseError& e) {
    // An option before the command, or a mistyped command: CLI11 would only say that a
    // subcommand is required.
    if (const std::string first = argc > 1 ? argv[1] : ""; first.starts_with("-") && first != "-h" &&
                                                           first != "--help" && first != "--version") {
      fmt::print(stderr, "rayscout: error: unknown option '{}' (options follow the command: rayscout <command> --help)\n",
                 first);
      return 2;
    }
    if (argc > 1 && argv[1][0] != '-') {
      std::string names;
      bool known = false;
      for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
        names += (names.empty() ? "" : ", ") + sub->get_name();
        known |= sub->get_name() == argv[1];
      }
      if (!known) {
        fmt::print(stderr, "rayscout: error: unknown command '{}' (commands: {}; see --help)\n", argv[1], names);
        return 2;
      }
    }
    // --help and --version exit 0; every command-line mistake is a usage error, exit 2 like
    // bad input files (CLI11's own codes, 100-120, would tell a caller nothing more).
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const rayscout::InputError& e) {
    fmt::print(stderr, "rayscout: error: {}\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "rayscout: error: out of memory (lower --width/--height, --spp, --light-samples, --ao-samples "
                       "or --vpls, bound the camera batch with --max-batch (not manylight), or load a smaller scene)\n");
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayscout: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
