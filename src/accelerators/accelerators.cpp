// The accelerator registry: the one place that knows every accelerator module.
#include "rayscout/accelerators.h"

#include <functional>

#include "rayscout/dacrt/dacrt.h"

#include "rayscout/bvh/bvh_accelerators.h"
#include "rayscout/shafts/shafts_accelerator.h"

#if RAYSCOUT_WITH_EMBREE
#include "rayscout/embree/embree_accelerator.h"
#endif

namespace rayscout {
namespace {

// A factory reads its options first and returns the build as a step of its own, so that a
// misspelt option is reported before a build that may take seconds, not after it.
using Build = std::function<std::unique_ptr<Accelerator>()>;
using Factory = std::function<Build(const Scene&, const AcceleratorOptions&)>;

struct Entry {
  AcceleratorInfo info;
  Factory make;
};

const std::vector<Entry>& registry() {
  static const std::vector<Entry> entries = {
      {{"brute", "every ray against every triangle (reference)"},
       [](const Scene& s, const AcceleratorOptions&) -> Build {
         return [&s] { return std::make_unique<BruteForce>(s.triangles); };
       }},
      {{"dacrt", "divide-and-conquer ray tracing, Afra 2012 (no stored hierarchy; options in docs/dacrt.md)"},
       [](const Scene& s, const AcceleratorOptions& o) -> Build {
         return [&s, c = DacrtConfig::from_options(o, DacrtConfig::afra())] {
           return std::make_unique<DacrtAccelerator>(s.triangles, c, "dacrt");
         };
       }},
      {{"dacrt-rs", "ray-sampled DACRT, Nabata et al. 2014 (sampled cost, order, skipping; docs/dacrt.md)"},
       [](const Scene& s, const AcceleratorOptions& o) -> Build {
         return [&s, c = DacrtConfig::from_options(o, DacrtConfig::ray_sampled())] {
           return std::make_unique<DacrtAccelerator>(s.triangles, c, "dacrt-rs");
         };
       }},
      {{"bvh2", "binary binned-SAH BVH, scalar single-ray traversal (options bins, max_leaf_size, traversal_cost, intersection_cost, leaf_block, presplit, presplit_pieces)"},
       [](const Scene& s, const AcceleratorOptions& o) -> Build {
         return [&s, c = bvh_config_from_options(o)] { return std::make_unique<Bvh2Accelerator>(s.triangles, c); };
       }},
      {{"bvh", "8-wide BVH collapsed from binned SAH, SIMD single-ray traversal (options as bvh2, plus collapse=greedy|sah, collapse_node_cost, collapse_leaf_cost, collapse_block_cost, collapse_max_leaf)"},
       [](const Scene& s, const AcceleratorOptions& o) -> Build {
         return [&s, c = wide_bvh_config_from_options(o)] { return std::make_unique<WideBvhAccelerator>(s.triangles, c); };
       }},
      {{"shafts", "ray classification, Hendrich et al. 2019: shaft candidate lists seed the binary BVH (options in docs/shafts.md)"},
       [](const Scene& s, const AcceleratorOptions& o) -> Build {
         return [&s, set = ShaftsAccelerator::settings_from_options(o, ShaftsAccelerator::Base::Binary)] {
           return std::make_unique<ShaftsAccelerator>(s, ShaftsAccelerator::Base::Binary, set.shafts, set.bvh);
         };
       }},
      {{"shafts-wide", "ray classification over the 8-wide BVH, min hit probability 7/8 (options in docs/shafts.md)"},
       [](const Scene& s, const AcceleratorOptions& o) -> Build {
         return [&s, set = ShaftsAccelerator::settings_from_options(o, ShaftsAccelerator::Base::Wide)] {
           return std::make_unique<ShaftsAccelerator>(s, ShaftsAccelerator::Base::Wide, set.shafts, set.bvh);
         };
       }},
#if RAYSCOUT_WITH_EMBREE
      {{"embree", "Intel Embree 3, high-quality build, robust mode (peer; options robust, quality, packet)"},
       [](const Scene& s, const AcceleratorOptions& o) -> Build {
         return [&s, c = EmbreeConfig::from_options(o)] { return std::make_unique<EmbreeAccelerator>(s.triangles, c); };
       }},
#endif
  };
  return entries;
}

}  // namespace

const std::vector<AcceleratorInfo>& accelerators() {
  static const std::vector<AcceleratorInfo> infos = [] {
    std::vector<AcceleratorInfo> v;
    for (const auto& e : registry()) v.push_back(e.info);
    return v;
  }();
  return infos;
}

namespace {

// The options read into a build that has not run yet; throws InputError for an unknown name
// or an option the accelerator does not have. Read from a copy that has read nothing yet:
// keys another accelerator read from the caller's object would otherwise pass as this one's.
Build prepare(const std::string& name, const Scene& scene, const AcceleratorOptions& options) {
  for (const auto& e : registry()) {
    if (e.info.name != name) continue;
    const AcceleratorOptions unread = options.unread();
    Build build = e.make(scene, unread);
    unread.check_all_used(name);
    return build;
  }
  std::string known;
  for (const auto& e : registry()) known += (known.empty() ? "" : ", ") + e.info.name;
#if !RAYSCOUT_WITH_EMBREE
  if (name == "embree")
    throw InputError("accelerator 'embree' is not in this build (configured with -DRAYSCOUT_WITH_EMBREE=OFF; known: " +
                     known + ")");
#endif
  throw InputError("unknown accelerator '" + name + "' (known: " + known + ")");
}

}  // namespace

void check_accelerator(const std::string& name, const AcceleratorOptions& options) {
  const Scene none;
  prepare(name, none, options);  // the build it returns never runs
}

std::unique_ptr<Accelerator> make_accelerator(const std::string& name, const Scene& scene,
                                              const AcceleratorOptions& options) {
  return prepare(name, scene, options)();
}

}  // namespace rayscout
