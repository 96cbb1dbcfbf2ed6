// Camera rays: pinhole or thin lens, stratified pixel samples.
#pragma once

#include <cstdint>

#include "rayscout/core/ray.h"
#include "rayscout/render/sampler.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

/// Maps film positions (in pixels from the top-left corner) and lens samples to world rays
/// of unit direction, tmin = 0, tmax = inf. Thin lens as in pbrt-v4 (Pharr et al., sec. 5.2.3):
/// the ray passes through the lens point and the point in focus at focus_distance along the
/// view axis.
class CameraRays {
 public:
  /// A film of width x height pixels; the horizontal field of view follows the aspect ratio.
  /// Throws InputError for a camera without a frame (see camera_frame).
  CameraRays(const Camera& camera, int width, int height);
  /// film_x, film_y in [0, width) x [0, height); lens_u, lens_v in [0, 1).
  Ray generate(float film_x, float film_y, float lens_u, float lens_v) const;

 private:
  CameraFrame frame_;
  Vec3 eye_;
  float lens_radius_ = 0, focus_distance_ = 1;
  int width_ = 1, height_ = 1;
};

/// Film position of sample `sample` of `spp` in pixel (x, y): jittered grid when spp is a
/// square, else N-rooks (x strata in order, y strata permuted per pixel); jitter from
/// sampler dims kDimPixel, kDimPixel + 1.
void pixel_sample_position(const PathSampler& sampler, int x, int y, int sample, int spp,
                           float& film_x, float& film_y);

/// Point on the unit disk from [0,1)^2, Shirley-Chiu concentric mapping.
void concentric_disk(float u, float v, float& dx, float& dy);

}  // namespace rayscout
