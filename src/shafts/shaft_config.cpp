// ShaftConfig: reading --accel-opt keys.
#include "rayscout/shafts/shaft_config.h"

namespace rayscout {

ShaftConfig ShaftConfig::from_options(const AcceleratorOptions& o) {
  ShaftConfig c;
  c.budget_mib = o.get_double("budget_mib", c.budget_mib);
  c.budget_rel = o.get_double("budget_rel", c.budget_rel);
  c.voxels = o.get_int("voxels", c.voxels);
  c.dir_res = int(o.get_int("dir_res", c.dir_res));
  c.samples = int(o.get_int("samples", c.samples));
  c.stratified = o.get_bool("stratified", c.stratified);
  if (o.has("reuse_rays")) c.reuse_rays = o.get_bool("reuse_rays", false) ? 1 : 0;
  else o.get_bool("reuse_rays", false);  // marks the key as known
  c.min_prob = o.get_double("min_prob", c.min_prob);
  c.max_list = int(o.get_int("max_list", c.max_list));
  c.retries = int(o.get_int("retries", c.retries));
  c.select = o.get_string("select", c.select);
  c.coverage = o.get_double("coverage", c.coverage);
  c.prepass_width = int(o.get_int("prepass_width", c.prepass_width));
  c.seed = unsigned(o.get_int("seed", c.seed));
  c.collapse = int(o.get_int("collapse", c.collapse));
  c.wide_sampling = o.get_bool("wide_sampling", c.wide_sampling);
  if (o.has("entry_boxes")) c.entry_boxes = o.get_bool("entry_boxes", false) ? 1 : 0;
  else o.get_bool("entry_boxes", false);  // marks the key as known
  auto bad = [](const std::string& what) { throw InputError("shafts option " + what); };
  if (c.budget_mib < 0) bad("budget_mib must be >= 0");
  if (!(c.budget_rel > 0)) bad("budget_rel must be > 0");
  if (c.voxels < 0) bad("voxels must be >= 0");
  if (c.dir_res < 1 || c.dir_res > 64) bad("dir_res must be in 1..64");
  if (c.samples != -1 && (c.samples < 1 || c.samples > 1000)) bad("samples must be in 1..1000 (or -1 = auto)");
  if (c.stratified && c.samples > 256) bad("samples must be <= 256 with stratified=1");
  if (c.max_list < 1 || c.max_list > 31) bad("max_list must be in 1..31");
  if (c.retries < 0) bad("retries must be >= 0");
  if (c.collapse < 1 || c.collapse > 4) bad("collapse must be in 1..4");
  if (c.select != "occupied" && c.select != "camera") bad("select must be occupied or camera");
  if (!(c.coverage > 0 && c.coverage <= 1)) bad("coverage must be in (0, 1]");
  if (c.prepass_width < 1) bad("prepass_width must be >= 1");
  return c;
}

}  // namespace rayscout
