// `rayscout compare-hits A B`: ray-by-ray agreement of two HITS (or two OCCL) files.
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "commands.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/hit_compare.h"
#include "rayscout/core/ray_file.h"

namespace rayscout::cli {
namespace {

struct CompareArgs {
  std::string a, b, rays, hits_a, hits_b;
  float tolerance = 1e-4f;
  float edge_eps = 1e-4f;
  float max_grazing = 0.01f;
  bool strict = false;
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

// Returns true when the files agree within the tolerance.
bool compare_files(const CompareArgs& args) {
  const ResultFile fa = read_results(args.a), fb = read_results(args.b);
  if (fa.kind != fb.kind) throw InputError(args.a + " and " + args.b + ": one is a HITS file, the other an OCCL file");
  const bool occl = fa.kind == RayFileKind::Occlusion;
  if (!occl && (!args.hits_a.empty() || !args.hits_b.empty()))
    throw InputError("--hits-a and --hits-b are for OCCL files; " + args.a + " is a HITS file");
  if (args.hits_a.empty() != args.hits_b.empty()) throw InputError("--hits-a and --hits-b go together");
  HitCompareConfig cfg;
  cfg.rel_tol = args.tolerance;
  cfg.allow_grazing = !args.strict;
  cfg.edge_eps = args.edge_eps;
  RayBatch rays;
  if (!args.rays.empty()) {
    rays = read_rays(args.rays);
    cfg.rays = &rays;
  }

  // Every file of a comparison describes the same rays, as many as A (or the RAYS file).
  const size_t n = cfg.rays ? rays.size() : occl ? fa.occluded.size() : fa.hits.size();
  const std::string& first = cfg.rays ? args.rays : args.a;
  auto check_size = [&](size_t size, const std::string& file, const char* what) {
    if (size != n)
      throw InputError(first + ": " + std::to_string(n) + (cfg.rays ? " rays" : occl ? " results" : " hits") + ", but " + file +
                       " holds " + std::to_string(size) + " " + what);
  };
  if (occl) {
    HitBatch ha, hb;
    if (!args.hits_a.empty()) {
      ha = read_hits(args.hits_a);
      hb = read_hits(args.hits_b);
    }
    const bool with_hits = !args.hits_a.empty();
    const std::vector<uint8_t>&oa = fa.occluded, &ob = fb.occluded;
    check_size(oa.size(), args.a, "results");
    check_size(ob.size(), args.b, "results");
    if (with_hits) {
      check_size(ha.size(), args.hits_a, "hits");
      check_size(hb.size(), args.hits_b, "hits");
    }
    const OcclusionDiff d = compare_occlusion(oa, ob, cfg, with_hits ? &ha : nullptr, with_hits ? &hb : nullptr);
    fmt::print("rays:                  {}\n", d.rays);
    fmt::print("occluded:              {} in A, {} in B\n", d.occluded_ref, d.occluded_got);
    fmt::print("disagreements:         {}\n", d.differ);
    if (with_hits && cfg.excuses_grazing())
      fmt::print("grazing contacts:      {} (the occluded side's closest hit is grazing; not counted)\n", d.grazing);
    if (!d.first.empty()) fmt::print("first:                 {}\n", d.first);
    const bool ok = grazing_within_bound(d.grazing, d.rays, args) && d.ok();
    fmt::print("result:                {}\n", ok ? "OK" : "DIFFERENT");
    return ok;
  }
  const HitBatch &ha = fa.hits, &hb = fb.hits;
  check_size(ha.size(), args.a, "hits");
  check_size(hb.size(), args.b, "hits");
  const HitDiff d = compare_hits(ha, hb, cfg);
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
             !cfg.excuses_grazing() ? "" : fmt::format(" (edge/vertex within {:g} barycentric or t ~ 0; not counted)", cfg.edge_eps));
  fmt::print("t beyond tolerance:    {}\n", d.t_mismatch);
  if (args.tolerance == 0) fmt::print("u, v not identical:    {}\n", d.uv_mismatch);
  fmt::print("t rel. difference:     max {:.3e}, 99th percentile {:.3e} ({})\n", d.max_rel_diff, d.p99_rel_diff,
             cfg.rays ? "world space: |dt| |d| / max(1, |o|, |hit point|)" : "|dt| / max(1, t_A)");
  if (!d.first.empty()) fmt::print("first:                 {}\n", d.first);
  const bool ok = grazing_within_bound(d.grazing, d.rays, args) && d.ok();
  fmt::print("result:                {} (tolerance {:g})\n", ok ? "OK" : "DIFFERENT", args.tolerance);
  return ok;
}

CommandRegistration registration{[](CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  auto* cmd = app.add_subcommand(
      "compare-hits", "Compare two HITS (or two OCCL) files ray by ray; exit 1 when they differ beyond the tolerance");
  set_memory_hint(*cmd, "compare smaller files");
  cmd->add_option("A", args->a, "reference HITS or OCCL file")->required();
  cmd->add_option("B", args->b, "candidate file of the same kind")->required();
  cmd->add_option("--tolerance", args->tolerance,
                  "relative t tolerance: |tA - tB| <= tol * max(1, tA); with --rays in world space: "
                  "|tA - tB| |d| <= tol * max(1, |o|, |hit point|) (max norms). 0 = bit-identical: same "
                  "triangle (no ties), t, u and v, and no grazing contact excused (as --strict)")
      ->capture_default_str()
      ->transform(in_range(0.0f));
  cmd->add_option("--rays", args->rays,
                  "the RAYS file both were traced from: judge distances in world space, where float "
                  "coordinates have their precision (a hit near the origin far from the world origin)");
  cmd->add_option("--edge-eps", args->edge_eps,
                  "a hit with a barycentric <= this is a grazing (edge/vertex) contact")
      ->capture_default_str()
      ->transform(in_range(0.0f, 1.0f));
  cmd->add_option("--hits-a", args->hits_a,
                  "OCCL only: A's closest hits (HITS file) of the same rays, so that a disagreement whose "
                  "blocker is a grazing contact is not counted");
  cmd->add_option("--hits-b", args->hits_b, "OCCL only: B's closest hits of the same rays");
  cmd->add_option("--max-grazing", args->max_grazing,
                  "largest share of the rays whose disagreement a grazing contact may excuse; above it the "
                  "files differ (a tracer reporting t = 0 or u = v = 0 would otherwise excuse itself)")
      ->capture_default_str()
      ->transform(in_range(0.0f, 1.0f));
  cmd->add_flag("--strict", args->strict, "count disagreements at grazing contacts as errors too");
  cmd->callback([args] {
    if (!compare_files(*args)) throw CLI::RuntimeError(1);
  });
}};

}  // namespace
}  // namespace rayscout::cli
