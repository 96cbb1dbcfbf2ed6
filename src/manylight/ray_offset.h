// Private helper of the manylight module: where its rays start off the surface they leave.
#pragma once

#include "rayscout/scene/scene.h"

namespace rayscout::manylight_detail {

/// 1e-4 of the scene diagonal. The camera paths, the VPL paths, the cluster-pair visibility
/// samples and a pass's shadow rays must leave surfaces alike, so all take it from here.
inline float ray_offset(const Scene& scene) { return 1e-4f * length(scene.bounds().diagonal()); }

}  // namespace rayscout::manylight_detail
