// Ray sets and option combinations shared by the DACRT tests.
#pragma once

#include <string>
#include <vector>

#include "generated_scenes.h"
#include "rayscout/core/accelerator_options.h"
#include "rayscout/core/ray.h"
#include "rayscout/scene/scene.h"

namespace rayscout::testing {

/// width x height pinhole rays from eye towards look_at (vertical fov in degrees), pixel-major.
RayBatch pinhole_rays(const Vec3& eye, const Vec3& look_at, float fov_deg, int width, int height);

/// Shadow rays from the closest hits of `primary` to `light` (tmax just short of the light).
RayBatch shadow_rays(const RayBatch& primary, const HitBatch& hits, const std::vector<Triangle>& tris,
                     const Vec3& light);

/// A generated scene: an 8 x 8 array of spheres (radius 0.3, one unit apart) on a floor
/// y = 0 over [-4, 4]^2. Seen from inside (kInsideEye), much of it is behind the camera.
std::vector<Triangle> spheres_on_floor();
inline const Vec3 kInsideEye{0.0f, 1.0f, 0.0f}, kInsideLook{1.0f, 0.6f, 3.0f};

/// Every combination of the three switches (cost, order, skip), each with a few samplings
/// and thresholds; min_rays is lowered so that the small test batches sample deep down.
std::vector<std::vector<std::string>> switch_combinations();

/// Options from "key=value" strings.
AcceleratorOptions options_of(const std::vector<std::string>& kv);
std::string label_of(const std::vector<std::string>& kv);

}  // namespace rayscout::testing
