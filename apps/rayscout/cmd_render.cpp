// `rayscout render`: renders a scene with an integrator on an accelerator and writes the image.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "progress_line.h"
#include "integrators.h"
#include "manylight_options.h"
#include "thread_limit.h"
#include "rayscout/accelerators.h"
#include "rayscout/core/file_extension.h"
#include "rayscout/core/machine_memory.h"
#include "rayscout/core/output_path.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/image/image.h"
#include "rayscout/manylight/visibility_cluster.h"
#include "rayscout/render/renderer.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::string integrator = "direct";
  std::string accel = kDefaultAccelerator;
  std::vector<std::string> accel_opts;
  int threads = 0;
  std::string out = "rayscout.png";
  std::string stats;
  RenderConfig config;
};

// The text of the progress line after every traced batch. The time left is extrapolated
// from whole passes, a pass being done when the next one starts or its last possible bounce
// is traced (manylight reports each pass once, done): the bounces of a pass take unequal
// times (bounce 0 is most of the work, and bounce max_depth is reached only through mirrors),
// so the bar's share of a pass per bounce is no clock.
class ProgressBar {
 public:
  std::string text(const RenderProgress& p) {
    if (p.pass != pass_) record_done(p.pass, p.elapsed_s);
    if (p.bounce >= p.max_depth) record_done(p.pass + 1, p.elapsed_s);
    pass_ = p.pass;
    // In doubles: --max-depth may be INT_MAX.
    const double done = (double(p.pass) + (double(p.bounce) + 1) / (double(p.max_depth) + 1)) / double(p.passes);
    const int width = 24, filled = std::clamp(int(done * width + 0.5), 0, width);
    const std::string bounce = p.max_depth > 0 ? fmt::format(" bounce {}/{}", p.bounce, p.max_depth) : "";
    const std::string left =
        done_passes_ > 0
            ? fmt::format("  ~{:.1f} s left", std::max(0.0, done_at_s_ / done_passes_ * p.passes - p.elapsed_s))
            : "";
    return fmt::format("[{}{}] pass {}/{}{}  {:.2f} Mrays traced  {:.1f} s{}", std::string(filled, '#'),
                       std::string(width - filled, '.'), p.pass + 1, p.passes, bounce, double(p.rays_traced) * 1e-6,
                       p.elapsed_s, left);
  }

 private:
  void record_done(int passes, double at_s) {
    done_passes_ = passes;
    done_at_s_ = at_s;
  }
  int pass_ = 0;
  int done_passes_ = 0;    // passes known to be done, ...
  double done_at_s_ = 0;  // ... at this time
};

// Film and image hold 12 bytes a pixel each, a pass ~200 bytes a camera ray and ~100 bytes for
// each occlusion ray a camera ray's hit sends in the same batch (the integrator's
// occlusion_rays_per_hit; the rays to point lights are known after the scene load, when this
// is checked again; measured 72-96); an integrator may add memory of its own (manylight:
// manylight_memory). A 32768 x 32768 image asked for ~26 GB on a 23 GB machine, and
// `--ao-samples 64` at 1024 x 1024 x 4 for ~26 GB: the kernel killed the process after the
// scene load. Refused here, before any work.
void check_memory(const RenderConfig& c, const IntegratorEntry& integrator, size_t point_lights = 0) {
  const double pixels = double(c.width) * double(c.height);
  const double pass_rays = std::min(pixels * double(c.spp), double(c.camera_batch_limit()));
  const double fan_out = integrator.occlusion_rays_per_hit(c, point_lights);
  const IntegratorMemory own = integrator.own_memory ? integrator.own_memory(c) : IntegratorMemory{};
  require_memory(24.0 * pixels + (200.0 + 100.0 * fan_out) * pass_rays + own.bytes,
                 fmt::format("--width {} x --height {} ({:.0f} pixels at 24 bytes for film and image, {:.0f} camera rays "
                             "a pass (--max-batch) at ~200 bytes{}{}) need",
                             c.width, c.height, pixels, pass_rays,
                             fan_out >= 1 ? fmt::format(" with {:.0f} occlusion rays each at ~100 bytes{}", fan_out,
                                                       point_lights > 0 ? fmt::format(" ({} to point lights)", point_lights) : "")
                                          : "",
                             own.explained));
}

// What can be checked before the scene load: output paths (before the work, not after it),
// memory, and the manylight run's files.
void check_before_work(const RenderOptions& o, const IntegratorEntry& integrator) {
  const ManylightRunOptions& ml = manylight_cli_options();
  const bool manylight = integrator.option_group == &kManylightOptions;  // its files
  check_image_path(o.out, o.config.width, o.config.height, "--out " + o.out);
  if (!o.stats.empty() && o.stats != "-") check_output_path(o.stats, "--stats " + o.stats);
  check_memory(o.config, integrator);
  o.config.validate();
  if (manylight) {
    if (!ml.skip_image.empty())
      check_image_path(ml.skip_image, o.config.width, o.config.height, "--skip-image " + ml.skip_image);
    if (!ml.rmse_log.empty()) {
      if (!rmse_log_format(ml.rmse_log))
        throw InputError("--rmse-log " + ml.rmse_log + ": the file name must end in .json or .csv");
      check_output_path(ml.rmse_log, "--rmse-log " + ml.rmse_log);
    }
    if (!ml.reference.empty()) {
      // An 8-bit sRGB PNG is clamped: an RMSE against it would be of another image.
      if (const std::string ext = lower_extension(ml.reference); ext != ".exr" && ext != ".pfm")
        throw InputError("--reference " + ml.reference + ": must be an .exr or .pfm image (a PNG is clamped 8-bit sRGB, "
                         "no reference for RMSE)");
      std::error_code ec;
      if (!std::filesystem::is_regular_file(ml.reference, ec))
        throw InputError("--reference " + ml.reference + ": no such file");
      // Read here too (the integrator reads it again), so that a reference of another size or
      // a broken file is found before the scene load and the build, not after them.
      if (const Image ref = read_image(ml.reference); ref.width != o.config.width || ref.height != o.config.height)
        throw InputError(fmt::format("--reference {}: {}x{} but rendering {}x{}", ml.reference, ref.width, ref.height,
                                     o.config.width, o.config.height));
    }
  }
  const NamedFile outputs[] = {{o.out, "--out " + o.out},
                               {o.stats, "--stats " + o.stats},
                               {manylight ? ml.skip_image : "", "--skip-image " + ml.skip_image},
                               {manylight ? ml.rmse_log : "", "--rmse-log " + ml.rmse_log}};
  const NamedFile inputs[] = {{o.scene, "the input --scene " + o.scene},
                              {manylight ? ml.reference : "", "the input --reference " + ml.reference}};
  check_distinct_files(outputs, inputs);
}

// What needs the scene: the memory of the shadow rays to its point lights, and settings that
// would give a silently wrong image (warnings).
void check_after_load(const RenderOptions& o, const IntegratorEntry& integrator, const Scene& scene) {
  print_scene_warnings(scene);
  if (!scene.point_lights.empty())  // a shadow ray per point light and hit
    check_memory(o.config, integrator, scene.point_lights.size());
  if (o.config.ray_epsilon > 0 && std::ranges::find(integrator.reads, "--ray-epsilon") != integrator.reads.end()) {
    const float size = length(scene.bounds().diagonal());
    if (o.config.ray_epsilon > 0.01f * size)
      fmt::print(stderr,
                 "rayscout: warning: --ray-epsilon {} is {:.0f} % of the scene's diagonal: rays leave surfaces that far "
                 "off them, past nearby walls and contact shadows\n",
                 o.config.ray_epsilon, 100.0 * o.config.ray_epsilon / size);
  }
  if (!integrator.thin_lens && scene.camera.lens_radius > 0)
    fmt::print(stderr,
               "rayscout: warning: --integrator {} renders through a pinhole: the camera's lens_radius {} "
               "(depth of field) is ignored\n",
               integrator.name, scene.camera.lens_radius);
  if (integrator.point_lights_only && scene.point_lights.empty())
    fmt::print(stderr,
               "rayscout: warning: --integrator {} lights with point lights only, and the scene has none "
               "(its {} emissive triangles light --integrator area, path or manylight): the image will be black "
               "but for the emitters seen directly or in mirrors\n",
               integrator.name, scene.emissive_triangles.size());
}

// Radiance beyond the float range (a light near 3e38) must not pass for a bright image.
void warn_if_not_finite(const Image& image) {
  size_t nonfinite = 0;
  for (const Vec3& p : image.pixels) nonfinite += !is_finite(p);
  if (nonfinite > 0)
    fmt::print(stderr, "rayscout: warning: {} of {} pixels are not finite (inf or NaN): radiance beyond the float "
               "range; lower the scene's light intensities or emission\n", nonfinite, image.pixels.size());
}

// --stats: the renderer's stats, what was rendered and how, and the load and build times.
void write_stats(const RenderOptions& o, const RenderStats& stats, const Scene& scene, const Integrator& integrator,
                 const Accelerator& accel, int n_threads, double load_ms, double build_ms) {
  nlohmann::json j = nlohmann::json::parse(stats.to_json());
  j["scene"] = o.scene.empty() ? "cornell" : o.scene;
  j["integrator"] = integrator.name();
  j["accel"] = accel.name();
  j["threads"] = n_threads;
  j["width"] = o.config.width;
  j["height"] = o.config.height;
  j["spp"] = o.config.spp;
  j["seed"] = o.config.seed;
  if (const auto& pass_seed = manylight_cli_options().pass_seed; integrator_entry(o.integrator).option_group == &kManylightOptions && pass_seed)
    j["pass_seed"] = *pass_seed;
  j["triangles"] = scene.triangles.size();
  j["load_ms"] = load_ms;
  j["build_ms"] = build_ms;
  j["accel_memory_bytes"] = accel.build_info().memory_bytes;
  if (o.config.count && !accel.counts_work()) {  // as trace writes it: no zeros posing as counts
    j["counters"] = nullptr;
    j["counters_note"] = accel.name() + " has no work counters";
  }
  // A scene path need not be UTF-8 (a Latin-1 file name): its bytes become U+FFFD instead of
  // the JSON library's exception after the image was written.
  const std::string text = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (o.stats == "-") fmt::print("{}\n", text);
  else write_file(o.stats, text + "\n", "--stats");
}

// What was written, where the time went and, with --count, the work per ray.
void print_summary(const RenderOptions& o, const RenderStats& stats, const Integrator& integrator,
                   const Accelerator& accel, int n_threads, double load_ms, double build_ms) {
  // With --stats - stdout carries only the JSON, so that it can be piped into a parser.
  std::FILE* const summary = o.stats == "-" ? stderr : stdout;
  fmt::print(summary, "wrote {} ({}x{}, {} spp, integrator {}, accel {}, {} threads)\n", printable(o.out),
             o.config.width, o.config.height, o.config.spp, integrator.name(), accel.name(), n_threads);
  // Integrators that do not time their batches (manylight) report no tracing share.
  const std::string tracing =
      stats.rays() == 0 ? std::string()
                        : fmt::format(" ({:.3f} s tracing {} rays, {:.2f} Mrays/s)", stats.trace_ms * 1e-3,
                                      stats.rays(), stats.mrays_per_s());
  fmt::print(summary, "time: {:.3f} s render{}, {:.3f} s scene load, {:.3f} s build\n", stats.total_ms * 1e-3,
             tracing, load_ms * 1e-3, build_ms * 1e-3);
  if (const TraceStats w = stats.counters(); w.rays > 0)
    fmt::print(summary,
               "work: {} rays, per ray {:.2f} traversal steps, {:.2f} ray-box tests, {:.2f} ray-triangle tests\n",
               w.rays, double(w.traversal_steps) / double(w.rays), double(w.ray_box_tests) / double(w.rays),
               double(w.ray_tri_tests) / double(w.rays));
}

void run(const RenderOptions& o) {
  const ThreadLimit limit(o.threads);
  const int n_threads = limit.threads;
  const IntegratorEntry& entry = integrator_entry(o.integrator);
  check_before_work(o, entry);
  const auto integrator = entry.make();
  const AcceleratorOptions accel_options = checked_accel_options(o.accel, o.accel_opts);

  // The progress line is cleared before each warning, so that a warning starts its line.
  ProgressLine progress;
  progress.draw("render: loading the scene");
  auto t = SteadyClock::now();
  const Scene scene = resolve_scene(o.scene);
  const double load_ms = ms_since(t);
  progress.end();
  check_after_load(o, entry, scene);
  progress.draw(fmt::format("render: building {} over {} triangles", o.accel, scene.triangles.size()));
  t = SteadyClock::now();
  const auto accel = make_accelerator(o.accel, scene, accel_options);
  const double build_ms = ms_since(t);
  progress.end();

  if (o.config.count && !accel->counts_work())
    fmt::print(stderr, "rayscout: warning: --count: {} has no work counters (none are printed or written to --stats)\n",
               accel->name());
  RenderConfig config = o.config;
  config.count = o.config.count && accel->counts_work();
  progress.draw(entry.first_progress);
  if (progress.on())
    config.on_progress = [&progress, bar = std::make_shared<ProgressBar>()](const RenderProgress& p) {
      progress.draw(bar->text(p));
    };
  RenderStats stats;
  const Image image = integrator->render(scene, *accel, config, &stats);
  progress.end();
  write_image(image, o.out);
  warn_if_not_finite(image);
  print_summary(o, stats, *integrator, *accel, n_threads, load_ms, build_ms);
  if (!o.stats.empty()) write_stats(o, stats, scene, *integrator, *accel, n_threads, load_ms, build_ms);
}

void add_render_options(CLI::App& cmd, RenderOptions& o) {
  RenderConfig& c = o.config;
  add_scene_option(cmd, o.scene, /*required=*/false);
  // Checked when parsed: a misspelt name is a usage error naming the option.
  cmd.add_option("--integrator", o.integrator, "integrator (listed below)")
      ->capture_default_str()
      ->check(CLI::IsMember(integrator_name_list()));
  cmd.footer(integrator_help());
  add_accel_options(cmd, o.accel, "to render with", &o.accel_opts);
  add_number(cmd, "--width", c.width, "image width in pixels", 1, 1 << 15);
  add_number(cmd, "--height", c.height, "image height in pixels", 1, 1 << 15);
  add_number(cmd, "--spp", c.spp, "camera samples per pixel (width x height x spp below 2^32)", 1, 1 << 16);
  add_number(cmd, "--seed", c.seed,
             "random seed (same seed and --max-batch, same image: another batch size can move the last bits of a "
             "pixel sum; manylight's skipping modes also need --costs and no --time-budget)", 0);
  add_number(cmd, "--max-depth", c.max_depth, "path: bounces; direct/area: mirror reflections", 0);
  add_number(cmd, "--rr-depth", c.rr_depth,
             "path: Russian roulette after this many bounces (pbrt-v3's 3; >= max-depth - 1 = never)", 0);
  add_number(cmd, "--light-samples", c.light_samples, "area/path: shadow rays to area lights per hit", 1);
  add_number(cmd, "--ao-samples", c.ao_samples, "ao: rays per hit", 1);
  add_number(cmd, "--ao-radius", c.ao_radius, "ao: ray length (0 = 10% of the scene diagonal)", 0.0f);
  add_number(cmd, "--ray-epsilon", c.ray_epsilon,
             "offset of rays leaving a surface, along its normal (0 = 1e-5 x the larger of the scene's diagonal "
             "and its largest coordinate)", 0.0f);
  add_number(cmd, "--max-batch", c.max_batch_rays,
             "camera rays per pass, which bounds memory (~200-400 bytes a ray): the samples per pixel are traced "
             "in passes of whole samples that stay under this; an image with more pixels is traced in bands of "
             "rows, one sample per pass (0 = 2^24)", 0L);
  add_threads_option(cmd, o.threads);
  cmd.add_flag("--count", c.count, "count traversal steps and box/triangle tests (slower); printed, and in --stats");
  cmd.add_option("--stats", o.stats,
                 "write JSON stats to this file ('-' = stdout, which then holds only the JSON: the summary lines go to "
                 "stderr)")->check(file_path());
  cmd.add_option("--out", o.out, "output image: .png, .exr or .pfm")->capture_default_str()->check(output_file_path());
}

// An option the chosen integrator does not read is reported, not dropped silently: the
// options some integrators read (IntegratorEntry::reads), in the order of --help, and the
// option groups of the others.
void warn_unread_options(const CLI::App& cmd, const IntegratorEntry& integrator) {
  for (const CLI::Option* option : cmd.get_options()) {
    const std::string name = option->get_name();
    if (option->count() > 0 && read_by_some_integrators(name) &&
        std::ranges::find(integrator.reads, name) == integrator.reads.end())
      fmt::print(stderr, "rayscout: warning: {} is ignored by --integrator {}\n", name, integrator.name);
  }
  for (const auto& e : integrator_table()) {
    if (!e.option_group) continue;
    const CLI::App& group = *cmd.get_option_group(e.name);
    if (&e == &integrator) e.option_group->warn_unread(group);
    else if (group.count_all() > 0)
      fmt::print(stderr, "rayscout: warning: the {} options given are ignored by --integrator {}\n", e.name,
                 integrator.name);
  }
}

CommandRegistration registration{[](CLI::App& app) {
  auto opts = std::make_shared<RenderOptions>();
  auto* cmd = app.add_subcommand("render", "Render a scene to an image (PNG, EXR or PFM)");
  add_render_options(*cmd, *opts);
  set_memory_hint(*cmd, "lower --width/--height, --spp, --light-samples, --ao-samples or --vpls, bound the camera "
                        "batch with --max-batch (not manylight), or load a smaller scene");
  // Integrator-specific options: one option group per integrator that has its own (a warning
  // names them when another integrator is chosen).
  for (const auto& e : integrator_table())
    if (e.option_group) e.option_group->add(*cmd->add_option_group(e.name, "Options of --integrator " + e.name));
  cmd->callback([opts, cmd] {
    warn_unread_options(*cmd, integrator_entry(opts->integrator));
    run(*opts);
  });
}};

}  // namespace
}  // namespace rayscout::cli
