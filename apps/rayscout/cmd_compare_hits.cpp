// `rayscout compare-hits A B`: ray-by-ray agreement of two HITS (or two OCCL) files.
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "commands.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/hit_compare.h"
#include "rayscout/core/ray_file.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout::cli {
namespace {

struct CompareArgs {
  std::string a, b, rays, hits_a, hits_b, scene;
  float tolerance = 1e-4f;
  float edge_eps = 1e-4f;
  float ulps = 4.0f;
  float max_grazing = 0.01f;
  bool strict = false;
  std::vector<std::string> hit_options;  // those given of the options that judge closest hits
  bool edge_eps_given = false, ulps_given = false;
};

// The excuse for a grazing contact rests on a claimed hit, possibly the candidate's own: a
// tracer that reports t = 0 or a zero barycentric everywhere would excuse itself. Real tracers
// disagree at grazing contacts on a few rays in 10^4 (bench/audit), so many more are an error.
bool grazing_within_bound(size_t grazing, size_t rays, const CompareArgs& args) {
  if (double(grazing) <= double(args.max_grazing) * double(rays)) return true;
  fmt::print("too many grazing:      {} of {} rays, above --max-grazing {:g}: check with --strict\n", grazing, rays,
             args.max_grazing);
  return false;
}

// What every comparison shares: the config (with the rays of --rays) and the record count
// that every file must hold, A's or the RAYS file's.
struct Comparison {
  const CompareArgs& args;
  HitCompareConfig cfg;
  RayBatch rays;
  Scene scene;
  size_t n = 0;
  std::string counted;  // what n counts, e.g. "a.hits: 64 hits"

  Comparison(const Comparison&) = delete;  // cfg.rays and cfg.triangles point into members
  Comparison(const CompareArgs& a, const ResultFile& fa) : args(a) {
    cfg.rel_tol = a.tolerance;
    cfg.allow_grazing = !a.strict;
    cfg.edge_eps = a.edge_eps;
    cfg.ulps = a.ulps;
    const bool occl = fa.kind == RayFileKind::Occlusion;
    if (!a.rays.empty()) {
      rays = read_rays(a.rays);
      cfg.rays = &rays;
    }
    if (!a.scene.empty()) {
      scene = resolve_scene(a.scene);
      print_scene_warnings(scene);
      cfg.triangles = scene.triangles;
    }
    n = cfg.rays ? rays.size() : occl ? fa.occluded.size() : fa.hits.size();
    counted = (cfg.rays ? a.rays : a.a) + ": " + std::to_string(n) + (cfg.rays ? " rays" : occl ? " results" : " hits");
  }

  // Every file of a comparison describes the same rays.
  void check_size(size_t size, const std::string& file, const char* what) const {
    if (size != n) throw InputError(counted + ", but " + file + " holds " + std::to_string(size) + " " + what);
  }
  // With --scene, every hit names one of its triangles (else the files come from another scene).
  void check_triangles(const HitBatch& hits, const std::string& file) const {
    if (args.scene.empty()) return;
    for (size_t i = 0; i < hits.size(); ++i)
      if (hits.prim[i] != kInvalidId && hits.prim[i] >= scene.triangles.size())
        throw InputError(fmt::format("{}: ray {} hits triangle {}, but --scene {} has {} triangles (traced against "
                                     "another scene?)",
                                     file, i, hits.prim[i], args.scene, scene.triangles.size()));
  }
  // What a grazing contact is, for the report.
  std::string grazing_rule() const {
    if (!args.scene.empty())
      return fmt::format("an edge, an end of the segment or two distances within {:g} float ulps of the coordinates",
                         args.ulps);
    return fmt::format("edge/vertex within {:g} barycentric or t ~ 0", args.edge_eps);
  }
};

// Two OCCL files; with --hits-a/--hits-b, disagreements whose blocker is grazing are excused.
bool compare_occlusion_files(const Comparison& c, const ResultFile& fa, const ResultFile& fb) {
  const CompareArgs& args = c.args;
  const bool with_hits = !args.hits_a.empty();
  HitBatch ha, hb;
  if (with_hits) {
    ha = read_hits(args.hits_a);
    hb = read_hits(args.hits_b);
  }
  c.check_size(fa.occluded.size(), args.a, "results");
  c.check_size(fb.occluded.size(), args.b, "results");
  if (with_hits) {
    c.check_size(ha.size(), args.hits_a, "hits");
    c.check_size(hb.size(), args.hits_b, "hits");
    c.check_triangles(ha, args.hits_a);
    c.check_triangles(hb, args.hits_b);
  }
  const OcclusionDiff d =
      compare_occlusion(fa.occluded, fb.occluded, c.cfg, with_hits ? &ha : nullptr, with_hits ? &hb : nullptr);
  fmt::print("rays:                  {}\n", d.rays);
  fmt::print("occluded:              {} in A, {} in B\n", d.occluded_ref, d.occluded_got);
  fmt::print("disagreements:         {}\n", d.differ);
  if (with_hits && c.cfg.excuses_grazing())
    fmt::print("grazing contacts:      {} (the occluded side's closest hit is grazing: {}; not counted)\n", d.grazing,
               c.grazing_rule());
  if (!d.first.empty()) fmt::print("first:                 {}\n", d.first);
  const bool ok = grazing_within_bound(d.grazing, d.rays, args) && d.ok();
  fmt::print("result:                {}\n", ok ? "OK" : "DIFFERENT");
  return ok;
}

// Two HITS files: hit or miss, triangle, t (and u, v at tolerance 0).
bool compare_hit_files(const Comparison& c, const ResultFile& fa, const ResultFile& fb) {
  const CompareArgs& args = c.args;
  const HitBatch &ha = fa.hits, &hb = fb.hits;
  c.check_size(ha.size(), args.a, "hits");
  c.check_size(hb.size(), args.b, "hits");
  c.check_triangles(ha, args.a);
  c.check_triangles(hb, args.b);
  const HitDiff d = compare_hits(ha, hb, c.cfg);
  size_t hits_a = 0, hits_b = 0;
  for (uint32_t p : ha.prim) hits_a += p != kInvalidId;
  for (uint32_t p : hb.prim) hits_b += p != kInvalidId;
  fmt::print("rays:                  {}\n", d.rays);
  fmt::print("hits:                  {} in A, {} in B, {} in both\n", hits_a, hits_b, d.both_hit);
  fmt::print("hit/miss:              {}\n", d.hit_miss);
  if (args.tolerance == 0)
    fmt::print("different triangle:    {} (tolerance 0: an exact tie broken another way counts)\n", d.other_prim);
  else
    fmt::print("different triangle:    {} (true ties excluded: {})\n", d.other_prim, d.ties);
  fmt::print("grazing contacts:      {}{}\n", d.grazing,
             !c.cfg.excuses_grazing()
                 ? ""
                 : fmt::format(" ({}; not counted)", c.grazing_rule()));
  fmt::print("t beyond tolerance:    {}\n", d.t_mismatch);
  if (args.tolerance == 0) fmt::print("u, v not identical:    {}\n", d.uv_mismatch);
  fmt::print("t rel. difference:     max {:.3e}, 99th percentile {:.3e} ({})\n", d.max_rel_diff, d.p99_rel_diff,
             c.cfg.rays ? "world space: |dt| |d| / max(1, |o|, |hit point|)" : "|dt| / max(1, t_A)");
  if (!c.cfg.triangles.empty())
    for (const auto& [name, p] : {std::pair{"A", d.ref_offsets}, std::pair{"B", d.got_offsets}})
      fmt::print("off the plane, {}:      median {:.2f}, 99th percentile {:.2f}, max {:.2f} ulps over {} hits (how far "
                 "o + t d lies from its triangle's plane; the unit of --ulps)\n",
                 name, p.median, p.p99, p.max, p.hits);
  if (!d.first.empty()) fmt::print("first:                 {}\n", d.first);
  const bool ok = grazing_within_bound(d.grazing, d.rays, args) && d.ok();
  fmt::print("result:                {} (tolerance {:g})\n", ok ? "OK" : "DIFFERENT", args.tolerance);
  // Tracers of other arithmetic (embree) differ in t by the precision of the coordinates, which
  // t alone does not show: a researcher comparing them without --rays got DIFFERENT and no clue.
  if (!ok && !c.cfg.rays && d.t_mismatch > 0 && d.hit_miss == 0 && d.other_prim == 0)
    fmt::print("hint:                  only distances differ, judged against t alone; if the files come from one RAYS "
               "file, give it (--rays FILE) to judge them in world space, where a float hit point is only as exact as "
               "its coordinates\n");
  return ok;
}

// Returns true when the files agree within the tolerance.
bool compare_files(const CompareArgs& args) {
  const ResultFile fa = read_results(args.a), fb = read_results(args.b);
  if (fa.kind != fb.kind) throw InputError(args.a + " and " + args.b + ": one is a HITS file, the other an OCCL file");
  const bool occl = fa.kind == RayFileKind::Occlusion;
  if (!occl && (!args.hits_a.empty() || !args.hits_b.empty()))
    throw InputError("--hits-a and --hits-b are for OCCL files; " + args.a + " is a HITS file");
  if (args.hits_a.empty() != args.hits_b.empty()) throw InputError("--hits-a and --hits-b go together");
  if (!args.scene.empty() && args.rays.empty())
    throw InputError("--scene judges contacts from the rays' geometry: give the RAYS file too (--rays FILE)");
  if (!args.scene.empty() && args.edge_eps_given)
    fmt::print(stderr, "rayscout: warning: --edge-eps ignored with --scene (contacts are judged from the triangles)\n");
  if (args.scene.empty() && args.ulps_given)
    fmt::print(stderr, "rayscout: warning: --ulps ignored without --scene (it judges contacts from the triangles)\n");
  if (occl && args.hits_a.empty() && !args.hit_options.empty()) {
    std::string names;
    for (const std::string& o : args.hit_options) names += (names.empty() ? "" : ", ") + o;
    fmt::print(stderr,
               "rayscout: warning: {} {} ignored comparing OCCL files without --hits-a and --hits-b (they judge "
               "closest hits)\n",
               names, args.hit_options.size() == 1 ? "is" : "are");
  }
  const Comparison c(args, fa);
  return occl ? compare_occlusion_files(c, fa, fb) : compare_hit_files(c, fa, fb);
}

CommandRegistration registration{[](CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  auto* cmd = app.add_subcommand(
      "compare-hits", "Compare two HITS (or two OCCL) files ray by ray; exit 1 when they differ beyond the tolerance");
  set_memory_hint(*cmd, "compare smaller files");
  cmd->add_option("A", args->a, "reference HITS or OCCL file")->required()->check(file_path());
  cmd->add_option("B", args->b, "candidate file of the same kind")->required()->check(file_path());
  add_number(*cmd, "--tolerance", args->tolerance,
             "relative t tolerance: |tA - tB| <= tol * max(1, tA); with --rays in world space: "
             "|tA - tB| |d| <= tol * max(1, |o|, |hit point|) (|d| the direction's length, |o| and |hit point| "
             "their largest coordinate; the hit point is A's). 0 = bit-identical: same "
             "triangle (no ties), t, u and v, and no grazing contact excused (as --strict)", 0.0f);
  cmd->add_option("--rays", args->rays,
                  "the RAYS file both were traced from: judge distances in world space, where float "
                  "coordinates have their precision (a hit near the origin far from the world origin)")
      ->check(file_path());
  add_number(*cmd, "--edge-eps", args->edge_eps,
             "without --scene: a hit with a barycentric <= this is a grazing (edge/vertex) contact", 0.0f, 1.0f);
  cmd->add_option("--scene", args->scene,
                  "the scene both files were traced against (with --rays): a contact is grazing when float "
                  "arithmetic cannot decide it, judged from its triangle in world units (see --ulps) instead of "
                  "--edge-eps, so a tiny triangle or a ray nearly in a triangle's plane is judged fairly");
  add_number(*cmd, "--ulps", args->ulps,
             "with --scene: the tracers' precision in float ulps (2^-24) of the largest coordinate of the ray's "
             "origin and the triangle's vertices; a contact is grazing when the ray passes an edge by less (in "
             "the plane, times the cosine of the incidence angle), an end of the segment lies that close to the "
             "plane, or two hit points lie that close to each other's planes",
             0.0f, 1e6f);
  cmd->add_option("--hits-a", args->hits_a,
                  "OCCL only: A's closest hits (HITS file) of the same rays, so that a disagreement whose "
                  "blocker is a grazing contact is not counted")->check(file_path());
  cmd->add_option("--hits-b", args->hits_b, "OCCL only: B's closest hits of the same rays")->check(file_path());
  add_number(*cmd, "--max-grazing", args->max_grazing,
             "largest share of the rays whose disagreement a grazing contact may excuse; above it the "
             "files differ (a tracer reporting t = 0 or u = v = 0 would otherwise excuse itself)", 0.0f, 1.0f);
  cmd->add_flag("--strict", args->strict, "count disagreements at grazing contacts as errors too");
  cmd->callback([args, cmd] {
    for (const char* option : {"--tolerance", "--edge-eps", "--scene", "--ulps", "--max-grazing", "--strict"})
      if (cmd->count(option) > 0) args->hit_options.push_back(option);
    args->edge_eps_given = cmd->count("--edge-eps") > 0;
    args->ulps_given = cmd->count("--ulps") > 0;
    if (!compare_files(*args)) throw CLI::RuntimeError(1);
  });
}};

}  // namespace
}  // namespace rayscout::cli
