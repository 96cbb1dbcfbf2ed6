// Shading points: the first non-mirror camera-path hits, spp per pixel.
#pragma once

#include <cstdint>
#include <vector>

#include "rayscout/core/accelerator.h"
#include "rayscout/manylight/manylight_config.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

/// A point where eq. (1) is evaluated. Points that see nothing carry no shading, only `emitted`.
struct ShadingPoint {
  Vec3 position;
  Vec3 normal;        ///< unit geometric normal flipped towards the viewer
  Vec3 wo;            ///< unit direction towards the previous camera-path vertex
  Vec3 weight{0.0f};  ///< camera-path throughput (mirror reflectances) / spp; 0 = no surface
  Vec3 emitted{0.0f}; ///< radiance emitted towards the camera along the path, already weighted
  uint32_t pixel = 0; ///< y * width + x
  uint32_t material = 0;
  bool valid() const { return weight.x > 0 || weight.y > 0 || weight.z > 0; }
};

/// Pinhole camera rays through jittered pixel positions (scene.camera, vertical fov),
/// traced as batches through accel.intersect, following perfect mirrors up to
/// config.max_mirror_bounces. Returns width * height * spp points, pixel-major.
std::vector<ShadingPoint> generate_shading_points(const Scene& scene, const Accelerator& accel,
                                                  const ManylightConfig& config);

}  // namespace rayscout
