// dacrt_bench: the experiments of the ray-sampling DACRT paper (Nabata et al., IPSJ Journal
// 2014): frame times of Afra's DACRT and the ray-sampled DACRT per resolution and bounce,
// the ablation, the sampling strategies, ray-box test reduction, and bvh/embree including
// their build on the same ray sets. Prints markdown tables and writes JSON for the plots.
#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "rayscout/accelerators.h"
#include "rayscout/core/output_path.h"
#include "rayscout/core/scenes_dir.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/dacrt/dacrt.h"
#include "rayscout/scene/load_scene.h"
#include "bench_support.h"
#include "ray_sets.h"
#include "views.h"

using namespace rayscout;
using namespace rayscout::bench;

namespace {

const std::vector<std::string> kExperiments = {"resolution", "ablation", "sampling", "counts", "peers", "variants", "memory"};
// Batch kinds the ray sets can have (bench ray sets and the renderer's BatchInfo::kind).
const std::vector<std::string> kBatchKinds = {"primary", "shadow", "ao", "mirror", "path"};

// --batches names are a kind or kind@bounce (bounce >= 1): a misspelt one used to give empty
// tables and a frame ratio of -nan with exit 0.
void check_batch_names(const std::vector<std::string>& given) {
  for (const std::string& g : given) {
    const size_t at = g.find('@');
    check_names("--batches", {g.substr(0, at)}, kBatchKinds);
    const std::string bounce = at == std::string::npos ? "1" : g.substr(at + 1);
    if (bounce.empty() || bounce.size() > 3 || bounce.find_first_not_of("0123456789") != std::string::npos ||
        std::stoi(bounce) < 1)
      throw InputError("--batches: '" + g + "': the bounce after '@' must be a number from 1 to 999");
  }
}

struct Options {
  std::vector<std::string> views;
  std::vector<int> res{512, 1024, 2048};
  bool big = false;
  int reps = 3;
  int threads = 1;
  std::vector<std::string> experiments{"resolution", "ablation", "sampling", "counts", "peers"};
  std::string json;  // none unless asked: a trial run must not overwrite the committed results
  int study_res = 2048;
  std::vector<std::string> study_views{"sibenik-a", "sponza-a"};
  std::string source = "render";
  std::vector<std::string> batches;   // empty = every batch
  std::vector<std::string> variants;  // "label[:accel][:key=value,...]", dacrt-rs unless accel is dacrt
  bool variants_only = false;         // no dacrt / dacrt-rs columns (profiling one variant)
};

/// A labelled set of accelerator options ("key=value") on top of an accelerator's defaults.
using Config = std::pair<std::string, std::vector<std::string>>;

bool contains(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

/// "VmRSS" or "VmHWM" (peak resident) of this process in bytes, from /proc/self/status.
double status_bytes(const std::string& key) {
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind(key + ":", 0) == 0) return std::stod(line.substr(key.size() + 1)) * 1024.0;  // "VmRSS:  1234 kB"
  return 0.0;
}

/// Returns freed heap to the system and restarts the peak at the current resident size
/// (proc(5), clear_refs value 5), so that the next VmHWM is the peak of what follows.
double restart_peak() {
  malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
  return status_bytes("VmRSS");
}

/// One run of the driver: the options, the scenes loaded so far and the JSON results; one
/// method per experiment.
class DacrtBench {
 public:
  explicit DacrtBench(const Options& o) : o_(o), clock_(o.threads == 1 ? Clock::ProcessCpu : Clock::Wall) {}

  int run() {
    print_header();
    if (wants("resolution")) resolution();
    if (wants("variants")) variants();
    for (const auto& v : paper_views())
      if (contains(o_.study_views, v.name)) study(v);
    for (const std::string& b : o_.batches)
      if (!matched_batches_.contains(b)) fmt::print("note: --batches {}: no view run has such a batch\n", b);
    if (!o_.json.empty()) {
      write_file(o_.json, out_.dump(1) + "\n", "results file");
      fmt::print("results: {}\n", o_.json);
    }
    return 0;
  }

 private:
  /// A study view's ray sets at --study-res and dacrt's frame time on them (when needed).
  struct Study {
    const View& view;
    const Scene& scene;
    std::vector<RaySet> sets;
    double afra_ms = 0;
  };

  bool wants(const std::string& e) const { return contains(o_.experiments, e); }
  bool rendered() const { return o_.source == "render"; }

  std::unique_ptr<Accelerator> make(const std::string& name, const Scene& scene,
                                    const std::vector<std::string>& extra = {}) const {
    AcceleratorOptions opts;
    if (name.rfind("dacrt", 0) == 0) opts.set("parallel", o_.threads > 1 ? "on" : "off");
    for (const auto& e : extra) opts.set(e);
    return make_accelerator(name, scene, opts);
  }

  /// One untimed trace of the largest of sets with each of accs: a DacrtAccelerator computes its
  /// triangle boxes at its first call and keeps its buffers, grown to the largest batch, between
  /// calls; without this the first timed repetition paid for both (and, with 1 or 2 repetitions,
  /// the median).
  static void warm_up(const std::vector<const Accelerator*>& accs, const std::vector<RaySet>& sets) {
    const auto largest = std::max_element(sets.begin(), sets.end(),
                                          [](const RaySet& a, const RaySet& b) { return a.rays.size() < b.rays.size(); });
    if (largest == sets.end()) return;
    for (const Accelerator* a : accs) trace(*a, *largest);
  }

  /// Median times of reps traces of s (ms) by each of accs, their repetitions interleaved so
  /// that a change of load on the shared machine hits every side of a ratio alike. One thread
  /// is timed by the process CPU time, more by the wall clock (bench_support.h). No warm-up
  /// here: the callers warm up once on the largest of their sets (warm_up).
  std::vector<double> interleaved_ms(const std::vector<const Accelerator*>& accs, const RaySet& s) const {
    return interleaved_medians(accs.size(), {.count = o_.reps, .warm_up = false},
                               [&](size_t k) { return trace_ms(clock_, *accs[k], s); });
  }

  /// Sum over the study's sets of a's median times (ms), after a warm-up.
  double frame_ms(const Accelerator& a, const Study& st) const {
    warm_up({&a}, st.sets);
    double t = 0;
    for (const auto& s : st.sets) t += interleaved_ms({&a}, s)[0];
    return t;
  }

  /// The view's scene, loaded once; null when its file is missing (or, for the renderer's ray
  /// sets, when the view has no bench scene).
  std::shared_ptr<Scene> scene_of(const View& v) {
    if (rendered() && v.scene_json.empty()) return nullptr;
    const std::string key = rendered() ? v.scene_json : v.file;
    if (auto it = scenes_.find(key); it != scenes_.end()) return it->second;
    if (!find_scene_file(v.file)) return nullptr;
    auto s = std::make_shared<Scene>(load_scene(rendered() ? std::string(RAYSCOUT_BENCH_SCENES) + "/" + v.scene_json
                                                           : find_scene_file(v.file)->string()));
    scenes_[key] = s;
    return s;
  }

  std::vector<RaySet> ray_sets(const View& v, const Scene& scene, int res) const {
    auto bvh = make_accelerator("bvh", scene);
    auto sets = rendered() ? render_ray_sets(scene, v, res, res, *bvh) : make_ray_sets(scene, v, res, res, *bvh);
    if (!o_.batches.empty()) std::erase_if(sets, [&](const RaySet& s) { return !contains(o_.batches, s.label()); });
    for (const RaySet& s : sets) matched_batches_.insert(s.label());
    return sets;
  }

  void print_header() {
    out_["threads"] = o_.threads;
    out_["reps"] = o_.reps;
    out_["clock"] = clock_name(clock_);
    fmt::print("# machine: {}\n", machine_description());
    fmt::print("# dacrt_bench: threads={} reps={} (median), clock: {}, ray sets: {}\n\n", o_.threads, o_.reps,
               clock_name(clock_), rendered() ? "renderer batches of bench/scenes" : "own camera");
    // The configurations as make() builds them: parallel follows --threads.
    DacrtConfig afra = DacrtConfig::afra(), rs = DacrtConfig::ray_sampled();
    afra.parallel = rs.parallel = o_.threads > 1;
    fmt::print("# dacrt:    {}\n# dacrt-rs: {}\n\n", afra.describe(), rs.describe());
    out_["dacrt_config"] = afra.describe();
    out_["dacrt_rs_config"] = rs.describe();
    out_["source"] = o_.source;
  }

  /// 1. Frame and per-bounce times of dacrt and dacrt-rs per resolution (figs. 4-8).
  void resolution() {
    fmt::print("## Tracing time per resolution and batch (ms; repetitions interleaved after a warm-up; "
               "ratio = dacrt / dacrt-rs, above 1 when dacrt-rs is faster)\n\n");
    fmt::print("| view | res | batch | rays | dacrt | dacrt-rs | dacrt / dacrt-rs | paper (frame) |\n|---|---|---|---|---|---|---|---|\n");
    for (const auto& v : paper_views()) {
      if (!contains(o_.views, v.name)) continue;
      auto scene = scene_of(v);
      if (!scene) {
        if (!rendered() || !v.scene_json.empty()) fmt::print("| {} | missing {} ({}) | | | | | | |\n", v.name, v.file, scenes_dir_origin());
        continue;
      }
      auto afra = make("dacrt", *scene), rs = make("dacrt-rs", *scene);
      for (int res : o_.res) {
        double fa = 0, fr = 0;
        const std::vector<RaySet> sets = ray_sets(v, *scene, res);
        warm_up({afra.get(), rs.get()}, sets);
        for (const auto& s : sets) {
          const std::vector<double> ms = interleaved_ms({afra.get(), rs.get()}, s);
          const double ta = ms[0], tr = ms[1];
          fa += ta;
          fr += tr;
          fmt::print("| {} | {} | {} | {} | {:.1f} | {:.1f} | {:.2f} | |\n", v.name, res, s.label(), s.rays.size(), ta, tr, ta / tr);
          out_["resolution"].push_back({{"view", v.name}, {"res", res}, {"batch", s.label()}, {"rays", s.rays.size()},
                                        {"dacrt_ms", ta}, {"dacrt_rs_ms", tr}});
        }
        const auto& pr = paper_ratios().at(v.name);
        // The paper measured 512^2 to 4096^2 only; other resolutions have no value to compare with.
        const bool has_paper = pr.count(res) > 0;
        fmt::print("| {} | {} | **frame** | | {:.1f} | {:.1f} | **{:.2f}** | {} |\n", v.name, res, fa, fr, fa / fr,
                   has_paper ? fmt::format("{:.2f}", pr.at(res)) : "–");
        out_["frames"].push_back({{"view", v.name}, {"res", res}, {"dacrt_ms", fa}, {"dacrt_rs_ms", fr},
                                  {"paper_ratio", has_paper ? nlohmann::json(pr.at(res)) : nlohmann::json(nullptr)}});
        std::fflush(stdout);
      }
    }
    fmt::print("\n");
  }

  /// Variants: dacrt, dacrt-rs and option sets on top of dacrt-rs, repetitions interleaved so
  /// that every ratio is measured side by side; plus each one's counts.
  void variants() {
    // A variant is dacrt-rs (or dacrt) plus its options; the first column is plain dacrt.
    std::vector<ColumnSpec> configs = {{"dacrt", "dacrt-rs", {"cost=sah", "order=one-ray", "skip=off"}},
                                       {"dacrt-rs", "dacrt-rs", {}}};
    if (o_.variants_only) configs.clear();
    for (const auto& v : o_.variants) configs.push_back(parse_column("--variants", v, "dacrt-rs"));
    // With --variants-only the ratios are against the first variant, not dacrt.
    fmt::print("## Variants (ms, repetitions interleaved after a warm-up, ratio = {} / variant; box = partition+sampling tests, tri = triangle tests, per ray)\n\n",
               configs.front().label);
    fmt::print("| view | res | batch | rays |");
    for (const auto& c : configs) fmt::print(" {} |", c.label);
    fmt::print("\n|---|---|---|---|");
    for (size_t k = 0; k < configs.size(); ++k) fmt::print("---|");
    fmt::print("\n");
    for (const auto& v : paper_views()) {
      if (!contains(o_.views, v.name)) continue;
      auto scene = scene_of(v);
      if (!scene) {
        if (!rendered() || !v.scene_json.empty()) fmt::print("| {} | missing {} ({}) | | |\n", v.name, v.file, scenes_dir_origin());
        continue;
      }
      std::vector<std::unique_ptr<Accelerator>> accs;
      for (const auto& c : configs) accs.push_back(make(c.accel, *scene, c.options));
      for (int res : o_.res) {
        std::vector<double> frame(configs.size(), 0.0);
        std::vector<const Accelerator*> timed;
        for (const auto& a : accs) timed.push_back(a.get());
        const std::vector<RaySet> sets = ray_sets(v, *scene, res);
        warm_up(timed, sets);
        for (const auto& s : sets) {
          const std::vector<double> ms = interleaved_ms(timed, s);
          fmt::print("| {} | {} | {} | {} |", v.name, res, s.label(), s.rays.size());
          const double base = ms[0];
          for (size_t k = 0; k < accs.size(); ++k) {
            const double m = ms[k];
            frame[k] += m;
            TraceStats st;
            trace(*accs[k], s, &st);
            const auto d = dynamic_cast<const DacrtAccelerator*>(accs[k].get())->last_stats();
            fmt::print(" {:.1f} ({:.2f}x; box {:.1f}+{:.1f}, tri {:.2f}) |", m, base / m,
                       double(d.partition_box_tests) / double(s.rays.size()),
                       double(d.sampling_box_tests) / double(s.rays.size()), double(st.ray_tri_tests) / double(s.rays.size()));
            out_["variants"].push_back({{"view", v.name}, {"res", res}, {"batch", s.label()}, {"config", configs[k].label},
                                        {"ms", m}, {"partition_box", d.partition_box_tests},
                                        {"sampling_box", d.sampling_box_tests}, {"tri", st.ray_tri_tests}});
          }
          fmt::print("\n");
          std::fflush(stdout);
        }
        fmt::print("| {} | {} | **frame** | |", v.name, res);
        for (size_t k = 0; k < accs.size(); ++k) fmt::print(" {:.1f} ({:.2f}x) |", frame[k], frame[0] / frame[k]);
        fmt::print("\n");
      }
    }
    fmt::print("\n");
  }

  /// 2-5. The studies at one resolution on one view.
  void study(const View& v) {
    if (!(wants("ablation") || wants("sampling") || wants("counts") || wants("peers") || wants("memory"))) return;
    auto scene = scene_of(v);
    if (!scene) {
      print_skip(v.name, "missing " + v.file);
      return;
    }
    Study st{v, *scene, ray_sets(v, *scene, o_.study_res)};
    if (wants("ablation") || wants("sampling")) st.afra_ms = frame_ms(*make("dacrt", *scene), st);
    if (wants("ablation")) ablation(st);
    if (wants("sampling")) sampling(st);
    if (wants("counts")) counts(st);
    if (wants("peers")) peers(st);
    if (wants("memory")) memory(st);
    std::fflush(stdout);
  }

  void ablation(const Study& st) {
    const std::string& name = st.view.name;
    fmt::print("## Ablation, {} at {}^2 (frame ms; one configuration after another, dacrt's frame timed once before "
               "them, not interleaved; paper, Sibenik (a) 4096^2: cost 1.24x, order 1.05x, skip 1.28x)\n\n",
               name, o_.study_res);
    fmt::print("| configuration | frame ms | speed-up vs dacrt |\n|---|---|---|\n");
    fmt::print("| dacrt (all off) | {:.1f} | 1.00 |\n", st.afra_ms);
    const std::vector<Config> configs = {
        {"cost only (eq. 2)", {"cost=sampled"}},
        {"order only (Algorithm 2 as printed)", {"order=literal-votes"}},
        {"order only (entry votes)", {"order=sampled"}},
        {"skip only (eq. 5)", {"skip=on"}},
        {"cost + order (entry votes)", {"cost=sampled", "order=sampled"}},
        {"all three, as printed (paper)", {"cost=sampled", "order=literal-votes", "skip=on"}},
        {"all three, entry votes", {"cost=sampled", "order=sampled", "skip=on"}},
        {"cost + skip (one-ray order)", {"cost=sampled", "skip=on"}},
        {"all three, sign votes", {"cost=sampled", "order=sign-votes", "skip=on"}},
        {"all three, interval votes", {"cost=sampled", "order=interval-votes", "skip=on"}},
        {"all three, entry votes + sampling budget", {"cost=sampled", "order=sampled", "skip=on", "sample_budget=1"}},
        {"dacrt-rs (interval votes + budget)",
         {"cost=sampled", "order=interval-votes", "vote_weight=depth", "skip=on", "sample_budget=1"}}};
    auto counted = [&](const Accelerator& a) {
      TraceStats stats;
      for (const auto& s : st.sets) trace(a, s, &stats);
      return stats;
    };
    const TraceStats base = counted(*make("dacrt", st.scene));
    fmt::print("| (counts of dacrt) | box {} | tri {} |\n", base.ray_box_tests, base.ray_tri_tests);
    for (const auto& [label, extra] : configs) {
      auto acc = make("dacrt", st.scene, extra);
      const double t = frame_ms(*acc, st);
      const TraceStats c = counted(*acc);
      fmt::print("| {} | {:.1f} | {:.2f} (box {:+.1f} %, tri {:+.1f} %) |\n", label, t, st.afra_ms / t,
                 100.0 * (double(c.ray_box_tests) / double(base.ray_box_tests) - 1.0),
                 100.0 * (double(c.ray_tri_tests) / double(base.ray_tri_tests) - 1.0));
      out_["ablation"].push_back({{"view", name}, {"res", o_.study_res}, {"config", label}, {"ms", t},
                                  {"speedup", st.afra_ms / t}, {"box", c.ray_box_tests}, {"tri", c.ray_tri_tests}});
    }
    fmt::print("\n");
  }

  void sampling(const Study& st) {
    const std::string& name = st.view.name;
    fmt::print("## Sampling strategies, {} at {}^2 (speed-up = dacrt frame / configuration frame, dacrt timed once "
               "before them, not interleaved; fig. 9)\n\n", name, o_.study_res);
    fmt::print("| sampling | frame ms | speed-up |\n|---|---|---|\n");
    const std::vector<Config> configs = {
        {"stride 1 %", {"fraction=0.01"}},   {"random 1 %", {"fraction=0.01", "strategy=random"}},
        {"stride 0.1 %", {"fraction=0.001"}}, {"random 0.1 %", {"fraction=0.001", "strategy=random"}},
        {"stride 100", {}},                  {"random 100", {"strategy=random"}}};
    for (const auto& [label, extra] : configs) {
      const double t = frame_ms(*make("dacrt-rs", st.scene, extra), st);
      fmt::print("| {} | {:.1f} | {:.2f} |\n", label, t, st.afra_ms / t);
      out_["sampling"].push_back({{"view", name}, {"res", o_.study_res}, {"config", label}, {"ms", t}, {"speedup", st.afra_ms / t}});
    }
    fmt::print("\n");
  }

  void counts(const Study& st) {
    fmt::print("## Ray-box tests per batch, {} at {}^2 (fig. 10; paper: -30..-50 % primary, -30..-40 % shadow, -50 % mirror, -20 % random)\n\n", st.view.name, o_.study_res);
    fmt::print("| batch | dacrt box tests | dacrt-rs partition | dacrt-rs sampling | change (partition) | change (all) | tri tests dacrt | tri tests dacrt-rs | skipped |\n|---|---|---|---|---|---|---|---|---|\n");
    auto a = make("dacrt", st.scene), r = make("dacrt-rs", st.scene);
    const auto* ad = dynamic_cast<const DacrtAccelerator*>(a.get());
    const auto* rd = dynamic_cast<const DacrtAccelerator*>(r.get());
    for (const auto& s : st.sets) {
      TraceStats sa, sr;
      trace(*a, s, &sa);
      trace(*r, s, &sr);
      const DacrtStats da = ad->last_stats(), dr = rd->last_stats();
      const double ch_p = double(dr.partition_box_tests) / double(da.partition_box_tests) - 1.0;
      const double ch_a = double(sr.ray_box_tests) / double(sa.ray_box_tests) - 1.0;
      fmt::print("| {} | {} | {} | {} | {:+.1f} % | {:+.1f} % | {} | {} | {} |\n", s.label(), sa.ray_box_tests,
                 dr.partition_box_tests, dr.sampling_box_tests, 100 * ch_p, 100 * ch_a, sa.ray_tri_tests,
                 sr.ray_tri_tests, dr.skipped_partitions);
      out_["counts"].push_back({{"view", st.view.name}, {"res", o_.study_res}, {"batch", s.label()},
                                {"dacrt_box", sa.ray_box_tests}, {"rs_partition_box", dr.partition_box_tests},
                                {"rs_sampling_box", dr.sampling_box_tests}, {"rs_box", sr.ray_box_tests},
                                {"dacrt_tri", sa.ray_tri_tests}, {"rs_tri", sr.ray_tri_tests}});
    }
    fmt::print("\n");
  }

  /// Median build and trace time (ms) of the named accelerator, built afresh for each repetition.
  std::pair<double, double> build_and_trace(const char* name, const Scene& scene, const RaySet& s) const {
    std::vector<double> b, t;
    for (int rep = 0; rep < o_.reps; ++rep) {
      const double t0 = now_ms(clock_);
      auto acc = make_accelerator(name, scene);
      b.push_back(now_ms(clock_) - t0);
      t.push_back(trace_ms(clock_, *acc, s));
    }
    return {median(b), median(t)};
  }

  void peers(const Study& st) {
    fmt::print("## Peers including their build, {} at {}^2 (ms; a build per batch, as DACRT re-splits per batch; "
               "dacrt and dacrt-rs interleaved after a warm-up, so without their triangle boxes, computed at their "
               "first call; bvh and embree built afresh for each repetition)\n\n", st.view.name, o_.study_res);
    fmt::print("| batch | rays | dacrt | dacrt-rs | bvh build | bvh trace | bvh total | embree build | embree trace | embree total |\n|---|---|---|---|---|---|---|---|---|---|\n");
    auto a = make("dacrt", st.scene), r = make("dacrt-rs", st.scene);
    const bool have_embree = std::any_of(accelerators().begin(), accelerators().end(), [](const auto& i) { return i.name == "embree"; });
    warm_up({a.get(), r.get()}, st.sets);
    for (const auto& s : st.sets) {
      const std::vector<double> ms = interleaved_ms({a.get(), r.get()}, s);
      const double ta = ms[0], tr = ms[1];
      const auto [bvh_build, bvh_trace] = build_and_trace("bvh", st.scene, s);
      const auto [embree_build, embree_trace] = have_embree ? build_and_trace("embree", st.scene, s) : std::pair{0.0, 0.0};
      fmt::print("| {} | {} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} |\n", s.label(), s.rays.size(), ta, tr,
                 bvh_build, bvh_trace, bvh_build + bvh_trace, embree_build, embree_trace, embree_build + embree_trace);
      out_["peers"].push_back({{"view", st.view.name}, {"res", o_.study_res}, {"batch", s.label()}, {"rays", s.rays.size()},
                               {"dacrt_ms", ta}, {"dacrt_rs_ms", tr}, {"bvh_build_ms", bvh_build}, {"bvh_trace_ms", bvh_trace},
                               {"embree_build_ms", embree_build}, {"embree_trace_ms", embree_trace}});
    }
    fmt::print("\n");
  }

  /// Sec. 3: DACRT's memory is known in advance from |R| and |T| alone. Each row traces the
  /// first |R| primary rays over the first |T| triangles with a fresh accelerator and compares
  /// the formula (last_trace_memory_bytes) with the peak resident memory it added.
  void memory(const Study& st) {
    fmt::print("## Memory, {} primary rays at {}^2 (fresh accelerator per row; peak = peak RSS over the call minus RSS before it)\n\n", st.view.name, o_.study_res);
    fmt::print("| accelerator | \\|R\\| | \\|T\\| | formula MiB | peak MiB | peak / formula |\n|---|---:|---:|---:|---:|---:|\n");
    const auto primary = std::find_if(st.sets.begin(), st.sets.end(), [](const RaySet& s) { return s.label() == "primary"; });
    if (primary == st.sets.end()) {
      fmt::print("(no primary batch)\n\n");
      return;
    }
    const size_t nr = primary->rays.size(), nt = st.scene.triangles.size();
    const std::vector<std::pair<size_t, size_t>> sizes = {{nr / 16, nt}, {nr / 4, nt}, {nr, nt}, {nr, nt / 4}, {nr, nt / 16}};
    for (const char* name : {"dacrt", "dacrt-rs"})
      for (const auto& [r, t] : sizes) {
        Scene part = st.scene;
        part.triangles.resize(t);
        part.emissive_triangles.clear();
        RayBatch rays = primary->rays;
        rays.resize(r);
        auto acc = make(name, part);
        HitBatch hits;
        hits.reset(r);  // the output, written before the peak restarts: not the accelerator's
        const double before = restart_peak();
        acc->intersect(rays, hits);
        const double grown = status_bytes("VmHWM") - before, formula = double(acc->last_trace_memory_bytes());
        fmt::print("| {} | {} | {} | {:.1f} | {:.1f} | {:.2f} |\n", name, r, t, formula / 1048576.0, grown / 1048576.0, grown / formula);
        out_["memory"].push_back({{"view", st.view.name}, {"accel", name}, {"rays", r}, {"triangles", t},
                                  {"formula_bytes", formula}, {"peak_bytes", grown}});
      }
    fmt::print("\n");
  }

  const Options& o_;
  const Clock clock_;
  nlohmann::json out_;
  std::map<std::string, std::shared_ptr<Scene>> scenes_;
  mutable std::set<std::string> matched_batches_;  ///< labels of the sets ray_sets() kept
};

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "Experiments of the ray-sampling DACRT paper. Times are medians of --reps traces, after one untimed warm-up "
      "trace of the largest batch; 1 thread is timed by process CPU time, more by the wall clock. dacrt and dacrt-rs (and --variants) "
      "are interleaved in resolution, variants and peers; ablation and sampling time one configuration after another; "
      "peers builds bvh and embree afresh for each repetition, without a warm-up."};
  std::string view_list;
  for (const auto& v : paper_views()) {
    o.views.push_back(v.name);
    view_list += (view_list.empty() ? "" : ",") + v.name;
  }
  app.add_option("--views", o.views, "views of resolution and variants (default: all ten: " + view_list + ")")->delimiter(',');
  app.add_option("--res", o.res, "square resolutions")->delimiter(',')->check(CLI::Range(1, 16384))->capture_default_str();
  app.add_flag("--big", o.big, "also 4096^2");
  app.add_option("--reps", o.reps, "repetitions per measurement (median)")->check(CLI::Range(1, 1000000))->capture_default_str();
  app.add_option("--threads", o.threads, "threads (1 = the paper's single thread, timed by process CPU time; more: wall clock and dacrt parallel=on)")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  app.add_option("--experiments", o.experiments, "of resolution,ablation,sampling,counts,peers,variants,memory")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--study-res", o.study_res, "resolution of ablation, sampling, counts, peers and memory")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  app.add_option("--study-views", o.study_views, "views of ablation, sampling, counts, peers and memory")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--json", o.json, "results file for plot_dacrt.py (default none; docs/figures/dacrt/dacrt_results.json holds the committed results)");
  app.add_option("--source", o.source, "ray sets: render (bench/scenes + the renderer's batches) or own (bench camera)")
      ->check(CLI::IsMember({"render", "own"}))
      ->capture_default_str();
  app.add_option("--batches", o.batches,
                 "only these batches: primary, shadow, ao, mirror or path, @N for bounce N (e.g. primary,shadow,mirror@1; "
                 "default all)")->delimiter(',');
  app.add_option("--variants", o.variants,
                 "experiment 'variants': label[:accel][:key=value,...], dacrt-rs (or accel dacrt) with these "
                 "options, timed side by side with dacrt and dacrt-rs (repeatable; e.g. cs:cost=sampled,skip=on)");
  app.add_flag("--variants-only", o.variants_only, "experiment 'variants' without the dacrt and dacrt-rs columns");
  CLI11_PARSE(app, argc, argv);
  return run_bench("dacrt_bench", [&] {
    std::vector<std::string> view_names;
    for (const auto& v : paper_views()) view_names.push_back(v.name);
    check_names("--views", o.views, view_names);
    check_names("--study-views", o.study_views, view_names);
    check_names("--experiments", o.experiments, kExperiments);
    check_batch_names(o.batches);
    // Without a variant the table would have no column to take the ratios against.
    if (o.variants_only && o.variants.empty()) throw InputError("--variants-only: give at least one --variants");
    // A bad variant key ends the run here, not after the headings and the first view's scene.
    for (const std::string& v : o.variants) {
      const ColumnSpec c = parse_column("--variants", v, "dacrt-rs");
      check_names("--variants '" + v + "'", {c.accel}, {"dacrt", "dacrt-rs"});  // the table reads DACRT's own counts
      check_argument("--variants", v, [&] {
        AcceleratorOptions opts = AcceleratorOptions::from_list(c.options);
        opts.set("parallel", o.threads > 1 ? "on" : "off");
        check_accelerator(c.accel, opts);
      });
    }
    if (!o.json.empty()) check_output_path(o.json, "--json");
    if (o.big && !std::count(o.res.begin(), o.res.end(), 4096)) o.res.push_back(4096);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(o.threads));
    return DacrtBench(o).run();
  });
}
