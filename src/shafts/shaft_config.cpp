// ShaftConfig: reading --accel-opt keys, the rules of valid values, the automatic values.
#include "rayscout/shafts/shaft_config.h"

#include <climits>
#include <sstream>
#include <string>

namespace rayscout {

namespace {

[[noreturn]] void bad(const std::string& what) { throw InputError("shafts option " + what); }

std::string format_value(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

void ShaftConfig::validate() const {
  auto range = [](const char* key, long value, long lo, long hi) {
    if (value < lo || value > hi)
      bad(std::string(key) + " must be in " + std::to_string(lo) + ".." + std::to_string(hi) + " (got " +
          std::to_string(value) + ")");
  };
  // Written so that NaN fails too.
  auto real_range = [](const char* key, double value, double lo, double hi) {
    if (!(value >= lo && value <= hi))
      bad(std::string(key) + " must be in [" + format_value(lo) + ", " + format_value(hi) + "] (got " +
          format_value(value) + ")");
  };
  real_range("budget_mib", budget_mib, 0.0, 4096.0);
  if (!(budget_rel > 0 && budget_rel <= 64))
    bad("budget_rel must be in (0, 64] (got " + format_value(budget_rel) + ")");
  range("voxels", voxels, 0, 1L << 28);
  range("dir_res", dir_res, 1, 64);
  real_range("min_prob", min_prob, -1.0, 1.0);
  range("max_list", max_list, 1, 31);  // the length is packed into 5 bits
  range("walk_levels", walk_levels, 1, 4);
  range("near_retries", near_retries, 0, 16);
  range("retries", retries, 0, 1000);
  range("prepass_width", prepass_width, 1, 1 << 14);
  if (samples) range("samples", *samples, 1, 1000);
  if (stratified && samples && *samples > 256) bad("samples must be <= 256 with stratified=1");
  if (!(coverage > 0 && coverage <= 1)) bad("coverage must be in (0, 1]");
}

ShaftConfig ShaftConfig::resolved(int arity) const {
  validate();
  const bool binary = arity == 2;
  ShaftConfig c = *this;
  if (!c.samples) c.samples = binary ? 4 : 3;
  if (!c.reuse_rays) c.reuse_rays = !binary;
  if (!c.entry_boxes) c.entry_boxes = !binary;
  if (c.min_prob < 0.0) c.min_prob = double(arity - 1) / arity;
  return c;
}

ShaftConfig ShaftConfig::from_options(const AcceleratorOptions& o, int arity) {
  ShaftConfig c;
  // The ranges of get_* only guard the reading (no narrowing cast wraps); validate() decides.
  auto is_auto = [&](const std::string& key) { return !o.has(key) || o.get_string(key, "") == "auto"; };
  c.budget_mib = o.get_double("budget_mib", c.budget_mib, 0.0, 4096.0);
  c.budget_rel = o.get_double("budget_rel", c.budget_rel, 0.0, 64.0);
  c.voxels = o.get_int("voxels", c.voxels, 0, 1L << 28);
  c.dir_res = int(o.get_int("dir_res", c.dir_res, 1, 64));
  if (!is_auto("samples")) {
    const long n = o.get_int("samples", -1, -1, 1000);
    if (n != -1) c.samples = int(n);  // -1 means auto too
  }
  c.stratified = o.get_bool("stratified", c.stratified);
  c.origins = o.get_choice("origins", c.origins, {{"volume", SampleOrigins::Volume}, {"surface", SampleOrigins::Surface}});
  if (!is_auto("reuse_rays")) c.reuse_rays = o.get_bool("reuse_rays", false);
  c.min_prob = o.get_double("min_prob", c.min_prob, -1.0, 1.0);
  c.max_list = int(o.get_int("max_list", c.max_list, 1, 31));
  c.near_retries = int(o.get_int("near_retries", c.near_retries, 0, 16));
  c.retries = int(o.get_int("retries", c.retries, 0, 1000));
  c.select = o.get_choice("select", c.select,
                          {{"occupied", ShaftSelect::Occupied}, {"camera", ShaftSelect::Camera},
                           {"camera-voxels", ShaftSelect::CameraVoxels}});
  c.coverage = o.get_double("coverage", c.coverage);
  c.prepass_width = int(o.get_int("prepass_width", c.prepass_width, 1, 1 << 14));
  c.seed = unsigned(o.get_int("seed", c.seed, 0, UINT_MAX));
  c.dedup = o.get_bool("dedup", c.dedup);
  if (arity == 2) {
    // Not "collapse": that key is the wide BVH's collapse method (greedy or sah).
    c.walk_levels = int(o.get_int("walk_levels", c.walk_levels, 1, 4));
    c.wide_sampling = o.get_bool("wide_sampling", c.wide_sampling);
  }
  if (!is_auto("entry_boxes")) c.entry_boxes = o.get_bool("entry_boxes", false);
  c.validate();
  return c;
}

}  // namespace rayscout
