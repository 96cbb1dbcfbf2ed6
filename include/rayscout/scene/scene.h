// Scene: triangles with materials, a camera and lights, as loaded from a scene or mesh file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rayscout/core/bounds3.h"
#include "rayscout/core/triangle.h"

namespace rayscout {

/// A surface material. Diffuse is Lambertian with albedo `diffuse`; Mirror reflects
/// perfectly with reflectance `specular`; Glossy is a normalised Phong lobe of exponent
/// `exponent` weighted by `specular`, added to the diffuse part. Emission makes the
/// triangles area lights.
struct Material {
  enum class Type { Diffuse, Mirror, Glossy };
  std::string name{};
  Type type = Type::Diffuse;
  Vec3 diffuse{0.8f};   ///< Kd, albedo in [0, 1]
  Vec3 specular{0.0f};  ///< Ks, mirror or glossy reflectance
  float exponent = 0;   ///< Ns, Phong exponent of Glossy
  Vec3 emission{0.0f};  ///< Ke, emitted radiance (W sr^-1 m^-2 in scene units)
  bool emissive() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

/// A pinhole or thin-lens camera.
struct Camera {
  Vec3 eye{0, 0, 1};
  Vec3 look_at{0, 0, 0};
  Vec3 up{0, 1, 0};
  float fov_deg = 60;         ///< vertical field of view, degrees
  float lens_radius = 0;      ///< 0 = pinhole
  float focus_distance = 1;   ///< distance of the plane in focus along the view axis
};

/// A camera's orthonormal basis and film; every producer of camera rays (renderer,
/// many-light shading points, the shafts' pre-pass) aims its pinhole rays with it.
struct CameraFrame {
  Vec3 forward, right, up;        ///< up lies in the plane of forward and Camera::up
  float half_w = 1, half_h = 1;   ///< half extents of the film at distance 1 along forward
  /// Unit direction through the film point (u, v) in [0, 1]^2, (0, 0) = top-left corner.
  Vec3 direction(float u, float v) const {
    return normalize(forward + right * ((2.0f * u - 1.0f) * half_w) + up * ((1.0f - 2.0f * v) * half_h));
  }
};

/// The frame of `camera` for a film of the given width / height. Any finite eye, look_at and
/// up give the frame of their normalised directions, however long or short they are.
/// Throws InputError (naming the key) when eye == look_at, when up is parallel to the view
/// direction (sine of the angle below 1e-6), or when a vector is not finite.
CameraFrame camera_frame(const Camera& camera, float aspect);

/// An isotropic point light; intensity in W/sr per colour channel.
struct PointLight {
  Vec3 position;
  Vec3 intensity{1.0f};
};

/// Everything a renderer needs. Triangle ids are indices into `triangles`, in load order:
/// the scene file's "meshes" entries (files and shapes) in list order, then its area
/// lights in list order; within a mesh, faces in file order (a polygon's n - 2 triangles in its
/// place: its fan v0 v1 v2, v0 v2 v3, ..., or ear-clipped when the fan leaves it). Dropped
/// degenerate faces take no id.
/// See docs/scene-format.md.
struct Scene {
  std::vector<Triangle> triangles;
  std::vector<uint32_t> material_ids;      ///< per triangle, index into materials
  std::vector<Material> materials;
  Camera camera;
  std::vector<PointLight> point_lights;
  std::vector<uint32_t> emissive_triangles;  ///< ids of triangles whose material emits
  std::vector<std::string> warnings;         ///< e.g. "dropped 12 degenerate triangles"

  const Material& material_of(uint32_t prim) const { return materials[material_ids[prim]]; }
  Bounds3 bounds() const {
    Bounds3 b;
    for (const auto& t : triangles) b.extend(t.bounds());
    return b;
  }
};

}  // namespace rayscout
