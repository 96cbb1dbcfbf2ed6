// The accelerator registry: every ray tracer of rayscout by name, built from a scene.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "rayscout/core/accelerator.h"
#include "rayscout/core/accelerator_options.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

/// One registered accelerator.
struct AcceleratorInfo {
  std::string name;
  std::string description;
};

/// The accelerator commands use when none is named: the 8-wide BVH.
inline constexpr const char* kDefaultAccelerator = "bvh";

/// Every accelerator compiled into this build, reference ("brute") first.
const std::vector<AcceleratorInfo>& accelerators();

/// Throws what make_accelerator would for `name` and `options` (an unknown name, an unknown
/// key, a bad value), without a scene or a build: commands call it before loading the scene.
void check_accelerator(const std::string& name, const AcceleratorOptions& options = {});

/// Builds accelerator `name` over scene.triangles (the scene must outlive it). Throws
/// InputError for an unknown name or an option the accelerator does not have.
std::unique_ptr<Accelerator> make_accelerator(const std::string& name, const Scene& scene,
                                              const AcceleratorOptions& options = {});
/// Not from a temporary scene: the accelerator would point into a scene already gone.
std::unique_ptr<Accelerator> make_accelerator(const std::string& name, const Scene&& scene,
                                              const AcceleratorOptions& options = {}) = delete;

}  // namespace rayscout
