// Virtual point lights (instant radiosity, Keller 1997) and their generation.
#pragma once

#include <cstdint>
#include <vector>

#include "rayscout/core/accelerator.h"
#include "rayscout/manylight/manylight_config.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

/// One VPL. Its radiant intensity towards direction w (unit, pointing away from it) is
///   Point:   intensity                          (an isotropic scene point light)
///   Emitter: power * max(0, n.w) / pi           (a point on an area light, emitting on the
///                                               side of its geometric normal)
///   Surface: power * f_r(wi, w) * max(0, n.w)   (a light-path vertex; power = incident flux)
/// in W/sr; see vpl_intensity().
struct Vpl {
  enum class Kind : uint8_t { Point, Emitter, Surface };
  Vec3 position;
  Vec3 normal;      ///< unit, on the lit side (unused for Point)
  Vec3 wi;          ///< Surface: unit direction towards the previous path vertex
  Vec3 power;       ///< W per colour (Point: the intensity in W/sr)
  uint32_t material = 0;  ///< Surface: index into Scene::materials
  Kind kind = Kind::Point;
};

/// The VPLs of a scene and how they were made.
struct VplSet {
  std::vector<Vpl> vpls;
  size_t light_paths = 0;  ///< paths traced; every power is already divided by it
  double build_ms = 0.0;
};

/// Radiant intensity (W/sr per colour) of vpl towards unit direction w.
Vec3 vpl_intensity(const Vpl& vpl, const Scene& scene, const Vec3& w);

/// Traces light paths from the scene's point and area lights (light chosen proportional to
/// power, area lights sampled uniformly by area) until at least config.vpl_count VPLs exist;
/// every path start and every non-mirror surface vertex becomes a VPL. Paths are traced as
/// wavefronts through accel.intersect. Russian roulette on the throughput; mirrors reflect
/// without a VPL; glossy surfaces sample their Phong lobe. Deterministic for a seed.
VplSet generate_vpls(const Scene& scene, const Accelerator& accel, const ManylightConfig& config);

}  // namespace rayscout
