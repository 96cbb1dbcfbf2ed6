// `rayscout info --scene S`: what a scene holds (triangles, bounds, materials, lights, warnings, load time).
#include <string>
#include <vector>

#include <fmt/core.h>

#include "commands.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout::cli {
namespace {

const char* type_name(Material::Type t) {
  switch (t) {
    case Material::Type::Diffuse: return "diffuse";
    case Material::Type::Mirror: return "mirror";
    case Material::Type::Glossy: return "glossy";
  }
  return "?";
}

std::string vec(const Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x, v.y, v.z); }

void print_info(const std::string& arg) {
  const auto start = SteadyClock::now();
  const Scene scene = resolve_scene(arg);
  const double load_ms = ms_since(start);

  const Bounds3 b = scene.bounds();
  fmt::print("scene:        {}\n", arg.empty() ? "cornell (built-in)" : printable(arg));
  fmt::print("load time:    {:.1f} ms\n", load_ms);
  fmt::print("triangles:    {}\n", scene.triangles.size());
  fmt::print("bounds:       min {} max {}\n", vec(b.lo), vec(b.hi));
  const Camera& c = scene.camera;
  fmt::print("camera:       eye {} look_at {} up {} fov_deg {:.6g} lens_radius {:.6g} focus_distance {:.6g}\n",
             vec(c.eye), vec(c.look_at), vec(c.up), c.fov_deg, c.lens_radius, c.focus_distance);

  std::vector<size_t> uses(scene.materials.size(), 0);
  for (uint32_t m : scene.material_ids) ++uses[m];
  fmt::print("materials:    {}\n", scene.materials.size());
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& m = scene.materials[i];
    fmt::print("  {:<24} {:<8} {:>9} tris  diffuse {}", printable(m.name), type_name(m.type), uses[i], vec(m.diffuse));
    if (m.type != Material::Type::Diffuse) fmt::print("  specular {}", vec(m.specular));
    if (m.type == Material::Type::Glossy) fmt::print("  exponent {:.6g}", m.exponent);
    if (m.emissive()) fmt::print("  emission {}", vec(m.emission));
    fmt::print("\n");
  }

  double emissive_area = 0;
  for (uint32_t t : scene.emissive_triangles) emissive_area += scene.triangles[t].area();
  fmt::print("lights:       {} point, {} emissive triangles (area {:.6g})\n", scene.point_lights.size(),
             scene.emissive_triangles.size(), emissive_area);
  for (const auto& l : scene.point_lights)
    fmt::print("  point at {} intensity {}\n", vec(l.position), vec(l.intensity));
  fmt::print("warnings:     {}\n", scene.warnings.size());
  for (const auto& w : scene.warnings) fmt::print("  {}\n", w);
}

CommandRegistration registration{[](CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Load a scene and print its triangles, bounds, materials, lights and load time");
  auto scene = std::make_shared<std::string>();
  set_memory_hint(*cmd, "load a smaller scene");
  add_scene_option(*cmd, *scene, /*required=*/false);
  cmd->callback([scene] { print_info(*scene); });
}};

}  // namespace
}  // namespace rayscout::cli
