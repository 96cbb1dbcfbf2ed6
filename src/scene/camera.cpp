// The camera frame shared by everything that shoots camera rays.
#include <cmath>
#include <numbers>

#include "rayscout/core/input_error.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

namespace {

// Scaled by its largest component before normalising: a length of 1e20 or 1e-30 would
// overflow or underflow when squared, and the direction is all the frame needs.
Vec3 unit(const Vec3& v) { return normalize(v / max_component(abs(v))); }

}  // namespace

CameraFrame camera_frame(const Camera& camera, float aspect) {
  const Vec3 view = camera.look_at - camera.eye;
  if (!is_finite(camera.eye) || !is_finite(camera.look_at) || !is_finite(view))
    throw InputError("camera: eye and look_at must be finite and closer than float's range");
  if (!is_finite(camera.up)) throw InputError("camera.up: must be finite");
  if (view == Vec3(0.0f)) throw InputError("camera.look_at: must differ from camera.eye");
  if (camera.up == Vec3(0.0f)) throw InputError("camera.up: must not be zero");
  if (!(camera.fov_deg > 0 && camera.fov_deg < 180)) throw InputError("camera.fov_deg: expected a number in (0, 180)");
  CameraFrame f;
  f.forward = unit(view);
  const Vec3 right = cross(f.forward, unit(camera.up));  // |right| = sine of the angle
  if (!(length(right) >= 1e-6f)) throw InputError("camera.up: is parallel to the view direction");
  f.right = normalize(right);
  f.up = cross(f.right, f.forward);
  f.half_h = std::tan(0.5f * camera.fov_deg * std::numbers::pi_v<float> / 180.0f);
  f.half_w = f.half_h * aspect;
  return f;
}

}  // namespace rayscout
