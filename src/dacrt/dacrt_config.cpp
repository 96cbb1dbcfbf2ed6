// DacrtConfig: option parsing and validation.
#include "rayscout/dacrt/dacrt_config.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

namespace rayscout {
namespace {

/// Values of option `order`: Afra's one-ray rule (no votes), or the sampled child order with
/// its vote rule.
using OrderRule = std::optional<DacrtVotes>;
constexpr std::pair<const char*, OrderRule> kOrderNames[] = {{"one-ray", std::nullopt},
                                                             {"sampled", DacrtVotes::Entry},
                                                             {"literal-votes", DacrtVotes::Literal},
                                                             {"sign-votes", DacrtVotes::Sign},
                                                             {"interval-votes", DacrtVotes::Interval}};

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("dacrt option " + what);
}

}  // namespace

size_t DacrtConfig::sample_count(size_t n) const {
  size_t ns = fraction > 0.0 ? size_t(std::max(1.0, std::round(fraction * double(n)))) : size_t(samples);
  return std::max<size_t>(1, std::min(ns, n));
}

double DacrtConfig::skip_threshold(size_t child_tris) const {
  const bool leaf = child_tris < delta_t;
  const double c_child = leaf ? c_tri : c_bv;
  const double n_child = leaf ? double(child_tris) : 2.0;
  return 1.0 - c_bv / (c_child * n_child);
}

DacrtConfig DacrtConfig::from_options(const AcceleratorOptions& o, DacrtConfig c) {
  c.sampled_cost = o.get_choice("cost", c.sampled_cost, {{"sampled", true}, {"sah", false}});
  const OrderRule order =
      o.get_choice<OrderRule>("order", c.sampled_order ? OrderRule(c.votes) : std::nullopt, kOrderNames);
  c.sampled_order = order.has_value();
  if (order) c.votes = *order;
  c.depth_weighted_votes = o.get_choice("vote_weight", c.depth_weighted_votes, {{"depth", true}, {"none", false}});
  c.skip_partitioning = o.get_bool("skip", c.skip_partitioning);
  c.resample_second = o.get_bool("resample", c.resample_second);
  c.strategy = o.get_choice("strategy", c.strategy, {{"random", DacrtSampling::Random}, {"stride", DacrtSampling::Stride}});
  c.samples = int(o.get_int("samples", c.samples, 1, INT_MAX));
  c.fraction = o.get_double("fraction", c.fraction, 0.0, 1.0);
  c.min_rays_sampling = size_t(o.get_int("min_rays", long(c.min_rays_sampling), 0, LONG_MAX));
  c.sample_budget = o.get_double("sample_budget", c.sample_budget);
  c.seed = uint64_t(o.get_int("seed", long(c.seed)));
  c.delta_r = size_t(o.get_int("delta_r", long(c.delta_r), 1, LONG_MAX));
  c.delta_t = size_t(o.get_int("delta_t", long(c.delta_t), 2, LONG_MAX));
  c.bins = int(o.get_int("bins", c.bins, 2, 256));
  c.midpoint_ratio = o.get_double("midpoint_ratio", c.midpoint_ratio);
  c.c_bv = o.get_double("C_bv", c.c_bv);
  c.c_tri = o.get_double("C_tri", c.c_tri);
  c.parallel = o.get_bool("parallel", c.parallel);
  c.validate();
  return c;
}

void DacrtConfig::validate() const {
  // Each written so that NaN fails too.
  require(bins >= 2 && bins <= 256, "bins: must be in [2, 256] (got " + std::to_string(bins) + ")");
  require(samples >= 1, "samples: must be >= 1 (got " + std::to_string(samples) + ")");
  require(fraction >= 0.0 && fraction <= 1.0, "fraction: must be in [0, 1]");
  require(delta_r >= 1, "delta_r: must be >= 1");
  require(delta_t >= 2, "delta_t: must be >= 2");
  require(sample_budget >= 0.0, "sample_budget: must be >= 0");
  require(midpoint_ratio >= 0.0, "midpoint_ratio: must be >= 0");
  require(c_bv > 0 && c_tri > 0, "C_bv, C_tri > 0 required");
}

std::string DacrtConfig::order_name() const {
  const OrderRule rule = sampled_order ? OrderRule(votes) : std::nullopt;
  for (const auto& [name, named_rule] : kOrderNames)
    if (named_rule == rule) return name;
  return "sampled";
}

std::string DacrtConfig::describe() const {
  std::ostringstream s;
  s << "cost=" << (sampled_cost ? "sampled" : "sah") << " order=" << order_name()
    << " vote_weight=" << (depth_weighted_votes ? "depth" : "none")
    << " skip=" << (skip_partitioning ? "on" : "off")
    << " resample=" << (resample_second ? "on" : "off")
    << " strategy=" << (strategy == DacrtSampling::Stride ? "stride" : "random");
  if (fraction > 0) s << " fraction=" << fraction; else s << " samples=" << samples;
  s << " min_rays=" << min_rays_sampling << " sample_budget=" << sample_budget << " delta_r=" << delta_r << " delta_t=" << delta_t << " bins=" << bins
    << " midpoint_ratio=" << midpoint_ratio << " C_bv=" << c_bv
    << " C_tri=" << c_tri << " parallel=" << (parallel ? "on" : "off");
  return s.str();
}

}  // namespace rayscout
