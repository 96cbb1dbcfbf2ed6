// Material evaluation for many-light shading: the renderer's BSDF (rayscout/render/bsdf.h),
// plus pi and the scalar luminance that the many-light probabilities use.
#pragma once

#include "rayscout/core/vec3.h"
#include "rayscout/render/bsdf.h"

namespace rayscout {

inline constexpr float kPi = 3.14159265358979323846f;

/// Mean of the colour channels: the scalar that probabilities and variances use.
inline float luminance(const Vec3& c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

}  // namespace rayscout
