// Ray-sampling pre-pass: a low-resolution rendering whose rays show which shafts matter.
#pragma once

#include <functional>

#include "rayscout/core/ray.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

/// Rays of a low-resolution pre-pass from scene.camera (Hendrich et al. 2019, sec. 4.4):
/// one pinhole primary ray per pixel of a width x (3/4 width) image; at each hit a cosine-
/// distributed diffuse ray, a shadow ray to every point light (up to 4) and, where the
/// diffuse ray hits, a second diffuse bounce. trace gives a ray's closest hit.
RayBatch camera_prepass_rays(const Scene& scene, const std::function<Hit(const Ray&)>& trace,
                             int width, unsigned seed);

}  // namespace rayscout
