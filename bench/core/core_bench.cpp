// core_bench: Mrays/s of bvh2, bvh and embree side by side, plus build times.
//
// For every scene, thread count and workload: one warm-up trace per accelerator, then
// `repeat` rounds in which every accelerator traces the same rays once (interleaved, so load
// drift on a shared machine hits all alike); the median of the rounds is reported. Builds are
// timed the same way. Work counters come from a separate, untimed run.
#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <tbb/global_control.h>

#include "bench_support.h"
#include "rayscout/accelerators.h"
#include "rayscout/bvh/bvh_accelerators.h"
#include "rayscout/core/scenes_dir.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/render/workloads.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

/// One accelerator column: registry name plus options ("embree" with robust=off is Embree's fastest mode).
using Column = bench::ColumnSpec;

std::unique_ptr<Accelerator> build(const Column& c, const Scene& scene) {
  return make_accelerator(c.accel, scene, AcceleratorOptions::from_list(c.options));
}

// --cpu-time: time traces by process CPU time instead of the wall clock.
bench::Clock g_clock = bench::Clock::Wall;

struct Options {
  std::vector<std::string> scenes;
  std::vector<std::string> workloads = {"primary", "shadow", "ao", "diffuse"};
  std::vector<int> threads = {1, 2};
  int width = 1024, height = 1024, repeat = 5, build_repeat = 3;
  bool embree_variants = true;  ///< also Embree robust=off and packet=16 columns
  bool bvh2 = true;             ///< the bvh2 column
  std::vector<std::string> extra;  ///< extra columns "label:accel[:key=value,...]" (bench::parse_column)
};

/// Prints the tree shape of a wide BVH column and its exact counters on one ray set (stderr).
void print_extra_counters(const Column& column, const Accelerator& accel, const bench::RaySet& set) {
  TraceStats st;
  bench::trace(accel, set, &st);
  const double n = double(std::max<size_t>(1, set.rays.size()));
  if (const auto* wa = dynamic_cast<const WideBvhAccelerator*>(&accel)) {
    const WideBvh& wb = wa->bvh();
    size_t slots = 0, leaves = 0, leaf_tris = 0;
    for (const WideNode& nd : wb.nodes) {
      slots += nd.count;
      for (uint32_t k = 0; k < nd.count; ++k)
        if (WideRef::is_leaf(nd.child[k])) {
          ++leaves;
          leaf_tris += WideRef::leaf_count(nd.child[k]);
        }
    }
    fmt::print(stderr, "    {} tree: {} nodes, {:.2f} children/node, {} leaves, {:.2f} tris/leaf, {} blocks\n", column.label,
               wb.nodes.size(), double(slots) / double(wb.nodes.size()), leaves, double(leaf_tris) / double(leaves),
               wb.leaf_blocks.size());
  }
  fmt::print(stderr, "    {} counters: {:.1f} nodes, {:.1f} boxes, {:.2f} tris per ray; {:.1f} MB\n", column.label,
             st.traversal_steps / n, st.ray_box_tests / n, st.ray_tri_tests / n, accel.build_info().memory_bytes / 1048576.0);
}

/// One run: the columns, and the three tables filled row by row, printed at the end.
class CoreBench {
 public:
  explicit CoreBench(const Options& opt) : opt_(opt) {
    // Columns 0..2 are bvh2, bvh, embree (the ratios use them); a left-out bvh2 is not timed.
    columns_ = {{"bvh2", "bvh2", {}}, {"bvh", "bvh", {}}, {"embree", "embree", {}}};
    if (opt.embree_variants) {
      columns_.push_back({"embree-fast", "embree", {"robust=off"}});
      columns_.push_back({"embree-p16", "embree", {"packet=16"}});
    }
    for (const auto& e : opt.extra) columns_.push_back(bench::parse_column("--column", e));
  }

  int run() {
    // Before any scene loads: an unknown accelerator (embree in a build without it) or option.
    for (size_t k = 0; k < columns_.size(); ++k) {
      auto check = [&] { check_accelerator(columns_[k].accel, AcceleratorOptions::from_list(columns_[k].options)); };
      if (k < first_extra()) check();
      else bench::check_argument("--column", opt_.extra[k - first_extra()], check);
    }
    bench::check_names("--workload", opt_.workloads, workload_names());  // before any scene loads
    start_tables();
    for (const std::string& scene_arg : opt_.scenes) run_scene(scene_arg);
    fmt::print("# machine: {}\n\n", bench::machine_description());
    fmt::print("### Trace throughput (median of {} interleaved repetitions after a warm-up, {}x{}, {}; "
               "the ratios are of Mrays/s, above 1 when the first is faster)\n\n{}\n", opt_.repeat,
               opt_.width, opt_.height, bench::clock_name(g_clock), trace_table_);
    fmt::print("### Build time (median of {} interleaved builds, wall clock; the ratio is of times, above 1 when bvh "
               "builds slower) and memory\n\n{}\n", opt_.build_repeat, build_table_);
    fmt::print("### Work counters (exact, separate untimed run; Embree has none)\n\n{}", counter_table_);
    return 0;
  }

 private:
  bool timed(size_t c) const { return c != 0 || opt_.bvh2; }
  /// "shadow (any hit)": the query a row's counts and times are of.
  static std::string workload_label(const bench::RaySet& set) { return set.kind + (set.occlusion ? " (any hit)" : ""); }
  /// The first extra column (after bvh2, bvh, embree and the Embree variants).
  size_t first_extra() const { return opt_.embree_variants ? 5 : 3; }

  void start_tables() {
    trace_table_ += "| scene | workload | rays | threads |";
    for (const auto& c : columns_) trace_table_ += fmt::format(" {} Mrays/s |", c.label);
    trace_table_ += " bvh/embree | bvh/best embree | bvh2/embree |\n|---|---|---:|---:|";
    for (size_t i = 0; i < columns_.size() + 3; ++i) trace_table_ += "---:|";
    trace_table_ += "\n";
    build_table_ = "| scene | triangles | threads |";
    for (const auto& c : columns_) build_table_ += fmt::format(" {} build ms |", c.label);
    build_table_ += " bvh/embree build time | bvh MB | embree MB |\n|---|---:|---:|";
    for (size_t i = 0; i < columns_.size() + 3; ++i) build_table_ += "---:|";
    build_table_ += "\n";
    counter_table_ = "| scene | workload | bvh2 nodes/ray | bvh2 boxes/ray | bvh2 tris/ray | bvh nodes/ray | bvh boxes/ray | bvh tris/ray |\n"
                     "|---|---|---:|---:|---:|---:|---:|---:|\n";
  }

  void run_scene(const std::string& scene_arg) {
    const std::string scene_name = std::filesystem::path(scene_arg).stem().string();
    const auto load_start = SteadyClock::now();
    const std::optional<Scene> loaded = bench::load_or_skip("--scene", scene_arg, scene_name);
    if (!loaded) return;
    const Scene& scene = *loaded;
    fmt::print(stderr, "{}: {} triangles loaded in {:.0f} ms\n", scene_name, scene.triangles.size(), ms_since(load_start));

    // Ray sets are made once (with all threads) and shared by every column and thread count.
    std::map<std::string, bench::RaySet> ray_sets;
    {
      const auto gen = make_accelerator("bvh", scene);
      for (const auto& w : opt_.workloads)
        ray_sets[w] = {w, 0, is_any_hit(parse_workload(w)),
                       make_workload(scene, *gen, parse_workload(w), {.width = opt_.width, .height = opt_.height})};
    }
    for (int threads : opt_.threads) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
      const auto accels = build_all(scene, scene_name, threads);
      for (const auto& w : opt_.workloads) {
        time_row(accels, ray_sets[w], scene_name, threads);
        if (threads == opt_.threads.back()) count_row(accels, ray_sets[w], scene_name);
      }
    }
  }

  /// Builds every column with interleaved repetitions; a row of the build table (median of
  /// the reported build_ms).
  std::vector<std::unique_ptr<Accelerator>> build_all(const Scene& scene, const std::string& scene_name, int threads) {
    std::vector<std::unique_ptr<Accelerator>> accels(columns_.size());
    const std::vector<double> build_med =
        bench::interleaved_medians(columns_.size(), {.count = opt_.build_repeat, .warm_up = false}, [&](size_t c) {
          if (!timed(c)) return 0.0;
          accels[c] = build(columns_[c], scene);
          return accels[c]->build_info().build_ms;
        });
    build_table_ += fmt::format("| {} | {} | {} |", scene_name, scene.triangles.size(), threads);
    for (double b : build_med) build_table_ += fmt::format(" {:.0f} |", b);
    build_table_ += fmt::format(" {:.2f} | {:.1f} | {:.1f} |\n", build_med[1] / build_med[2],
                                accels[1]->build_info().memory_bytes / 1048576.0,
                                accels[2]->build_info().memory_bytes / 1048576.0);
    fmt::print(stderr, "  {} threads: builds done\n", threads);
    return accels;
  }

  /// A row of the trace table: a warm-up, then repeat rounds of every column once.
  void time_row(const std::vector<std::unique_ptr<Accelerator>>& accels, const bench::RaySet& set,
                const std::string& scene_name, int threads) {
    const std::vector<double> ms = bench::interleaved_medians(columns_.size(), {.count = opt_.repeat}, [&](size_t c) {
      return timed(c) ? bench::trace_ms(g_clock, *accels[c], set) : 0.0;
    });
    std::vector<double> mrays;
    for (size_t c = 0; c < columns_.size(); ++c) mrays.push_back(timed(c) ? mrays_per_s(set.rays.size(), ms[c]) : 0.0);
    trace_table_ += fmt::format("| {} | {} | {} | {} |", scene_name, workload_label(set), set.rays.size(), threads);
    for (double m : mrays) trace_table_ += fmt::format(" {:.2f} |", m);
    double best = 0;
    for (size_t c = 0; c < columns_.size(); ++c)
      if (columns_[c].accel == "embree") best = std::max(best, mrays[c]);
    trace_table_ += fmt::format(" **{:.2f}** | {:.2f} | {:.2f} |\n", mrays[1] / mrays[2], mrays[1] / best, mrays[0] / mrays[2]);
    fmt::print(stderr, "  {} {} threads: bvh {:.2f}, embree {:.2f} Mrays/s", set.kind, threads, mrays[1], mrays[2]);
    for (size_t c = first_extra(); c < columns_.size(); ++c)
      fmt::print(stderr, ", {} {:.2f} ({:.3f}x embree)", columns_[c].label, mrays[c], mrays[c] / mrays[2]);
    fmt::print(stderr, "\n");
  }

  /// A row of the counter table (bvh2, bvh), plus the counters of extra bvh columns (stderr).
  void count_row(const std::vector<std::unique_ptr<Accelerator>>& accels, const bench::RaySet& set,
                 const std::string& scene_name) {
    TraceStats s2, sw;
    if (opt_.bvh2) bench::trace(*accels[0], set, &s2);
    bench::trace(*accels[1], set, &sw);
    for (size_t c = first_extra(); c < columns_.size(); ++c)
      if (columns_[c].accel == "bvh") print_extra_counters(columns_[c], *accels[c], set);
    const double n = double(std::max<size_t>(1, set.rays.size()));
    counter_table_ += fmt::format("| {} | {} | {:.1f} | {:.1f} | {:.2f} | {:.1f} | {:.1f} | {:.2f} |\n", scene_name,
                                  workload_label(set),
                                  s2.traversal_steps / n, s2.ray_box_tests / n, s2.ray_tri_tests / n,
                                  sw.traversal_steps / n, sw.ray_box_tests / n, sw.ray_tri_tests / n);
  }

  const Options& opt_;
  std::vector<Column> columns_;
  std::string trace_table_, build_table_, counter_table_;
};

}  // namespace
}  // namespace rayscout

int main(int argc, char** argv) {
  rayscout::Options opt;
  const std::string dir = std::string(RAYSCOUT_SOURCE_DIR) + "/bench/scenes/";
  opt.scenes = {dir + "sponza.json", dir + "sibenik-a.json", dir + "conference.json"};
  CLI::App app{
      "core_bench: bvh2, bvh and embree side by side. Per scene, thread count and workload: one untimed warm-up "
      "trace per column, then --repeat rounds of every column tracing the same rays once (interleaved); each column's median over "
      "the rounds is printed, in Mrays/s of wall-clock time (--cpu-time: process CPU time). Builds: --build-repeat "
      "interleaved rounds, median of each accelerator's own wall-clock build time. Work counts: one untimed trace "
      "at the last thread count."};
  app.add_option("--scene", opt.scenes, "Scene or mesh files, or cornell for the built-in box (repeatable)")->capture_default_str();
  app.add_option("--workload", opt.workloads, "primary, shadow, ao, diffuse (repeatable or comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--threads", opt.threads, "Thread counts (repeatable or comma-separated)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  app.add_option("--width", opt.width)->capture_default_str()->check(CLI::Range(1, 32768));
  app.add_option("--height", opt.height)->capture_default_str()->check(CLI::Range(1, 32768));
  app.add_option("--repeat", opt.repeat, "Timed repetitions per row (median)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  app.add_option("--build-repeat", opt.build_repeat, "Builds per accelerator (median)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  bool no_variants = false;
  app.add_flag("--no-embree-variants", no_variants, "Leave out the embree robust=off and packet=16 columns");
  bool no_bvh2 = false;
  app.add_flag("--no-bvh2", no_bvh2, "Skip bvh2: no build or trace (its columns print 0)");
  app.add_option("--column", opt.extra,
                 "Extra column label:accel[:key=value,...] (repeatable), e.g. bvh-p1:bvh:presplit=0.1; an embree column "
                 "counts in 'best embree', a bvh column's tree shape and counters go to stderr");
  bool cpu_time = false;
  app.add_flag("--cpu-time", cpu_time,
               "Time traces by process CPU time (all threads summed; for 1 thread on a loaded machine)");
  CLI11_PARSE(app, argc, argv);
  if (cpu_time) rayscout::g_clock = rayscout::bench::Clock::ProcessCpu;
  opt.embree_variants = !no_variants;
  opt.bvh2 = !no_bvh2;
  return rayscout::bench::run_bench("core_bench", [&] { return rayscout::CoreBench(opt).run(); });
}
