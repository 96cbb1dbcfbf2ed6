// Sample rays of shafts (private): the random numbers of a shaft's rays, tracing them, and the
// two ways the build gathers them for many shafts (cell-major chunks, or shared along paths).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "group_list_builder.h"
#include "rayscout/core/random.h"
#include "rayscout/shafts/shaft_collection.h"
#include "shaft.h"
#include "voxel_surfaces.h"

namespace rayscout::detail {

/// Random numbers of the sample rays of one shaft (voxel x cell `sid`): depend only on the
/// seed and the shaft id. Latin hypercube when config.stratified.
class SampleStream {
 public:
  SampleStream(uint64_t sid, const ShaftConfig& config)
      : rng_{(uint64_t(config.seed) << 40) ^ (sid * 0x2545F4914F6CDD1Dull)}, n_(config.samples.value()),
        stratified_(config.stratified) {
    if (stratified_)
      for (auto& p : perm_) {
        for (int i = 0; i < n_; ++i) p[i] = uint8_t(i);
        for (int i = n_ - 1; i > 0; --i) std::swap(p[i], p[rng_.next() % uint64_t(i + 1)]);
      }
  }
  /// The 5 numbers of sample ray k (k < config.samples, drawn in order).
  void next(int k, float rnd[5]) {
    for (int d = 0; d < 5; ++d) rnd[d] = rng_.uniform();
    if (stratified_)
      for (int d = 0; d < 5; ++d) rnd[d] = std::min((float(perm_[d][k]) + rnd[d]) / float(n_), 0.99999994f);
  }
  float uniform() { return rng_.uniform(); }

 private:
  SplitMix64 rng_;
  int n_;
  bool stratified_;
  uint8_t perm_[5][256];
};

/// Stores sample ray k (origin, inverse direction, hit distance) in samples.
inline void store_sample(ShaftSamples& samples, size_t k, const Vec3& org, const Vec3& dir, float hit_t) {
  samples.ox[k] = org.x; samples.oy[k] = org.y; samples.oz[k] = org.z;
  samples.ix[k] = 1.0f / dir.x; samples.iy[k] = 1.0f / dir.y; samples.iz[k] = 1.0f / dir.z;
  samples.hit_t[k] = hit_t;
}

/// Shaft::sample_ray of the voxel and cell for rnd; with surfaces (config.origins = surface)
/// its origin is moved onto the voxel's surfaces when it has any, tmin just off them.
inline Ray sample_ray(const Bounds3& voxel, const ShaftGrid::CellRange& cell, const float rnd[5],
                      const VoxelSurfaces* surfaces, uint32_t voxel_id) {
  Ray ray = Shaft::sample_ray(voxel, cell, rnd);
  if (surfaces && surfaces->sample(voxel_id, rnd, ray.org)) ray.tmin = surfaces->epsilon();
  return ray;
}

/// Draws the `config.samples` own sample rays of shaft `sid` (voxel box, direction cell),
/// traces each and hands it to out(s, ray, hit_t). With surfaces (config.origins = surface)
/// the origins lie on the voxel's surfaces when it has any.
template <class Out>
void trace_own_samples(const Bounds3& voxel, const ShaftGrid::CellRange& cell, uint64_t sid,
                       const VoxelSurfaces* surfaces, uint32_t voxel_id, const ShaftCollection::TraceFn& trace,
                       const ShaftConfig& config, Out&& out) {
  SampleStream stream(sid, config);
  const int samples = config.samples.value();
  for (int s = 0; s < samples; ++s) {
    float rnd[5];
    stream.next(s, rnd);
    const Ray ray = sample_ray(voxel, cell, rnd, surfaces, voxel_id);
    out(size_t(s), ray, trace(ray));
  }
}

/// One sample ray in a pool (shared or a chunk's), one record: shared deposits land at random
/// places, and one cache line per deposit beats seven.
struct PooledSample {
  float org[3], inv_dir[3], hit_t;
};

/// Sample rays shared along their paths (ray reuse): for one direction cell, voxels are
/// visited upstream first (along the cell's face axis); a voxel still short of samples shoots
/// its own, and each traced ray also gives a sample to every later listed voxel it crosses
/// before its hit (origin uniform on its chord through that voxel, so origins stay about
/// uniform in the voxel; hit distance shortened accordingly). Fills pool[(cell * listed +
/// li) * per ...] for listed voxel index li; count[cell * listed + li] = samples stored.
/// Returns the number of rays traced.
size_t shared_samples(const ShaftGrid& grid, const std::vector<uint32_t>& listed,
                      const std::vector<int32_t>& listed_index, const std::vector<uint8_t>& shaft_selected,
                      const VoxelSurfaces* surfaces, const ShaftCollection::TraceFn& trace, const ShaftConfig& config,
                      std::vector<PooledSample>& pool, std::vector<uint16_t>& count);

/// The own sample rays (trace_own_samples) of every selected shaft of listed voxels
/// [l0, l1), traced direction cell by direction cell, into pool[(cell * (l1 - l0) + li - l0)
/// * per + k]: rays of one cell from neighbouring voxels take similar paths through the BVH,
/// so the tracing stays in cache (a voxel's own rays scatter in all 6 d^2 directions). The
/// caller takes chunks of a few dozen voxels: the pool stays small and warm for their walks.
void cell_major_samples(const ShaftGrid& grid, const std::vector<uint32_t>& listed, size_t l0, size_t l1,
                        const std::vector<uint8_t>& shaft_selected, const VoxelSurfaces* surfaces,
                        const ShaftCollection::TraceFn& trace, const ShaftConfig& config,
                        std::vector<PooledSample>& pool);

}  // namespace rayscout::detail
