// Ray sets of the ray-sampling DACRT paper's workloads, per bounce: primary, shadow (point or
// area light), mirror reflections off a mirror floor and the shadow rays of their hits, and
// short random (ambient-occlusion) rays.
#pragma once

#include <string>
#include <vector>

#include "bench_support.h"
#include "rayscout/core/accelerator.h"
#include "rayscout/scene/scene.h"

namespace rayscout::bench {

/// A benchmark view: camera, lights and which surfaces mirror.
struct View {
  std::string name;            ///< e.g. "sibenik-a"
  std::string file;            ///< relative to the scenes folder
  Camera camera;
  std::vector<Vec3> point_lights;
  bool area_light = false;     ///< shadow rays to a random point of the area quad instead
  Vec3 area_corner, area_u, area_v;
  bool mirror_floor = false;   ///< upward-facing triangles below mirror_below_y reflect
  float mirror_below_y = 0;
  bool ao = false;             ///< add short random rays (10 % of the diagonal) from primary hits
  std::string scene_json;      ///< bench/scenes file for the renderer source ("" = none)
  std::string integrator;      ///< "direct", "area", "ao" or "path" for the renderer source
  int max_depth = 1;           ///< renderer: mirror reflections (direct/area) or path bounces
};

/// The frame's ray sets at width x height (one primary ray per pixel centre, pixel-major).
/// Hits that spawn secondary rays are found with `tracer` (any accelerator; results agree).
std::vector<RaySet> make_ray_sets(const Scene& scene, const View& view, int width, int height,
                                  const Accelerator& tracer);

/// The batches the renderer traces for one frame of view.integrator at width x height, one
/// sample per pixel (RenderConfig::on_batch), in trace order. Rendering uses `tracer`.
std::vector<RaySet> render_ray_sets(const Scene& scene, const View& view, int width, int height,
                                    const Accelerator& tracer);

}  // namespace rayscout::bench
