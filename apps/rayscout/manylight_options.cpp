// Options of `rayscout render --integrator manylight`: parsed into statics that
// make_manylight_cli_integrator() reads after parsing.
#include "manylight_options.h"

#include <limits>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "commands.h"
#include "rayscout/manylight/probabilistic_visibility.h"
#include "rayscout/manylight/visibility_cluster.h"

namespace rayscout::cli {
namespace {

/// The manylight options as parsed.
ManylightRunOptions& parsed_options() {
  static ManylightRunOptions options;
  return options;
}

/// The values of --visibility.
std::vector<std::string> visibility_mode_names() {
  std::vector<std::string> names;
  for (const auto& [name, mode] : kVisibilityModes) names.push_back(name);
  return names;
}

/// The --visibility string as parsed.
std::string& parsed_visibility() {
  static std::string visibility = "proposed";
  return visibility;
}

/// The --costs values as parsed (microseconds per VPL sample with / without its shadow ray).
std::vector<double>& parsed_costs() {
  static std::vector<double> costs;
  return costs;
}

}  // namespace

const ManylightRunOptions& manylight_cli_options() { return parsed_options(); }

void add_manylight_options(CLI::App& cmd) {
  ManylightRunOptions& o = parsed_options();
  ManylightConfig& c = o.config;
  add_number(cmd, "--vpls", c.vpl_count,
             "manylight: VPLs to make, at least this many (whole light paths are kept, so a few more)", 1, 4294967295);
  cmd.add_option("--visibility", parsed_visibility(),
                 "manylight: which shadow rays may be skipped: exact (none), veach (by contribution alone; a "
                 "skipped ray counts as occluded), conservative or proposed (by contribution and the cluster pair's "
                 "visibility r, which a skipped ray counts as; docs/manylight.md)")
      ->capture_default_str()
      ->check(CLI::IsMember(visibility_mode_names()));
  add_number(cmd, "--time-budget", o.time_budget, "manylight: seconds of progressive rendering (0 = --passes)", 0.0);
  // At most INT_MAX: the progress line counts passes in an int (2^32 + 1 showed 'pass 2/1').
  add_number(cmd, "--passes", o.passes, "manylight: passes when there is no time budget", 1,
             size_t(std::numeric_limits<int>::max()));
  add_number(cmd, "--vpl-samples", c.samples_per_pass, "manylight: VPL samples per shading point per pass", 1);
  cmd.add_option("--pass-seed", o.pass_seed,
                 "manylight: seed of the render passes only (default: --seed, which also makes the VPLs and shading "
                 "points); render a --reference with another one, so that its noise is independent of the run's")
      ->transform(in_range<uint64_t>(0));
  cmd.add_option("--reference", o.reference, "manylight: reference image (.exr/.pfm); RMSE after every pass")
      ->check(file_path());
  cmd.add_option("--rmse-log", o.rmse_log, "manylight: write RMSE over time (.json or .csv)")
      ->check(output_file_path());
  cmd.add_option("--skip-image", o.skip_image, "manylight: write the per-pixel skip rate (white = skipped)")
      ->check(output_file_path());
  add_number(cmd, "--epsilon", c.epsilon, "manylight: floor of (v - r)^2 in proposed", 0.0f);
  add_number(cmd, "--clamp-distance", c.clamp_distance, "manylight: geometry-term clamp distance (0 = off)", 0.0f);
  add_number(cmd, "--shading-clusters", c.shading_clusters,
             "manylight: shading-point clusters, rounded up to a power of two, at most the shading points", 1);
  add_number(cmd, "--vpl-clusters", c.vpl_clusters,
             "manylight: VPL clusters, rounded up to a power of two, at most the VPLs", 1);
  add_number(cmd, "--visibility-samples", c.visibility_samples, "manylight: shadow rays per cluster pair", 1,
             kMaxPairSamples);
  cmd.add_flag("--cpu-clock", c.cpu_clock, "manylight: time budget and calibration in process CPU time");
  cmd.add_option("--costs", parsed_costs(),
                 "manylight: EVAL,SKIP microseconds per VPL sample with / without its shadow ray, instead of "
                 "measuring them (a run prints both); fixed costs make the skipping modes repeatable")
      ->expected(2)
      ->delimiter(',')
      ->transform(in_range(0.001));
}

void warn_unread_manylight_options(const CLI::App& group) {
  const ManylightRunOptions& o = parsed_options();
  const std::string& visibility = parsed_visibility();
  const VisibilityMode mode = parse_visibility_mode(visibility);
  const std::vector<double>& costs = parsed_costs();
  auto warn = [](const std::string& text) { fmt::print(stderr, "rayscout: warning: {}\n", text); };
  if (!o.rmse_log.empty() && o.reference.empty())
    warn("--rmse-log without --reference logs passes and skip rates only (rmse -1)");
  if (group.count("--passes") > 0 && o.time_budget > 0)
    warn("--passes is ignored with --time-budget (passes run until the budget is spent)");
  if (group.count("--epsilon") > 0 && mode != VisibilityMode::Proposed)
    warn("--epsilon is ignored by --visibility " + visibility + " (only proposed floors (v - r)^2 with it)");
  if (costs.size() == 2 && mode == VisibilityMode::Exact)
    warn("--costs is ignored by --visibility exact, which never skips a shadow ray");
  else if (costs.size() == 2 && costs[0] <= costs[1])  // t_hat of eq. (16) is 0: q = 0 for every sample
    warn(fmt::format("--costs {:g},{:g}: a sample costs no more with its shadow ray than without it: skipping saves "
                     "nothing, and --visibility {} traces every sample as exact does (EVAL comes first)",
                     costs[0], costs[1], visibility));
}

const IntegratorOptionGroup kManylightOptions = {add_manylight_options, warn_unread_manylight_options};

// Measured sizes, rounded up: the renderer keeps ~130 bytes per shading point of the whole image
// (--max-batch does not split it), ~100 per VPL (the light, its cluster records), ~40 per pair
// of shading and VPL clusters (the pair's sample counts and sums, 20; its r, weight and id, 12;
// its unit of the row's distribution, 8: 655 MB measured for 2048 x 8192 pairs), and ~110 per
// VPL sample of a wavefront round (its sample record and shadow ray; a round takes 16 points of
// every shading cluster). Cluster counts are rounded up to a power of two, as cluster_points
// does (--shading-clusters 600 makes 1024), and are at most the points and VPLs.
// `--vpls 4294967295` asked for ~430 GB.
IntegratorMemory manylight_memory(const RenderConfig& c) {
  const ManylightConfig& m = parsed_options().config;
  const double points = double(c.width) * double(c.height) * double(c.spp);
  const double vpls = double(m.vpl_count);
  const double shading_clusters = double(cluster_count(size_t(points), m.shading_clusters));
  const double pairs = shading_clusters * double(cluster_count(size_t(vpls), m.vpl_clusters));
  const double round = shading_clusters * double(m.points_per_round) * double(m.samples_per_pass);
  return {130.0 * points + 100.0 * vpls + 40.0 * pairs + 110.0 * round,
          fmt::format("; manylight: --vpls {} at ~100 bytes, {:.0f} cluster pairs (--shading-clusters x --vpl-clusters) "
                      "at ~40 bytes, {:.0f} VPL samples a round (--vpl-samples) at ~110 bytes, {:.0f} shading points "
                      "at ~130 bytes",
                      m.vpl_count, pairs, round, points)};
}

std::unique_ptr<Integrator> make_manylight_cli_integrator() {
  ManylightRunOptions o = parsed_options();
  o.config.mode = parse_visibility_mode(parsed_visibility());
  if (const auto& costs = parsed_costs(); costs.size() == 2) {
    o.config.t_eval = costs[0] * 1e-6;
    o.config.t_skip = costs[1] * 1e-6;
  }
  if (const std::string w = epsilon_bias_warning(o.config.mode, o.config.epsilon); !w.empty())
    fmt::print(stderr, "rayscout: warning: {}\n", w);
  return make_manylight_integrator(o);
}

}  // namespace rayscout::cli
