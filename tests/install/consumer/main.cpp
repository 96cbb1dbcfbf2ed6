// An engine outside the tree, built against an installed rayscout (tests/install/install_test.cmake):
// README's library example, then a small render written through the image module.
#include <cstdio>
#include <exception>

#include "rayscout/accelerators.h"
#include "rayscout/image/image.h"
#include "rayscout/manylight/manylight_config.h"
#include "rayscout/render/renderer.h"
#include "rayscout/scene/load_scene.h"

int main(int argc, char** argv) try {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer <out.exr>\n");
    return 2;
  }
  const rayscout::Scene scene = rayscout::resolve_scene("cornell");
  const auto accel = rayscout::make_accelerator("bvh", scene);
  rayscout::RayBatch rays;
  rays.push_back({scene.camera.eye, 0.0f, scene.camera.look_at - scene.camera.eye, rayscout::kInfinity});
  rayscout::HitBatch hits;
  accel->intersect(rays, hits);
  std::printf("triangles %zu\nhit %u t %.6f\n", scene.triangles.size(), hits.prim[0], hits.t[0]);

  rayscout::RenderConfig config;
  config.width = config.height = 8;
  config.spp = 1;
  const rayscout::Image image = rayscout::make_path_integrator()->render(scene, *accel, config);
  rayscout::write_image(image, argv[1]);
  std::printf("rendered %dx%d\nvisibility %s\n", image.width, image.height,
              rayscout::to_string(rayscout::parse_visibility_mode("proposed")).c_str());
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "consumer: %s\n", e.what());
  return 1;
}
