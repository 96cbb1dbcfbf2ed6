// The rayscout CLI's subcommands. Each cmd_<name>.cpp registers one with a static
// CommandRegistration, so adding a command never edits main.cpp; options several commands
// share are added by one function each (common_options.cpp).
#pragma once

#include <charconv>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <CLI/CLI.hpp>

#include "rayscout/core/accelerator_options.h"
#include "rayscout/core/input_error.h"
#include "rayscout/scene/scene.h"

namespace rayscout::cli {

/// Adds one subcommand (with its callback) to the app.
using AddCommand = std::function<void(CLI::App&)>;

/// Every registered subcommand, in registration order.
std::vector<AddCommand>& command_registry();

/// `static CommandRegistration reg{[](CLI::App& app) { ... }};` in a cmd_*.cpp file.
struct CommandRegistration {
  explicit CommandRegistration(AddCommand add) { command_registry().push_back(std::move(add)); }
};

/// What to lower when `cmd` runs out of memory (std::bad_alloc), e.g. "lower --width";
/// main prints it with the error.
void set_memory_hint(const CLI::App& cmd, std::string hint);
/// The hint set for `cmd`, or "".
std::string memory_hint(const CLI::App& cmd);

/// --scene. `required` for commands without a default scene; the others load the built-in
/// Cornell box when it is left out (resolve_scene("")).
void add_scene_option(CLI::App& cmd, std::string& scene, bool required);

/// --accel (what the command uses it for: `use`, e.g. "to trace with") and, when accel_opts
/// is given, --accel-opt. The help lists the accelerators of this build.
void add_accel_options(CLI::App& cmd, std::string& accel, const std::string& use,
                       std::vector<std::string>* accel_opts = nullptr);

/// The parsed --accel-opt list, once --accel and it are checked (check_accelerator): commands
/// call it before they read a scene or ray file, so that a misspelt name or key costs nothing.
/// An error of the list names --accel-opt and the accelerator.
AcceleratorOptions checked_accel_options(const std::string& accel, const std::vector<std::string>& accel_opts);

/// The scene loader's warnings (a material library not found, triangles dropped, ...) on
/// stderr, one "rayscout: warning:" line each: what every command that loads a scene prints
/// once it is loaded (info lists them instead).
void print_scene_warnings(const Scene& scene);

/// --threads (0 = all cores; see ThreadLimit).
void add_threads_option(CLI::App& cmd, int& threads);

/// Use with ->check(file_path()) on every option that names a file: an empty value is refused,
/// where it would otherwise read as the option left out (--scene "" rendered the built-in
/// Cornell box, --stats "" wrote nothing).
CLI::Validator file_path();

/// file_path() for an output that cannot go to stdout (an image, a ray file, a log): "-" is
/// refused too, where it would write a file called '-' (rays and trace print their summary on
/// stdout; only render's --stats takes "-" for stdout).
CLI::Validator output_file_path();

/// Use with ->transform(in_range(lo, hi)): the option's value must be a number in [lo, hi]
/// (hi omitted: >= lo, finite; an integer for an integral T). Unlike CLI::Range it rejects NaN
/// and infinity, reads integers as decimal (CLI11 alone reads "010" as 8) and rejects "-1" for
/// an unsigned option (CLI11 alone wraps it). The help shows the range; an error names the
/// option and the value.
template <typename T>
CLI::Validator in_range(T lo, T hi = std::numeric_limits<T>::max()) {
  const bool open = hi == std::numeric_limits<T>::max();
  const std::string range = open ? ">= " + CLI::detail::to_string(lo)
                                 : "in [" + CLI::detail::to_string(lo) + ", " + CLI::detail::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        T value{};
        bool ok;
        if constexpr (std::is_integral_v<T>) {
          auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
          ok = ec == std::errc() && end == text.data() + text.size();
          if (ok) text = std::to_string(value);  // what CLI11 converts next: decimal, no leading zeros
        } else {
          ok = CLI::detail::lexical_cast(text, value) && std::isfinite(value);
        }
        if (ok && value >= lo && value <= hi) return {};
        // "'1e3' is not a number" would puzzle: it is one, but not the integer this option takes.
        return "'" + text + "' is not " + (std::is_integral_v<T> ? "an integer " : "a number ") + range;
      },
      open ? "min " + CLI::detail::to_string(lo) : range);  // help: "INT:min 1=4" (4 is the default)
}

/// Adds option `name` holding a number in [lo, hi] (in_range; hi omitted: >= lo), its default
/// (value's initial value) shown in --help: what every numeric option with a default repeated.
template <typename T>
CLI::Option* add_number(CLI::App& cmd, const std::string& name, T& value, const std::string& help,
                        std::type_identity_t<T> lo, std::type_identity_t<T> hi = std::numeric_limits<T>::max()) {
  return cmd.add_option(name, value, help)->capture_default_str()->transform(in_range<T>(lo, hi));
}

}  // namespace rayscout::cli
