// The integrator table of the CLI: add an integrator with one line in integrator_table().
#include "integrators.h"

#include <functional>

#include <fmt/core.h>

#include "rayscout/core/input_error.h"
#include "manylight_options.h"

namespace rayscout::cli {
namespace {

/// One integrator of the CLI: its name, a line of help and a factory.
struct IntegratorEntry {
  std::string name;
  std::string description;
  std::function<std::unique_ptr<Integrator>()> make;
};

/// Every integrator, in the order `rayscout render --help` lists them.
const std::vector<IntegratorEntry>& integrator_table() {
  static const std::vector<IntegratorEntry> table = {
      {"direct", "point lights + mirror reflections (papers' Sibenik (a), (b))", [] { return make_direct_integrator(); }},
      {"area", "direct + --light-samples shadow rays to area lights per hit (Sibenik (c))", [] { return make_area_integrator(); }},
      {"ao", "ambient occlusion: --ao-samples rays of length --ao-radius per hit", [] { return make_ao_integrator(); }},
      {"path", "path tracing, --max-depth bounces, next-event estimation with MIS for area lights", [] { return make_path_integrator(); }},
      {"manylight", "VPLs + VisibilityCluster + probabilistic visibility (--vpls, --visibility, --time-budget; docs/manylight.md)", [] { return make_manylight_cli_integrator(); }},
      // New integrators: one line each above this comment.
  };
  return table;
}

/// The names, comma-separated (for the error message).
std::string integrator_names() {
  std::string names;
  for (const auto& e : integrator_table()) names += (names.empty() ? "" : ", ") + e.name;
  return names;
}

}  // namespace

std::unique_ptr<Integrator> make_integrator(const std::string& name) {
  for (const auto& e : integrator_table())
    if (e.name == name) return e.make();
  throw InputError("unknown integrator '" + name + "' (known: " + integrator_names() + ")");
}

std::string integrator_help() {
  std::string help = "Integrators (--integrator):";
  for (const auto& e : integrator_table()) help += fmt::format("\n  {:<11} {}", e.name, e.description);
  return help + "\nAll but manylight render the camera's thin lens (lens_radius, focus_distance: depth of field).";
}

std::vector<std::string> integrator_name_list() {
  std::vector<std::string> names;
  for (const auto& e : integrator_table()) names.push_back(e.name);
  return names;
}

}  // namespace rayscout::cli
