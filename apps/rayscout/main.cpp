// rayscout: the command-line front end. Parses options, wires modules, prints results.
#include <cstdio>
#include <exception>
#include <map>
#include <new>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "commands.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/output_path.h"

namespace rayscout::cli {
std::vector<AddCommand>& command_registry() {
  static std::vector<AddCommand> commands;
  return commands;
}

namespace {
std::map<const CLI::App*, std::string>& memory_hints() {
  static std::map<const CLI::App*, std::string> hints;
  return hints;
}
}  // namespace

void set_memory_hint(const CLI::App& cmd, std::string hint) { memory_hints()[&cmd] = std::move(hint); }

std::string memory_hint(const CLI::App& cmd) {
  const auto it = memory_hints().find(&cmd);
  return it == memory_hints().end() ? std::string() : it->second;
}
}  // namespace rayscout::cli

int main(int argc, char** argv) {
  rayscout::remove_temporaries_on_signals();  // Ctrl-C during a write leaves no hidden .tmp file
  CLI::App app{"rayscout: a ray tracing engine that looks at the rays before tracing them"};
  app.set_version_flag("--version", "rayscout " RAYSCOUT_VERSION);
  app.require_subcommand(1);
  // CLI11's usage errors read as rayscout's own, and point at the command's --help. Every error
  // is printed through printable(): it quotes file names and arguments (a name holding
  // ESC [ 2 J cleared the terminal), and escaping twice changes nothing.
  app.failure_message([](const CLI::App* top, const CLI::Error& e) {
    std::string command = "rayscout";
    for (const CLI::App* sub : top->get_subcommands()) command += " " + sub->get_name();
    return fmt::format("rayscout: error: {}\nRun '{} --help' for the options.\n", rayscout::printable(e.what()),
                       command);
  });
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
                 rayscout::printable(first));
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
        fmt::print(stderr, "rayscout: error: unknown command '{}' (commands: {}; see --help)\n",
                   rayscout::printable(argv[1]), names);
        return 2;
      }
    }
    // --help and --version exit 0; every command-line mistake is a usage error, exit 2 like
    // bad input files (CLI11's own codes, 100-120, would tell a caller nothing more).
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const rayscout::InputError& e) {
    fmt::print(stderr, "rayscout: error: {}\n", rayscout::printable(e.what()));
    return 2;
  } catch (const std::bad_alloc&) {
    std::string hint;  // the command's own options, not another command's
    for (const CLI::App* sub : app.get_subcommands()) hint = rayscout::cli::memory_hint(*sub);
    fmt::print(stderr, "rayscout: error: out of memory{}\n", hint.empty() ? "" : " (" + hint + ")");
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayscout: error: {}\n", rayscout::printable(e.what()));
    return 1;
  }
  return 0;
}
