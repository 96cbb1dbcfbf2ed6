// The scalar of a colour that the many-light probabilities and variances use.
#pragma once

#include "rayscout/core/vec3.h"

namespace rayscout {

/// Mean of the colour channels (not a perceptual luminance): the scalar t, t V~ / p and light
/// powers of the many-light module (docs/manylight.md, Probabilistic visibility).
inline float channel_mean(const Vec3& c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

}  // namespace rayscout
