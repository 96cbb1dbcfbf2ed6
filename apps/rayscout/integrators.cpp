// The integrator table of the CLI: add an integrator with one entry in integrator_table().
#include "integrators.h"

#include <algorithm>

#include <fmt/core.h>

#include "rayscout/core/input_error.h"
#include "manylight_options.h"

namespace rayscout::cli {
namespace {

// The wavefront integrators offset rays by --ray-epsilon and trace camera batches of
// --max-batch rays, with work counters; the many-light renderer offsets by its own 1e-4 of
// the scene diagonal, makes its own batches and keeps no traversal counters.
const std::vector<std::string> kWavefront = {"--ray-epsilon", "--max-batch", "--count"};

std::vector<std::string> reads(std::vector<std::string> own, const std::vector<std::string>& shared) {
  own.insert(own.end(), shared.begin(), shared.end());
  return own;
}

// Shadow rays of a hit: one per point light (direct, area, path) and --light-samples to area
// lights (area, path).
double to_point_lights(const RenderConfig&, size_t point_lights) { return double(point_lights); }
double to_all_lights(const RenderConfig& c, size_t point_lights) { return double(c.light_samples) + double(point_lights); }

}  // namespace

const std::vector<IntegratorEntry>& integrator_table() {
  static const std::vector<IntegratorEntry> table = {
      {.name = "direct",
       .description = "point lights + mirror reflections (papers' Sibenik (a), (b))",
       .reads = reads({"--max-depth"}, kWavefront),
       .point_lights_only = true,
       .occlusion_rays_per_hit = to_point_lights,
       .make = [] { return make_direct_integrator(); }},
      {.name = "area",
       .description = "direct + --light-samples shadow rays to area lights per hit (Sibenik (c))",
       .reads = reads({"--max-depth", "--light-samples"}, kWavefront),
       .occlusion_rays_per_hit = to_all_lights,
       .make = [] { return make_area_integrator(); }},
      {.name = "ao",
       .description = "ambient occlusion: --ao-samples rays of length --ao-radius per hit",
       .reads = reads({"--ao-samples", "--ao-radius"}, kWavefront),
       .occlusion_rays_per_hit = [](const RenderConfig& c, size_t) { return double(c.ao_samples); },
       .make = [] { return make_ao_integrator(); }},
      {.name = "path",
       .description = "path tracing, --max-depth bounces, next-event estimation with MIS for area lights",
       .reads = reads({"--max-depth", "--rr-depth", "--light-samples"}, kWavefront),
       .occlusion_rays_per_hit = to_all_lights,
       .make = [] { return make_path_integrator(); }},
      {.name = "manylight",
       .description = "VPLs + VisibilityCluster + probabilistic visibility (--vpls, --visibility, --time-budget; "
                      "docs/manylight.md)",
       .option_group = &kManylightOptions,
       .thin_lens = false,
       .occlusion_rays_per_hit = [](const RenderConfig&, size_t) { return 0.0; },
       .own_memory = manylight_memory,
       .first_progress = "render: manylight preprocess (VPLs, clusters, their visibility) and calibration",
       .make = [] { return make_manylight_cli_integrator(); }},
      // New integrators: one entry each above this comment.
  };
  return table;
}

const IntegratorEntry& integrator_entry(const std::string& name) {
  for (const auto& e : integrator_table())
    if (e.name == name) return e;
  std::string names;
  for (const auto& e : integrator_table()) names += (names.empty() ? "" : ", ") + e.name;
  throw InputError("unknown integrator '" + name + "' (known: " + names + ")");
}

std::string integrator_help() {
  std::string help = "Integrators (--integrator):";
  for (const auto& e : integrator_table()) help += fmt::format("\n  {:<11} {}", e.name, e.description);
  std::string pinholes;
  for (const auto& e : integrator_table())
    if (!e.thin_lens) pinholes += (pinholes.empty() ? "" : ", ") + e.name;
  return help + "\nAll" + (pinholes.empty() ? "" : " but " + pinholes) +
         " render the camera's thin lens (lens_radius, focus_distance: depth of field).";
}

std::vector<std::string> integrator_name_list() {
  std::vector<std::string> names;
  for (const auto& e : integrator_table()) names.push_back(e.name);
  return names;
}

bool read_by_some_integrators(const std::string& option) {
  return std::ranges::any_of(integrator_table(), [&](const IntegratorEntry& e) {
    return std::ranges::find(e.reads, option) != e.reads.end();
  });
}

}  // namespace rayscout::cli
