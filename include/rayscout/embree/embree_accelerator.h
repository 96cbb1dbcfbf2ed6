// EmbreeAccelerator: Intel Embree 3 as a peer accelerator, measured in the same process.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rayscout/core/accelerator.h"
#include "rayscout/core/accelerator_options.h"

namespace rayscout {

/// Tunables of the Embree peer.
struct EmbreeConfig {
  /// RTC_SCENE_FLAG_ROBUST: Embree's watertight (Pluecker) triangle test, so rays through
  /// shared edges and vertices do not leak, as with our own kernel. Default on; off gives
  /// Embree's fastest (non-watertight) mode.
  bool robust = true;
  /// RTC_BUILD_QUALITY_HIGH (spatial splits in the SAH build); off = MEDIUM. Default on.
  bool high_quality = true;
  /// Rays traced per rtcIntersect16/rtcOccluded16 packet call; 1 = rtcIntersect1 (the
  /// standard single-ray use). Default 1.
  int packet = 1;

  /// Reads "robust", "quality" (high|medium) and "packet" (1|16) from options.
  static EmbreeConfig from_options(const AcceleratorOptions& options);
};

/// Embree 3 with one triangle geometry whose primIDs are our triangle ids. Embree uses its
/// own triangle test, so t differs from ours in the last bits and exact ties may resolve to
/// another triangle: compare with a tolerance (1e-4 relative), never bit for bit.
/// Embree has no work counters: intersect/occluded fill only TraceStats::rays.
/// Rays Embree cannot trace (an origin coordinate NaN or beyond FLT_LARGE = 1.844e18 in
/// magnitude, a NaN direction, a negative or NaN tmin, a NaN tmax, or tmin > tmax: Embree's
/// RayK::valid() and tnear >= 0) are not handed to it, since its assertion would abort the
/// process; they miss. Our own accelerators trace them as brute force does.
/// A finite direction of any length is traced: Accelerator::intersect scales one whose
/// largest component lies outside [2^-32, 2^32] by a power of two first, which changes none
/// of Embree's answers but t's units (unscaled, Embree lost hits of directions shorter than
/// about 1e-16 and asserted on those beyond FLT_LARGE).
/// Embree's builder leaves out a triangle with a vertex coordinate of magnitude FLT_LARGE (the
/// float 1.844e18f) or more, which brute force still hits.
class EmbreeAccelerator final : public Accelerator {
 public:
  /// Copies the triangles into an Embree vertex buffer and builds the BVH (timed, with the
  /// memory Embree's memory monitor saw allocated during the build).
  explicit EmbreeAccelerator(std::span<const Triangle> triangles, const EmbreeConfig& config = {});
  ~EmbreeAccelerator() override;
  EmbreeAccelerator(const EmbreeAccelerator&) = delete;
  EmbreeAccelerator& operator=(const EmbreeAccelerator&) = delete;

  std::string name() const override { return "embree"; }
  BuildInfo build_info() const override { return info_; }
  bool counts_work() const override { return false; }

 private:
  void intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const override;
  void occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const override;

  struct State;
  std::unique_ptr<State> state_;
  EmbreeConfig config_;
  BuildInfo info_;
};

}  // namespace rayscout
