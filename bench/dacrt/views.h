// The benchmark views of the ray-sampling DACRT paper's figures 4-7 and their published ratios.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "ray_sets.h"

namespace rayscout::bench {

/// Every view: Sibenik (a) point light, (b) other point lights, (c) area light, all with the
/// mirror floor of fig. 4, and Sibenik ambient occlusion (fig. 5(b); our camera (a), the
/// paper's is not given); Sponza (a), (b) point lights, (c) path tracing; Conference likewise.
/// The renderer source (default) renders bench/scenes/<scene_json> with `integrator` (the (b)
/// views have two point lights); the own generator (--source own) uses the camera and lights
/// here instead (AO rays stand in for path tracing).
inline std::vector<View> paper_views() {
  std::vector<View> v;
  View s;
  s.file = "sibenik/sibenik.obj";
  s.camera.eye = {-17.0f, -10.0f, 0.0f};
  s.camera.look_at = {0.0f, -9.0f, 0.0f};
  s.camera.fov_deg = 70;
  s.mirror_floor = true;
  s.mirror_below_y = -12.0f;
  s.integrator = "direct";
  s.name = "sibenik-a"; s.scene_json = "sibenik-a.json"; s.point_lights = {{0.0f, 0.0f, 0.0f}}; v.push_back(s);
  s.name = "sibenik-b"; s.scene_json = "sibenik-b.json"; s.point_lights = {{-8.0f, -9.0f, 3.0f}}; v.push_back(s);
  s.name = "sibenik-c"; s.scene_json = "sibenik-c.json"; s.integrator = "area"; s.point_lights = {}; s.area_light = true;
  s.area_corner = {-3.0f, 2.0f, -3.0f}; s.area_u = {6.0f, 0.0f, 0.0f}; s.area_v = {0.0f, 0.0f, 6.0f};
  v.push_back(s);
  s.name = "sibenik-ao"; s.scene_json = "sibenik-a.json"; s.integrator = "ao"; s.area_light = false; s.ao = true;
  s.mirror_floor = false; v.push_back(s);

  View p;
  p.file = "crytek-sponza/sponza.obj";
  p.camera.eye = {-110.0f, 20.0f, -4.0f};
  p.camera.look_at = {0.0f, 35.0f, 0.0f};
  p.camera.fov_deg = 70;
  p.integrator = "direct";
  p.name = "sponza-a"; p.scene_json = "sponza.json"; p.point_lights = {{0.0f, 110.0f, 0.0f}}; v.push_back(p);
  p.name = "sponza-b"; p.scene_json = "sponza-b.json"; p.point_lights = {{-60.0f, 30.0f, 20.0f}}; v.push_back(p);
  p.name = "sponza-c"; p.scene_json = "sponza.json"; p.integrator = "path"; p.max_depth = 3;
  p.point_lights = {{0.0f, 110.0f, 0.0f}}; p.ao = true; v.push_back(p);

  View c;
  c.file = "conference/conference.obj";
  c.camera.eye = {-800.0f, 420.0f, -850.0f};
  c.camera.look_at = {400.0f, 100.0f, -150.0f};
  c.camera.fov_deg = 60;
  c.integrator = "direct";
  c.name = "conference-a"; c.scene_json = "conference.json"; c.point_lights = {{300.0f, 550.0f, -200.0f}}; v.push_back(c);
  c.name = "conference-b"; c.scene_json = "conference-b.json"; c.point_lights = {{1200.0f, 300.0f, 300.0f}}; v.push_back(c);
  c.name = "conference-c"; c.scene_json = "conference.json"; c.integrator = "path"; c.max_depth = 3;
  c.point_lights = {{300.0f, 550.0f, -200.0f}}; c.ao = true; v.push_back(c);
  return v;
}

/// Afra time / proposed time per view and resolution, figs. 4, 5(b), 6, 7 (the whole frame).
inline const std::map<std::string, std::map<int, double>>& paper_ratios() {
  static const std::map<std::string, std::map<int, double>> r = {
      {"sibenik-a", {{512, 1.41}, {1024, 1.52}, {2048, 1.59}, {4096, 1.86}}},
      {"sibenik-b", {{512, 1.54}, {1024, 1.61}, {2048, 1.76}, {4096, 1.75}}},
      {"sibenik-c", {{512, 1.47}, {1024, 1.66}, {2048, 1.81}, {4096, 1.94}}},
      {"sibenik-ao", {{512, 1.22}, {1024, 1.41}, {2048, 1.59}, {4096, 1.53}}},  // fig. 5(b)
      {"sponza-a", {{512, 1.38}, {1024, 1.61}, {2048, 1.74}, {4096, 1.80}}},
      {"sponza-b", {{512, 1.52}, {1024, 1.50}, {2048, 1.64}, {4096, 1.73}}},
      {"sponza-c", {{512, 1.22}, {1024, 1.17}, {2048, 1.34}, {4096, 1.39}}},
      {"conference-a", {{512, 1.24}, {1024, 1.34}, {2048, 1.43}, {4096, 1.43}}},
      {"conference-b", {{512, 1.44}, {1024, 1.54}, {2048, 1.60}, {4096, 1.69}}},
      {"conference-c", {{512, 1.13}, {1024, 1.20}, {2048, 1.26}, {4096, 1.36}}},
  };
  return r;
}

}  // namespace rayscout::bench
