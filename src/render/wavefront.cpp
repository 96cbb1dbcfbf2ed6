// The wavefront loop: whole batches per bounce, shading in fixed-size chunks, ordered accumulation.
#include "wavefront.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/parallel_for.h>

#include "rayscout/core/input_error.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/render/camera_rays.h"

namespace rayscout {
namespace {

// Paths per shading task. Fixed (not derived from the thread count) so that the merge order,
// and with it every floating-point sum, is the same for any number of threads.
constexpr size_t kShadeChunk = 4096;

// Adds the contributions of the occlusion rays that nothing occluded to the film. Each pixel's
// contributions are added in array order by one task, so the sums do not depend on the thread
// count: blocks of whole pixels in parallel when the list is sorted by pixel (as paths keep the
// pixel-major camera order), else all in one sequential pass.
template <typename Contribution>
void accumulate_unoccluded(std::vector<Vec3>& film, const std::vector<Contribution>& list,
                           const std::vector<uint8_t>& occluded) {
  auto add = [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i)
      if (!occluded[i]) film[list[i].pixel] += list[i].value;
  };
  const bool sorted = std::is_sorted(list.begin(), list.end(),
                                     [](const Contribution& a, const Contribution& b) { return a.pixel < b.pixel; });
  constexpr size_t kBlock = 1 << 12;
  if (!sorted || list.size() <= kBlock) return add(0, list.size());
  const size_t blocks = (list.size() + kBlock - 1) / kBlock;
  // A block starts at its first pixel not begun by the block before, and ends with its last
  // pixel complete.
  auto first_own = [&](size_t i) {
    if (i >= list.size()) return list.size();
    while (i > 0 && i < list.size() && list[i].pixel == list[i - 1].pixel) ++i;
    return i;
  };
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) { add(first_own(b * kBlock), first_own((b + 1) * kBlock)); });
}

// The camera samples' split into passes: all samples of every pixel in one pass unless that
// batch would exceed max_batch_rays; then passes of whole samples; when even one sample of
// every pixel exceeds it, bands of rows of one sample each. Passes run band-major.
class PassPlan {
 public:
  struct Pass { int sample_begin, sample_end, row_begin, row_end; };

  explicit PassPlan(const RenderConfig& config) : spp_(config.spp), height_(config.height) {
    const size_t max_rays = config.camera_batch_limit();
    const size_t n_pixels = size_t(config.width) * size_t(config.height);
    per_pass_ = int(std::clamp<size_t>(max_rays / n_pixels, 1, size_t(spp_)));
    sample_passes_ = (spp_ + per_pass_ - 1) / per_pass_;
    band_rows_ = int(std::clamp<size_t>(max_rays / size_t(config.width), 1, size_t(height_)));
    bands_ = (height_ + band_rows_ - 1) / band_rows_;
  }
  int passes() const { return bands_ * sample_passes_; }
  Pass pass(int k) const {
    const int band = k / sample_passes_, sample_pass = k % sample_passes_;
    return {sample_pass * per_pass_, std::min(spp_, (sample_pass + 1) * per_pass_), band * band_rows_,
            std::min(height_, (band + 1) * band_rows_)};
  }

 private:
  int spp_, height_;
  int per_pass_ = 1, sample_passes_ = 1;  // samples per pass, passes per band
  int band_rows_ = 1, bands_ = 1;
};

}  // namespace

std::string samples_beyond_32_bits(const char* what, int width, int height, int spp) {
  return std::string(what) + ": width " + std::to_string(width) + " x height " + std::to_string(height) + " x spp " +
         std::to_string(spp) + " = " + std::to_string(uint64_t(width) * uint64_t(height) * uint64_t(spp)) +
         " camera samples, more than 2^32 - 1 (sample ids are 32-bit): lower spp, or average images of other seeds";
}

void RenderConfig::validate() const {
  if (width <= 0 || height <= 0 || width > 1 << 15 || height > 1 << 15)
    throw InputError("render: width and height must be in 1..32768");
  if (spp <= 0 || spp > 1 << 16) throw InputError("render: spp must be in 1..65536");
  if (uint64_t(width) * uint64_t(height) * uint64_t(spp) > (uint64_t(1) << 32) - 1)
    throw InputError(samples_beyond_32_bits("render", width, height, spp));
  if (max_depth < 0) throw InputError("render: max_depth must be >= 0");
  if (rr_depth < 0) throw InputError("render: rr_depth must be >= 0");
  if (light_samples < 1 || ao_samples < 1) throw InputError("render: light_samples and ao_samples must be >= 1");
  // 0 picks the default; a NaN or negative value would pick it silently too, and an infinite
  // offset sends every secondary ray from infinity (an AO image of open sky).
  if (!(ray_epsilon >= 0 && std::isfinite(ray_epsilon))) throw InputError("render: ray_epsilon must be finite and >= 0");
  if (!(ao_radius >= 0 && std::isfinite(ao_radius))) throw InputError("render: ao_radius must be finite and >= 0");
  if (max_batch_rays < 0) throw InputError("render: max_batch_rays must be >= 0 (0 = 2^24)");
}

void generate_camera_rays(const Scene& scene, int width, int height, int spp, uint64_t seed,
                          RayBatch& rays, std::vector<PathState>* paths, int sample_begin, int sample_end,
                          int row_begin, int row_end) {
  const CameraRays camera(scene.camera, width, height);
  if (sample_end < 0 || sample_end > spp) sample_end = spp;
  if (row_end < 0 || row_end > height) row_end = height;
  const int per_pixel = sample_end - sample_begin;
  const size_t first_pixel = size_t(row_begin) * size_t(width);
  const size_t n = size_t(width) * size_t(row_end - row_begin) * size_t(per_pixel);
  rays.resize(n);
  if (paths) paths->resize(n);
  tbb::parallel_for(tbb::blocked_range<int>(row_begin, row_end), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < width; ++x) {
        const uint32_t pixel = uint32_t(y) * uint32_t(width) + uint32_t(x);
        for (int s = sample_begin; s < sample_end; ++s) {
          const PathSampler sampler{seed, pixel, uint32_t(s), 0};
          float fx, fy;
          pixel_sample_position(sampler, x, y, s, spp, fx, fy);
          const size_t i = (size_t(pixel) - first_pixel) * size_t(per_pixel) + size_t(s - sample_begin);
          rays.set(i, camera.generate(fx, fy, sampler.get(kDimLens), sampler.get(kDimLens + 1)));
          if (paths) (*paths)[i] = PathState{pixel, uint32_t(s), Vec3{1.0f}, true};
        }
      }
  });
}

// The batches of one bounce. They live across bounces and passes: their capacity is reused,
// so later bounces do not page-fault.
struct WavefrontIntegrator::Bounce {
  RayBatch rays;                   // this bounce's rays ...
  std::vector<PathState> paths;    // ... and their paths
  HitBatch hits;
  std::vector<ShadeOutput> outs;   // shading output per chunk of kShadeChunk paths
  RayBatch occlusion_rays;         // merged: shadow / AO rays ...
  std::vector<ShadeOutput::Contribution> occlusion;  // ... and what each adds if unoccluded
  std::vector<uint8_t> occluded;
  RayBatch next_rays;              // merged: the next bounce's rays and paths
  std::vector<PathState> next_paths;
};

// Shades every hit (or miss) of the bounce, chunks in parallel, into b.outs.
void WavefrontIntegrator::shade_bounce(const ShadeContext& ctx, Bounce& b) const {
  const size_t n = b.paths.size(), chunks = (n + kShadeChunk - 1) / kShadeChunk;
  b.outs.resize(chunks);
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    ShadeOutput& out = b.outs[c];
    for (size_t i = c * kShadeChunk, end = std::min(n, i + kShadeChunk); i < end; ++i) {
      const Ray ray = b.rays[i];
      const Hit hit = b.hits[i];
      if (!hit.hit()) { miss(ctx, b.paths[i], ray, out); continue; }
      const Hit refined = refine_hit(*ctx.scene, ray, hit);
      shade(ctx, b.paths[i], ray, surface_point(*ctx.scene, ray, refined), out);
    }
  });
}

// Merges the chunks' outputs in chunk order, the fixed order of every per-pixel sum: radiance
// into the film, occlusion rays and next paths into flat batches. Chunk offsets first, so the
// copies can run in parallel.
void WavefrontIntegrator::merge_bounce(Bounce& b, std::vector<Vec3>& film) {
  const size_t chunks = b.outs.size();
  std::vector<size_t> occ_at(chunks + 1, 0), next_at(chunks + 1, 0);
  for (size_t c = 0; c < chunks; ++c) {
    occ_at[c + 1] = occ_at[c] + b.outs[c].occlusion_.size();
    next_at[c + 1] = next_at[c] + b.outs[c].next_.size();
    for (const auto& r : b.outs[c].radiance_) film[r.pixel] += r.value;
  }
  b.occlusion.resize(occ_at[chunks]);
  b.next_paths.resize(next_at[chunks]);
  b.occlusion_rays.resize(occ_at[chunks]);
  b.next_rays.resize(next_at[chunks]);
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    ShadeOutput& out = b.outs[c];
    for (size_t k = 0; k < out.occlusion_.size(); ++k) {
      b.occlusion_rays.set(occ_at[c] + k, out.occlusion_rays_[k]);
      b.occlusion[occ_at[c] + k] = out.occlusion_[k];
    }
    for (size_t k = 0; k < out.next_.size(); ++k) {
      b.next_rays.set(next_at[c] + k, out.next_rays_[k]);
      b.next_paths[next_at[c] + k] = out.next_[k];
    }
    out.clear();
  });
}

Image WavefrontIntegrator::render(const Scene& scene, const Accelerator& accel, const RenderConfig& config,
                                  RenderStats* stats_out) const {
  config.validate();
  const auto start = SteadyClock::now();
  RenderStats stats;
  const LightSampler lights(scene);
  const Bounds3 bounds = scene.bounds();
  ShadeContext ctx;
  ctx.scene = &scene;
  ctx.config = &config;
  ctx.lights = &lights;
  ctx.epsilon = config.ray_epsilon > 0 ? config.ray_epsilon : scene_ray_epsilon(bounds);
  ctx.ao_radius = ao_radius_for(config.ao_radius, bounds);

  std::vector<Vec3> film(size_t(config.width) * size_t(config.height));
  const PassPlan plan(config);
  const int passes = plan.passes();

  uint64_t rays_traced = 0;
  int pass = 0;
  auto trace = [&](const BatchInfo& info, const RayBatch& batch, HitBatch* hits, std::vector<uint8_t>* occluded) {
    if (config.on_batch) config.on_batch(info, batch);
    BatchStats bs;
    bs.info = info;
    bs.rays = batch.size();
    TraceStats* counters = config.count ? &bs.counters : nullptr;
    const auto t = SteadyClock::now();
    if (hits) accel.intersect(batch, *hits, counters);
    else accel.occluded(batch, *occluded, counters);
    bs.trace_ms = ms_since(t);
    stats.trace_ms += bs.trace_ms;
    stats.batches.push_back(bs);
    rays_traced += batch.size();
    if (config.on_progress)
      config.on_progress({info.bounce, max_bounce(config), pass, passes, rays_traced,
                          ms_since(start) / 1000.0});
  };

  Bounce b;
  for (pass = 0; pass < passes; ++pass) {
    auto t0 = SteadyClock::now();
    const PassPlan::Pass p = plan.pass(pass);
    generate_camera_rays(scene, config.width, config.height, config.spp, config.seed, b.rays, &b.paths,
                         p.sample_begin, p.sample_end, p.row_begin, p.row_end);
    stats.raygen_ms += ms_since(t0);
    for (int bounce = 0; !b.paths.empty(); ++bounce) {
      ctx.bounce = bounce;
      trace({bounce, bounce == 0 ? "primary" : continuation_kind(), false}, b.rays, &b.hits, nullptr);
      t0 = SteadyClock::now();
      shade_bounce(ctx, b);
      merge_bounce(b, film);
      stats.shading_ms += ms_since(t0);
      if (!b.occlusion_rays.empty()) {
        trace({bounce, occlusion_kind(), true}, b.occlusion_rays, nullptr, &b.occluded);
        t0 = SteadyClock::now();
        accumulate_unoccluded(film, b.occlusion, b.occluded);
        stats.shading_ms += ms_since(t0);
      }
      std::swap(b.rays, b.next_rays);
      std::swap(b.paths, b.next_paths);
    }
  }

  Image image(config.width, config.height);
  const float inv_spp = 1.0f / float(config.spp);
  for (size_t i = 0; i < film.size(); ++i) image.pixels[i] = film[i] * inv_spp;
  stats.total_ms = ms_since(start);
  if (stats_out) *stats_out = std::move(stats);
  return image;
}

}  // namespace rayscout
