// shafts_bench: traversal steps and time of ray classification vs plain traversal of the same
// BVH, per scene and workload, side by side in one run; plus a memory/direction sweep (CSV).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <tbb/global_control.h>

#include "bench_support.h"
#include "rayscout/accelerators.h"
#include "rayscout/core/scenes_dir.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/render/renderer.h"
#include "rayscout/render/workloads.h"
#include "rayscout/scene/load_scene.h"
#include "rayscout/shafts/shafts_accelerator.h"

using namespace rayscout;
using bench::Clock;
using bench::median;
using bench::RaySet;

namespace {

std::vector<RaySet> make_ray_sets(const Scene& scene, const Accelerator& accel, int width, int height,
                                  const std::vector<std::string>& wanted) {
  std::vector<RaySet> sets;
  WorkloadConfig wc;
  wc.width = width;
  wc.height = height;
  auto want = [&](const std::string& n) { return std::find(wanted.begin(), wanted.end(), n) != wanted.end(); };
  for (Workload w : {Workload::Primary, Workload::Shadow, Workload::Ao, Workload::Diffuse}) {
    if (!want(workload_name(w))) continue;
    sets.push_back({workload_name(w), 0, is_any_hit(w), make_workload(scene, accel, w, wc)});
  }
  if (want("path")) {
    // Path-tracing bounces 1..3 (closest hit), recorded from a low-resolution render.
    RaySet path{"path", 0, false, {}};
    RenderConfig rc;
    rc.width = std::max(1, width / 2);
    rc.height = std::max(1, height / 2);
    rc.spp = 1;
    rc.max_depth = 3;
    rc.on_batch = [&](const BatchInfo& info, const RayBatch& rays) {
      if (info.kind != "path" || info.occlusion || info.bounce < 1) return;
      for (size_t i = 0; i < rays.size(); ++i) path.rays.push_back(rays[i]);
    };
    make_path_integrator()->render(scene, accel, rc);
    sets.push_back(std::move(path));
  }
  return sets;
}

/// The calling thread's CPU time with one thread (TBB then runs inline), else the wall clock.
Clock g_clock = Clock::Wall;

double now_ms() { return bench::now_ms(g_clock); }

struct Measure {
  TraceStats with, without;
  double ms_with = 0, ms_without = 0;
  double ms_lookup = 0;  ///< classification + lookup of every ray, no traversal
};

Measure measure(const ShaftsAccelerator& acc, const RaySet& set, int reps) {
  Measure m;
  HitBatch hits;
  std::vector<uint8_t> occ;
  auto run = [&](bool lists, TraceStats* st) {
    const double t0 = now_ms();
    if (set.occlusion) acc.occluded(set.rays, occ, st, lists);
    else acc.intersect(set.rays, hits, st, lists);
    return now_ms() - t0;
  };
  run(true, &m.with);
  run(false, &m.without);
  // Plain (0) and shafts (1), the order alternated so neither side always runs on a warmer cache.
  const std::vector<double> ms =
      bench::interleaved_medians(2, {.count = reps, .alternate = true}, [&](size_t k) { return run(k == 1, nullptr); });
  m.ms_without = ms[0];
  m.ms_with = ms[1];
  // Classification + lookup alone (what every listed ray pays before its traversal), after an
  // untimed pass as every timed column: the first pass would pay for the caches the traces left.
  size_t sink = 0;
  auto lookup_all = [&](size_t) {
    const double t0 = now_ms();
    for (size_t i = 0; i < set.rays.size(); ++i) {
      const Candidates c = acc.collection().lookup(set.rays[i]);
      sink += c.list.size() + (c.list.empty() ? 0 : c.list[0]);
    }
    return now_ms() - t0;
  };
  const double lookup_ms = bench::interleaved_medians(1, {.count = reps}, lookup_all)[0];
  m.ms_lookup = lookup_ms + double(sink & 1) * 1e-12;  // sink read after the passes: they are not dead code
  return m;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

struct Options {
  std::string scenes;
  std::string workloads = "primary,shadow,ao,diffuse,path";
  std::string bases = "binary,wide";
  std::vector<std::string> accel_opts;  // key=value
  int width = 512, height = 384, reps = 5, threads = 1, build_reps = 1;
  bool sweep = false;
  std::string csv;
  std::string profile_side;  // "", "plain" or "lists"
};

/// A scene argument: a path as given, else a bench view by name, else a file under
/// $RAYSCOUT_SCENES; nothing when it is found nowhere.
std::optional<std::filesystem::path> resolve_scene(const std::string& s, const std::string& bench_dir) {
  const std::filesystem::path path = s, view = std::filesystem::path(bench_dir) / (s + ".json");
  if (std::filesystem::exists(path)) return path;
  if (std::filesystem::exists(view)) return view;
  return find_scene_file(s);
}

/// One collection to measure: over which BVH, and the sweep's value (-1 = the option's).
struct Variant {
  std::string base;
  double budget_rel;
  int dir_res;
};

/// Build times on the trace clock: the BVH alone, then BVH + collection, alternated
/// build_reps times (medians; the collection's = total - BVH of that rep).
struct Built {
  std::unique_ptr<ShaftsAccelerator> acc;
  size_t reps = 0;
  double bvh_ms = 0, collection_ms = 0;
};

Built build_alternated(const Scene& scene, ShaftsAccelerator::Base base, const ShaftConfig& cfg,
                       const BvhBuildConfig& bvh_cfg, int build_reps) {
  std::vector<double> bvh_times, col_times;
  Built b;
  for (int r = 0; r < build_reps; ++r) {
    double t = now_ms();
    if (base == ShaftsAccelerator::Base::Wide) (void)WideBvh::build(scene.triangles, bvh_cfg);
    else (void)Bvh2::build(scene.triangles, bvh_cfg);
    const double bvh_ms = now_ms() - t;
    b.acc.reset();
    t = now_ms();
    b.acc = std::make_unique<ShaftsAccelerator>(scene, base, cfg, bvh_cfg);
    const double all_ms = now_ms() - t;
    bvh_times.push_back(bvh_ms);
    col_times.push_back(all_ms - bvh_ms);
  }
  b.reps = bvh_times.size();
  b.bvh_ms = median(bvh_times);
  b.collection_ms = median(col_times);
  return b;
}

/// --profile-side: only one side, reps times per ray set (for perf stat).
void profile(const ShaftsAccelerator& acc, const std::vector<RaySet>& sets, const Options& o) {
  const bool lists = o.profile_side == "lists";
  for (const RaySet& set : sets) {
    HitBatch hits;
    std::vector<uint8_t> occ;
    const double t0 = now_ms();
    for (int r = 0; r < o.reps; ++r) {
      if (set.occlusion) acc.occluded(set.rays, occ, nullptr, lists);
      else acc.intersect(set.rays, hits, nullptr, lists);
    }
    fmt::print("{} {}: {:.2f} ms per pass\n", set.label(), o.profile_side, (now_ms() - t0) / o.reps);
  }
}

/// The table of one collection: steps, tests and time with and without the lists, per ray set.
void compare(const ShaftsAccelerator& acc, const std::vector<RaySet>& sets, const Options& o,
             const std::function<void(const RaySet&, const Measure&)>& csv_row) {
  fmt::print("| workload | rays | steps/ray plain | steps/ray shafts | steps saved | box tests/ray plain / shafts "
             "| tri tests/ray plain / shafts | ms plain | ms shafts | speedup | lookup ns/ray |\n");
  fmt::print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  double saved_sum = 0.0, log_speedup_sum = 0.0;
  for (const RaySet& set : sets) {
    const Measure m = measure(acc, set, o.reps);
    const double n = double(std::max<size_t>(1, set.rays.size()));
    const double saved = 1.0 - double(m.with.traversal_steps) / double(std::max<uint64_t>(1, m.without.traversal_steps));
    saved_sum += saved;
    log_speedup_sum += std::log(m.ms_without / m.ms_with);
    fmt::print("| {} | {} | {:.2f} | {:.2f} | {:.1f} % | {:.1f} / {:.1f} | {:.1f} / {:.1f} | {:.2f} | {:.2f} | {:.2f}x | {:.1f} |\n",
               set.label(), set.rays.size(), m.without.traversal_steps / n, m.with.traversal_steps / n, 100.0 * saved,
               m.without.ray_box_tests / n, m.with.ray_box_tests / n, m.without.ray_tri_tests / n,
               m.with.ray_tri_tests / n, m.ms_without, m.ms_with, m.ms_without / m.ms_with, m.ms_lookup * 1e6 / n);
    csv_row(set, m);
  }
  if (!sets.empty())
    fmt::print("| mean of these workloads | | | | {:.1f} % | | | | | {:.2f}x (geometric) | |\n"
               "paper (EGSR 2019, mean over its scenes and ray types): 42 % fewer steps, about 15 % less time (1.18x)\n",
               100.0 * saved_sum / double(sets.size()), std::exp(log_speedup_sum / double(sets.size())));
}

/// Every variant (base x sweep value) of one scene: build, summary, table.
void run_scene(const Scene& scene, const std::string& sname, const Options& o, std::ofstream& csv) {
  std::vector<Variant> variants;
  for (const auto& b : split(o.bases)) {
    if (!o.sweep) { variants.push_back({b, -1, -1}); continue; }
    for (double r : {0.25, 0.5, 1.0, 2.0, 4.0}) variants.push_back({b, r, -1});
    for (int d : {2, 3, 6, 8}) variants.push_back({b, -1, d});
  }
  const bool build_only = split(o.workloads) == std::vector<std::string>{"none"};
  std::vector<RaySet> sets;
  for (const Variant& v : variants) {
    const auto base = v.base == "wide" ? ShaftsAccelerator::Base::Wide : ShaftsAccelerator::Base::Binary;
    // The options as the registry reads them; a key the accelerator does not read is an error.
    AcceleratorOptions opts = AcceleratorOptions::from_list(o.accel_opts);
    auto [cfg, bvh_cfg] = ShaftsAccelerator::settings_from_options(opts, base);
    opts.check_all_used(base == ShaftsAccelerator::Base::Wide ? "shafts-wide" : "shafts");
    if (v.budget_rel > 0) cfg.budget_rel = v.budget_rel;
    if (v.dir_res > 0) cfg.dir_res = v.dir_res;
    const Built built = build_alternated(scene, base, cfg, bvh_cfg, o.build_reps);
    const ShaftsAccelerator& acc = *built.acc;
    if (sets.empty() && !build_only)
      sets = make_ray_sets(scene, acc, o.width, o.height, split(o.workloads));
    const ShaftStats& st = acc.collection_stats();
    const double bvh_mib = acc.bvh_memory_bytes() / 1048576.0;
    // budget_mib, when set, overrides budget_rel (ShaftConfig): the heading names the one in force.
    const std::string budget =
        cfg.budget_mib > 0 ? fmt::format("budget_mib {}", cfg.budget_mib) : fmt::format("budget_rel {}", cfg.budget_rel);
    fmt::print("\n### {} over {} ({}, dir_res {})\n{}\n", acc.name(), v.base == "wide" ? "WideBvh" : "Bvh2", budget,
               cfg.dir_res, st.summary());
    fmt::print("BVH build {:.1f} ms, {:.2f} MiB; collection build {:.1f} ms ({:.2f}x BVH), {:.2f} MiB ({:.2f}x BVH)\n",
               acc.bvh_build_ms(), bvh_mib, st.build_ms, st.build_ms / acc.bvh_build_ms(),
               st.memory_bytes() / 1048576.0, st.memory_bytes() / 1048576.0 / bvh_mib);
    fmt::print("build on the trace clock (median of {}): BVH {:.1f} ms, collection {:.1f} ms = {:.2f}x the BVH\n\n",
               built.reps, built.bvh_ms, built.collection_ms, built.collection_ms / built.bvh_ms);
    if (build_only) continue;
    if (!o.profile_side.empty()) {
      profile(acc, sets, o);
      continue;
    }
    compare(acc, sets, o, [&](const RaySet& set, const Measure& m) {
      if (!csv.is_open()) return;
      const double n = double(std::max<size_t>(1, set.rays.size()));
      csv << sname << "," << v.base << "," << cfg.budget_rel << "," << cfg.dir_res << "," << set.label() << ","
          << set.rays.size() << "," << m.without.traversal_steps / n << "," << m.with.traversal_steps / n << ","
          << m.ms_without << "," << m.ms_with << "," << built.bvh_ms << "," << built.collection_ms << "," << bvh_mib
          << "," << st.memory_bytes() / 1048576.0 << "," << st.mean_list << "," << m.without.ray_box_tests / n << ","
          << m.with.ray_box_tests / n << "," << m.without.ray_tri_tests / n << "," << m.with.ray_tri_tests / n << "\n";
    });
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Ray classification (shafts, shafts-wide) vs plain traversal of the same BVH, side by side: exact steps and "
               "tests per ray, trace times (--reps) and build times (--build-reps)"};
  const std::string dir = RAYSCOUT_BENCH_SCENES;
  Options o;
  o.scenes = dir + "/sibenik-a.json," + dir + "/sponza.json," + dir + "/conference.json";
  app.add_option("--scenes", o.scenes, "comma-separated scene files: a path as given (absolute or from the current folder), else a "
                 "bench view by name (sponza = bench/scenes/sponza.json), else relative to $RAYSCOUT_SCENES; a file found "
                 "nowhere is skipped (default: sibenik-a, sponza, conference)");
  auto* workloads = app.add_option("--workloads", o.workloads,
                                   "primary,shadow,ao,diffuse,path (bounces 1-3 of a path-traced frame at half the width and height), "
                                   "or none (builds only, for build times); with --sweep the default is shadow,ao,diffuse")
                        ->capture_default_str();
  app.add_option("--base", o.bases, "binary (shafts over Bvh2), wide (shafts-wide over WideBvh), comma-separated")
      ->capture_default_str();
  app.add_option("--accel-opt", o.accel_opts, "shafts or BVH build option key=value, repeatable, as rayscout's (docs/shafts.md)");
  app.add_option("--width", o.width)->capture_default_str()->check(CLI::Range(1, 32768));
  app.add_option("--height", o.height)->capture_default_str()->check(CLI::Range(1, 32768));
  app.add_option("--reps", o.reps, "timed repetitions of each side, plain and shafts alternated after an untimed warm-up (median); "
                 "then as many of the lookup alone (lookup ns/ray), after its own warm-up")->capture_default_str()->check(CLI::Range(1, 1000000));
  app.add_option("--threads", o.threads, "0 = all cores; 1 (default) times with the thread's CPU clock, robust on a loaded machine; more with the wall clock")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--sweep", o.sweep, "a table per budget_rel (0.25-4) and per dir_res (2-8) instead of one per base, on shadow, ao and diffuse "
               "rays unless --workloads is given (--workloads none: builds only)");
  app.add_option("--csv", o.csv, "also write rows as CSV to this file");
  app.add_option("--build-reps", o.build_reps, "builds of BVH and accelerator, alternated (median build times)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  app.add_option("--profile-side", o.profile_side, "plain|lists: only trace that side reps times per ray set (for perf stat)")
      ->check(CLI::IsMember({"plain", "lists"}));
  CLI11_PARSE(app, argc, argv);
  // The sweep's own default (its CSV feeds plot_shafts.py's sweep plot); a given --workloads wins.
  if (o.sweep && workloads->count() == 0) o.workloads = "shadow,ao,diffuse";
  return bench::run_bench("shafts_bench", [&] {
    // An empty list would print headings without rows and exit 0.
    for (const auto& [option, list] : {std::pair{"--scenes", &o.scenes}, {"--workloads", &o.workloads}, {"--base", &o.bases}})
      if (split(*list).empty()) throw InputError(std::string(option) + ": empty (give at least one name)");
    bench::check_names("--base", split(o.bases), {"binary", "wide"});
    const std::vector<std::string> wl = split(o.workloads);
    bench::check_names("--workloads", wl, {"primary", "shadow", "ao", "diffuse", "path", "none"});
    if (std::find(wl.begin(), wl.end(), "none") != wl.end() && wl.size() > 1)
      throw InputError("--workloads: 'none' (builds only) cannot be combined with workloads");
    // A bad --accel-opt ends the run before the first scene loads, not after it.
    for (const std::string& b : split(o.bases))
      check_accelerator(b == "wide" ? "shafts-wide" : "shafts", AcceleratorOptions::from_list(o.accel_opts));
    // budget_mib overrides budget_rel (ShaftConfig): every budget row of the sweep would be the same.
    if (o.sweep && AcceleratorOptions::from_list(o.accel_opts).has("budget_mib"))
      throw InputError("--sweep varies budget_rel, which --accel-opt budget_mib overrides: give budget_rel or no budget");

    const int nthreads = o.threads > 0 ? o.threads : int(std::thread::hardware_concurrency());
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(nthreads));
    g_clock = nthreads == 1 ? Clock::ThreadCpu : Clock::Wall;
    fmt::print("# machine: {}\n", bench::machine_description());
    fmt::print("# shafts_bench: {} thread(s), trace times = {}, {}x{} workloads, median of {} reps\n", nthreads,
               bench::clock_name(g_clock), o.width, o.height, o.reps);
    std::ofstream csv;
    if (!o.csv.empty()) {
      csv.open(o.csv);
      if (!csv) throw InputError(o.csv + ": cannot open for writing");
      csv << "scene,base,budget_rel,dir_res,workload,rays,steps_bvh,steps_shafts,ms_bvh,ms_shafts,"
             "bvh_build_ms,shaft_build_ms,bvh_mib,shaft_mib,mean_list,box_bvh,box_shafts,tri_bvh,tri_shafts\n";
    }
    for (const std::string& s : split(o.scenes)) {
      const auto path = resolve_scene(s, dir);
      if (!path) {
        bench::print_skip(s, "no such file, bench view or file under the scenes folder");
        continue;
      }
      const std::optional<Scene> loaded = bench::load_or_skip("--scenes", path->string(), s);
      if (!loaded) continue;
      const Scene& scene = *loaded;
      const std::string sname = path->extension() == ".json" ? path->stem().string() : path->parent_path().filename().string();
      fmt::print("\n## {} ({} triangles)\n", sname, scene.triangles.size());
      run_scene(scene, sname, o, csv);
    }
    return 0;
  });
}
