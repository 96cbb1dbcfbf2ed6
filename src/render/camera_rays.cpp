// Camera rays: pinhole and thin-lens models, stratified pixel samples.
#include "rayscout/render/camera_rays.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "rayscout/core/input_error.h"

namespace rayscout {

CameraRays::CameraRays(const Camera& camera, int width, int height)
    : frame_(camera_frame(camera, float(width) / float(height))), eye_(camera.eye),
      lens_radius_(camera.lens_radius), focus_distance_(camera.focus_distance), width_(width),
      height_(height) {
  if (!(lens_radius_ >= 0 && std::isfinite(lens_radius_)))
    throw InputError("camera.lens_radius: must be finite and >= 0");
  if (lens_radius_ > 0 && !(focus_distance_ > 0 && std::isfinite(focus_distance_)))
    throw InputError("camera.focus_distance: a thin lens needs a finite focus distance > 0");
}

Ray CameraRays::generate(float film_x, float film_y, float lens_u, float lens_v) const {
  Vec3 dir = frame_.direction(film_x / float(width_), film_y / float(height_));
  Vec3 org = eye_;
  if (lens_radius_ > 0) {
    // The ray runs from the lens point eye + offset to the point in focus eye + dir * k, i.e.
    // along dir * k - offset. Divided by s = max(k, |offset|) first, that vector has a length
    // between min(cos, 1 - sin) of dir's angle to the view axis and 2, so neither a far focus
    // plane nor a wide lens overflows or underflows the normalisation.
    const float k = focus_distance_ / dot(dir, frame_.forward);
    float dx, dy;
    concentric_disk(lens_u, lens_v, dx, dy);
    const Vec3 offset = (frame_.right * dx + frame_.up * dy) * lens_radius_;
    const float s = std::max(k, std::hypot(dx, dy) * lens_radius_);
    org = eye_ + offset;
    dir = normalize(dir * (k / s) - offset / s);
  }
  return {org, 0.0f, dir, kInfinity};
}

void pixel_sample_position(const PathSampler& sampler, int x, int y, int sample, int spp,
                           float& film_x, float& film_y) {
  const float jx = sampler.get(kDimPixel), jy = sampler.get(kDimPixel + 1);
  const int k = int(std::lround(std::sqrt(double(spp))));
  if (k * k == spp) {
    film_x = float(x) + (float(sample % k) + jx) / float(k);
    film_y = float(y) + (float(sample / k) + jy) / float(k);
    return;
  }
  // N-rooks: y stratum = (a * sample + b) mod spp with a coprime to spp, a permutation per pixel.
  const uint64_t h = sampler.pixel_sampler().bits(0);
  uint64_t a = 1 + (h % uint64_t(spp));
  while (std::gcd(a, uint64_t(spp)) != 1) ++a;
  const uint64_t b = (h >> 32) % uint64_t(spp);
  const uint64_t ys = (a * uint64_t(sample) + b) % uint64_t(spp);
  film_x = float(x) + (float(sample) + jx) / float(spp);
  film_y = float(y) + (float(ys) + jy) / float(spp);
}

void concentric_disk(float u, float v, float& dx, float& dy) {
  const float a = 2.0f * u - 1.0f, b = 2.0f * v - 1.0f;
  if (a == 0 && b == 0) { dx = dy = 0; return; }
  constexpr float pi = std::numbers::pi_v<float>;
  float r, phi;
  if (std::fabs(a) > std::fabs(b)) { r = a; phi = (pi / 4) * (b / a); }
  else { r = b; phi = pi / 2 - (pi / 4) * (a / b); }
  dx = r * std::cos(phi);
  dy = r * std::sin(phi);
}

}  // namespace rayscout
