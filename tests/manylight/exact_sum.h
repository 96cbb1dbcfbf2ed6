// Eq. (1) of the many-light renderer summed over every VPL with exact visibility: the value the
// renderer's estimate converges to, for one set of VPLs and shading points.
#pragma once

#include <vector>

#include "rayscout/core/accelerator.h"
#include "rayscout/manylight/channel_mean.h"
#include "rayscout/render/bsdf.h"
#include "rayscout/manylight/shading_points.h"
#include "rayscout/manylight/visibility_cluster.h"
#include "rayscout/manylight/vpl.h"

namespace rayscout::testing {

/// Per pixel (width * height) emission seen plus sp.weight times the visible VPLs' tentative
/// contributions, every shading point and VPL, shadow rays in one batch per point.
inline std::vector<Vec3> exact_sum(const Scene& scene, const Accelerator& accel, const std::vector<ShadingPoint>& points,
                                   const std::vector<Vpl>& vpls, int width, int height, float clamp_distance) {
  const float offset = 1e-4f * length(scene.bounds().diagonal());
  std::vector<Vec3> img(size_t(width) * height, Vec3(0.0f));
  RayBatch rays;
  std::vector<Vec3> t;
  std::vector<uint8_t> occ;
  for (const ShadingPoint& sp : points) {
    img[sp.pixel] += sp.emitted;
    if (!sp.valid()) continue;
    rays.clear();
    t.clear();
    for (const Vpl& v : vpls) {
      const Vec3 c = tentative_contribution(scene, sp, v, clamp_distance);
      if (max_component(c) <= 0.0f) continue;
      t.push_back(c);
      rays.push_back(shadow_ray(sp, v, offset));
    }
    accel.occluded(rays, occ);
    Vec3 sum(0.0f);
    for (size_t i = 0; i < t.size(); ++i)
      if (!occ[i]) sum += t[i];
    img[sp.pixel] += sp.weight * sum;
  }
  return img;
}

}  // namespace rayscout::testing
