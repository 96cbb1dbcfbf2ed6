// ShaftConfig: reading --accel-opt keys.
#include "rayscout/shafts/shaft_config.h"

#include <climits>

namespace rayscout {

ShaftConfig ShaftConfig::from_options(const AcceleratorOptions& o, int arity) {
  ShaftConfig c;
  // "auto" (or leaving the key out) keeps -1: resolved() picks the value for the BVH's arity.
  auto is_auto = [&](const std::string& key) { return o.get_string(key, "") == "auto"; };
  c.budget_mib = o.get_double("budget_mib", c.budget_mib, 0.0, 4096.0);
  c.budget_rel = o.get_double("budget_rel", c.budget_rel, 0.0, 64.0);
  c.voxels = o.get_int("voxels", c.voxels, 0, 1L << 28);
  c.dir_res = int(o.get_int("dir_res", c.dir_res, 1, 64));
  if (!is_auto("samples")) c.samples = int(o.get_int("samples", c.samples, -1, 1000));
  c.stratified = o.get_bool("stratified", c.stratified);
  if (o.has("reuse_rays") && !is_auto("reuse_rays")) c.reuse_rays = o.get_bool("reuse_rays", false) ? 1 : 0;
  c.min_prob = o.get_double("min_prob", c.min_prob, -1.0, 1.0);
  c.max_list = int(o.get_int("max_list", c.max_list, 1, 31));
  c.retries = int(o.get_int("retries", c.retries, 0, 1000));
  c.select = o.get_string("select", c.select);
  c.coverage = o.get_double("coverage", c.coverage);
  c.prepass_width = int(o.get_int("prepass_width", c.prepass_width, 1, 1 << 14));
  c.seed = unsigned(o.get_int("seed", c.seed, 0, UINT_MAX));
  c.dedup = o.get_bool("dedup", c.dedup);
  if (arity == 2) {
    // Not "collapse": that key is the wide BVH's collapse method (greedy or sah).
    c.collapse = int(o.get_int("walk_levels", c.collapse, 1, 4));
    c.wide_sampling = o.get_bool("wide_sampling", c.wide_sampling);
  }
  if (o.has("entry_boxes") && !is_auto("entry_boxes")) c.entry_boxes = o.get_bool("entry_boxes", false) ? 1 : 0;
  auto bad = [](const std::string& what) { throw InputError("shafts option " + what); };
  if (!(c.budget_rel > 0)) bad("budget_rel must be > 0");
  if (c.samples != -1 && c.samples < 1) bad("samples must be in 1..1000 (or auto)");
  if (c.stratified && c.samples > 256) bad("samples must be <= 256 with stratified=1");
  if (c.select != "occupied" && c.select != "camera") bad("select must be occupied or camera");
  if (!(c.coverage > 0 && c.coverage <= 1)) bad("coverage must be in (0, 1]");
  return c;
}

}  // namespace rayscout
