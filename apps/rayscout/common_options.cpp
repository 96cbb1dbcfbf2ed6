// Options several commands share, added by one function each so that their names, checks and
// help texts agree between commands.
#include <string>
#include <vector>

#include <fmt/core.h>

#include "commands.h"
#include "rayscout/accelerators.h"

namespace rayscout::cli {

CLI::Validator file_path() {
  return CLI::Validator(
      [](const std::string& text) { return text.empty() ? std::string("an empty path names no file") : std::string(); },
      "");
}

CLI::Validator output_file_path() {
  return CLI::Validator(
      [](const std::string& text) {
        if (text == "-") return std::string("'-' is not standard output here: name a file (./- for one called '-')");
        return file_path()(text);
      },
      "");
}

void add_scene_option(CLI::App& cmd, std::string& scene, bool required) {
  const std::string help = "a .json scene file (docs/scene-format.md), a mesh (.obj, .ply, .gltf, .glb) or cornell, "
                           "the built-in Cornell box";
  auto* option = cmd.add_option("--scene", scene, help + (required ? "" : " (the default)"))
                     ->check(file_path());
  if (required) option->required();
}

void add_accel_options(CLI::App& cmd, std::string& accel, const std::string& use,
                       std::vector<std::string>* accel_opts) {
  std::string names;
  for (const auto& a : accelerators()) names += (names.empty() ? "" : ", ") + a.name;
  // Checked when parsed, as --integrator is: a misspelt name is a usage error naming the option
  // and the help (it said only "unknown accelerator 'bvh4'", once the command ran).
  const CLI::Validator known(
      [](const std::string& name) {
        try {
          check_accelerator(name);
          return std::string();
        } catch (const InputError& e) {
          return std::string(e.what());
        }
      },
      "");
  cmd.add_option("--accel", accel, "accelerator " + use + ": " + names + " (`rayscout accelerators` describes them)")
      ->capture_default_str()
      ->check(known);
  if (accel_opts)
    cmd.add_option("--accel-opt", *accel_opts,
                   "accelerator tunable key=value, repeatable (`rayscout accelerators` names them or their doc)");
}

AcceleratorOptions checked_accel_options(const std::string& accel, const std::vector<std::string>& accel_opts) {
  check_accelerator(accel);  // an unknown name is --accel's error (checked when parsed)
  try {
    AcceleratorOptions options = AcceleratorOptions::from_list(accel_opts);
    check_accelerator(accel, options);
    return options;
  } catch (const InputError& e) {
    // The accelerator's message names the key ("option 'bins': 300 is not in [2, 256]"); the
    // command-line option and the accelerator it was given to are named here.
    const std::string what = e.what();
    throw InputError("--accel-opt: " + (what.starts_with("accelerator '") ? "" : "accelerator '" + accel + "': ") +
                     what);
  }
}

void print_scene_warnings(const Scene& scene) {
  for (const auto& w : scene.warnings) fmt::print(stderr, "rayscout: warning: {}\n", printable(w));
}

void add_threads_option(CLI::App& cmd, int& threads) {
  add_number(cmd, "--threads", threads, "worker threads (0 = all cores)", 0);
}

}  // namespace rayscout::cli
