// Private helper of the manylight module: where its rays start off the surface they leave.
#pragma once

#include "rayscout/scene/scene.h"

namespace rayscout::manylight_detail {

/// 1e-4 of the scene diagonal (its length given). The camera paths, the VPL paths, the
/// cluster-pair visibility samples and a pass's shadow rays must leave surfaces alike, so all
/// take it from here.
inline float ray_offset(float diagonal) { return 1e-4f * diagonal; }
/// The same for a scene (Scene::bounds() walks every triangle: callers that also need the
/// diagonal compute it once and call the overload above).
inline float ray_offset(const Scene& scene) { return ray_offset(length(scene.bounds().diagonal())); }

}  // namespace rayscout::manylight_detail
