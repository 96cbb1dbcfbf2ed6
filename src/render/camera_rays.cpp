// Camera rays: pinhole and thin-lens models, stratified pixel samples.
#include "rayscout/render/camera_rays.h"

#include <cmath>
#include <numbers>

namespace rayscout {

CameraRays::CameraRays(const Camera& camera, int width, int height)
    : eye_(camera.eye), lens_radius_(camera.lens_radius), focus_distance_(camera.focus_distance),
      width_(width), height_(height) {
  forward_ = normalize(camera.look_at - camera.eye);
  Vec3 right = cross(forward_, camera.up);
  if (length(right) < 1e-6f)  // up parallel to the view axis: any perpendicular will do
    right = cross(forward_, std::fabs(forward_.y) < 0.9f ? Vec3{0, 1, 0} : Vec3{1, 0, 0});
  right_ = normalize(right);
  up_ = cross(right_, forward_);
  half_h_ = std::tan(0.5f * camera.fov_deg * std::numbers::pi_v<float> / 180.0f);
  half_w_ = half_h_ * float(width) / float(height);
}

Ray CameraRays::generate(float film_x, float film_y, float lens_u, float lens_v) const {
  const float sx = (2.0f * film_x / float(width_) - 1.0f) * half_w_;
  const float sy = (1.0f - 2.0f * film_y / float(height_)) * half_h_;
  Vec3 dir = normalize(forward_ + right_ * sx + up_ * sy);
  Vec3 org = eye_;
  if (lens_radius_ > 0) {
    const Vec3 focus = eye_ + dir * (focus_distance_ / dot(dir, forward_));
    float dx, dy;
    concentric_disk(lens_u, lens_v, dx, dy);
    org = eye_ + (right_ * dx + up_ * dy) * lens_radius_;
    dir = normalize(focus - org);
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
  auto gcd = [](uint64_t p, uint64_t q) { while (q) { uint64_t r = p % q; p = q; q = r; } return p; };
  while (gcd(a, uint64_t(spp)) != 1) ++a;
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
