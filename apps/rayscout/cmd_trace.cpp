// `rayscout trace`: traces a ray file with one accelerator and prints one JSON line of timings.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "progress_line.h"
#include "thread_limit.h"
#include "rayscout/accelerators.h"
#include "rayscout/core/median.h"
#include "rayscout/core/output_path.h"
#include "rayscout/core/ray_file.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout::cli {
namespace {

struct TraceArgs {
  std::string scene, rays, accel = kDefaultAccelerator, out;
  bool occluded = false, count = false;
  int threads = 0, repeat = 5;
  std::vector<std::string> accel_opts;
};

// x rounded to 3 decimals (milliseconds to the microsecond) for the JSON line.
double round3(double x) { return std::round(x * 1e3) / 1e3; }

void run_trace(const TraceArgs& a) {
  const ThreadLimit limit(a.threads);
  const int threads = limit.threads;

  if (!a.out.empty()) check_output_path(a.out, "--out " + a.out);
  check_distinct_files(std::array{NamedFile{a.out, "--out " + a.out}},
                       std::array{NamedFile{a.scene, "the input --scene " + a.scene},
                                  NamedFile{a.rays, "the input --rays " + a.rays}});
  const AcceleratorOptions options = checked_accel_options(a.accel, a.accel_opts);
  // A slow accelerator on a big ray file takes minutes per run.
  ProgressLine progress;
  progress.draw("trace: loading the scene");
  const Scene scene = resolve_scene(a.scene);
  progress.end();
  print_scene_warnings(scene);
  progress.draw("trace: loading the rays");
  const RayBatch rays = read_rays(a.rays);
  progress.draw(fmt::format("trace: building {} over {} triangles", a.accel, scene.triangles.size()));
  const auto accel = make_accelerator(a.accel, scene, options);
  const BuildInfo build = accel->build_info();
  const std::string built = fmt::format("trace: built in {:.2f} s; {} rays: ", build.build_ms * 1e-3, rays.size());

  HitBatch hits;
  std::vector<uint8_t> occ;
  auto trace_once = [&](TraceStats* stats) {
    if (a.occluded) accel->occluded(rays, occ, stats);
    else accel->intersect(rays, hits, stats);
  };
  progress.draw(built + "warm-up run");
  trace_once(nullptr);  // warm-up: page in the structure and the rays
  std::vector<double> times;
  for (int r = 0; r < a.repeat; ++r) {
    progress.draw(built + fmt::format("run {}/{}", r + 1, a.repeat) +
                  (times.empty() ? "" : fmt::format(", the last took {:.1f} ms", times.back())));
    const auto start = SteadyClock::now();
    trace_once(nullptr);
    times.push_back(ms_since(start));
  }
  const double trace_ms = median(times);
  size_t positives = 0;
  if (a.occluded) for (uint8_t o : occ) positives += o != 0;
  else for (uint32_t p : hits.prim) positives += p != kInvalidId;
  if (!a.out.empty()) {
    if (a.occluded) write_occlusion(a.out, occ);
    else write_hits(a.out, hits);
  }

  nlohmann::ordered_json line;
  line["accel"] = a.accel;
  line["query"] = a.occluded ? "occluded" : "intersect";
  line["rays"] = rays.size();
  line[a.occluded ? "occluded" : "hits"] = positives;
  line["threads"] = threads;
  line["build_ms"] = round3(build.build_ms);
  line["trace_ms"] = round3(trace_ms);
  line["trace_ms_min"] = round3(*std::min_element(times.begin(), times.end()));
  line["repeat"] = a.repeat;
  line["mrays_per_s"] = round3(mrays_per_s(rays.size(), trace_ms));
  line["memory_bytes"] = build.memory_bytes;
  if (accel->last_trace_memory_bytes() > 0) line["trace_memory_bytes"] = accel->last_trace_memory_bytes();
  if (a.count) {
    // A separate run: counting must never slow the timed runs.
    TraceStats stats;
    progress.draw(built + "counting run");
    trace_once(&stats);
    if (!accel->counts_work()) {
      line["counters"] = nullptr;
      line["counters_note"] = accel->name() + " has no work counters";
    } else {
      auto per_ray = [&](uint64_t n) { return rays.empty() ? 0.0 : round3(double(n) / double(rays.size())); };
      line["counters"] = {{"rays", stats.rays},
                          {"traversal_steps", stats.traversal_steps},
                          {"ray_box_tests", stats.ray_box_tests},
                          {"ray_tri_tests", stats.ray_tri_tests},
                          {"box_tests_per_ray", per_ray(stats.ray_box_tests)},
                          {"tri_tests_per_ray", per_ray(stats.ray_tri_tests)}};
    }
  }
  progress.end();
  fmt::print("{}\n", line.dump());
}

CommandRegistration registration{[](CLI::App& app) {
  auto args = std::make_shared<TraceArgs>();
  auto* cmd = app.add_subcommand("trace", "Trace a ray file; print one JSON line of build and trace times");
  set_memory_hint(*cmd, "trace fewer rays (a smaller --rays file), another --accel, or load a smaller scene");
  add_scene_option(*cmd, args->scene, /*required=*/true);
  cmd->add_option("--rays", args->rays, "RAYS file (rayscout rays writes one)")->required()->check(file_path());
  add_accel_options(*cmd, args->accel, "to trace with", &args->accel_opts);
  cmd->add_flag("--occluded", args->occluded, "any-hit queries (shadow rays) instead of closest hits");
  add_threads_option(*cmd, args->threads);
  add_number(*cmd, "--repeat", args->repeat, "timed repetitions after one warm-up; trace_ms is their median", 1);
  cmd->add_flag("--count", args->count, "add exact work counters (from a separate, untimed run)");
  cmd->add_option("--out", args->out, "write the hits (HITS file, or OCCL with --occluded)")->check(output_file_path());
  cmd->callback([args] { run_trace(*args); });
}};

}  // namespace
}  // namespace rayscout::cli
