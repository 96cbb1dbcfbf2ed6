// `rayscout rays`: writes a workload's ray set (primary, shadow, ao, diffuse) to a RAYS file.
#include <array>
#include <memory>
#include <string>

#include <fmt/core.h>

#include "commands.h"
#include "progress_line.h"
#include "rayscout/accelerators.h"
#include "rayscout/core/machine_memory.h"
#include "rayscout/core/output_path.h"
#include "rayscout/core/ray_file.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/render/workloads.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout::cli {
namespace {

struct RaysArgs {
  std::string scene, workload = "primary", out, accel = kDefaultAccelerator;
  WorkloadConfig config;
};

// The rays are held twice, as the batch and as the encoded file: at least 64 bytes per camera
// ray, 112 measured for the secondary workloads (primary rays, hits and the new rays). Asked
// for more than the machine's memory and swap, the kernel killed the process mid-run (--width
// 2147483647 --height 1: 24 GB used, then SIGKILL) instead of an error; refused here, before
// the scene is loaded. The shadow workload has a ray per point light and hit: checked again
// once the scene is loaded (64 lights at 4096 x 4096 x 2 asked for ~140 GB).
void check_memory(const WorkloadConfig& c, Workload workload, size_t rays_per_hit = 1) {
  const double rays = double(c.width) * double(c.height) * double(c.spp);
  // Primary: the batch and the file, 32 bytes each. Secondary: ~48 for the primary ray, hit
  // and path state of each pixel sample, and 64 for each new ray (batch and file).
  const double per_ray = workload == Workload::Primary ? 64.0 : 48.0 + 64.0 * double(rays_per_hit);
  require_memory(per_ray * rays, fmt::format("--width {} x --height {} x --spp {} = {:.0f} rays ({:.0f} bytes a ray{}) need",
                                             c.width, c.height, c.spp, rays, per_ray,
                                             rays_per_hit > 1 ? fmt::format(", {} shadow rays each", rays_per_hit) : ""));
}

void run_rays(const RaysArgs& a) {
  const Workload workload = parse_workload(a.workload);
  check_output_path(a.out, "--out " + a.out);
  check_distinct_files(std::array{NamedFile{a.out, "--out " + a.out}},
                       std::array{NamedFile{a.scene, "the input --scene " + a.scene}});
  check_memory(a.config, workload);
  check_accelerator(a.accel);
  const auto start = SteadyClock::now();
  ProgressLine progress;
  progress.draw("rays: loading the scene");
  const Scene scene = resolve_scene(a.scene);
  progress.end();
  print_scene_warnings(scene);
  if (workload == Workload::Shadow && scene.point_lights.size() > 1)
    check_memory(a.config, workload, scene.point_lights.size());
  // Secondary workloads start at the primary hits, found with this accelerator. Primary rays
  // need no tracing: brute force, which builds nothing, stands in for a build never used.
  const bool traces = workload != Workload::Primary;
  if (traces) progress.draw(fmt::format("rays: building {} over {} triangles", a.accel, scene.triangles.size()));
  const auto accel = make_accelerator(traces ? a.accel : "brute", scene);
  progress.draw(fmt::format("rays: making the {} rays of {}x{} pixels at {} spp", workload_name(workload),
                            a.config.width, a.config.height, a.config.spp));
  const RayBatch rays = make_workload(scene, *accel, workload, a.config);
  progress.draw(fmt::format("rays: writing {} rays", rays.size()));
  write_rays(a.out, rays);
  progress.end();
  if (rays.empty())
    fmt::print(stderr, "rayscout: warning: no {} rays: every primary ray missed the scene (where does the camera look?)\n",
               workload_name(workload));
  fmt::print("wrote {} {} rays ({}x{}, {} spp, seed {}) to {} in {:.0f} ms\n", rays.size(), workload_name(workload),
             a.config.width, a.config.height, a.config.spp, a.config.seed, printable(a.out), ms_since(start));
}

CommandRegistration registration{[](CLI::App& app) {
  auto args = std::make_shared<RaysArgs>();
  auto* cmd = app.add_subcommand("rays", "Write a workload's rays to a RAYS file (for trace and other tracers)");
  set_memory_hint(*cmd, "lower --width, --height or --spp, or load a smaller scene");
  add_scene_option(*cmd, args->scene, /*required=*/true);
  cmd->add_option("--workload", args->workload, "secondary rays (shadow, ao, diffuse) start at primary hits; "
                                                "pixels whose primary ray missed are left out")
      ->capture_default_str()
      ->check(CLI::IsMember(workload_names()));
  add_number(*cmd, "--width", args->config.width, "image width in pixels", 1);
  add_number(*cmd, "--height", args->config.height, "image height in pixels", 1);
  add_number(*cmd, "--spp", args->config.spp, "camera samples per pixel", 1);
  add_number(*cmd, "--seed", args->config.seed, "random seed", 0);
  add_number(*cmd, "--ao-radius", args->config.ao_radius, "ao: ray length (0 = 10% of the scene diagonal)", 0.0f);
  add_accel_options(*cmd, args->accel, "that finds the primary hits");
  cmd->add_option("--out", args->out, "output RAYS file")->required()->check(output_file_path());
  cmd->callback([args, cmd] {
    if (cmd->count("--ao-radius") > 0 && args->workload != "ao")
      fmt::print(stderr, "rayscout: warning: --ao-radius is ignored by --workload {}\n", args->workload);
    if (cmd->count("--accel") > 0 && args->workload == "primary")
      fmt::print(stderr, "rayscout: warning: --accel is ignored by --workload primary (its rays need no tracing)\n");
    run_rays(*args);
  });
}};

}  // namespace
}  // namespace rayscout::cli
