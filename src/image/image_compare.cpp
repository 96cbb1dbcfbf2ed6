// Error metrics between images and the false-colour difference picture.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "rayscout/core/input_error.h"
#include "rayscout/image/image.h"

namespace rayscout {
namespace {

void check_same_size(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw InputError("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                     " vs " + std::to_string(b.width) + "x" + std::to_string(b.height));
}

}  // namespace

ImageError compare_images(const Image& a, const Image& b) {
  check_same_size(a, b);
  double se = 0, rel = 0, max_abs = 0;
  ImageError e;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = double(a.pixels[i][c]) - double(b.pixels[i][c]);
      const double r = b.pixels[i][c];
      e.nonfinite += !std::isfinite(a.pixels[i][c]) + !std::isfinite(b.pixels[i][c]);
      se += d * d;
      rel += d * d / (r * r + 0.01);
      // std::max would drop a NaN difference; keep it, so that max_abs is NaN too.
      if (!(std::fabs(d) <= max_abs)) max_abs = std::isnan(max_abs) ? max_abs : std::fabs(d);
    }
  const double n = 3.0 * double(std::max<size_t>(1, a.pixels.size()));
  e.rmse = std::sqrt(se / n);
  e.rel_mse = rel / n;
  e.psnr = se == 0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(n / se);
  e.max_abs = max_abs;
  return e;
}

Image difference_image(const Image& a, const Image& b, float scale) {
  check_same_size(a, b);
  if (!std::isfinite(scale)) throw InputError("difference scale " + std::to_string(scale) + " is not finite");
  std::vector<float> diff(a.pixels.size());
  float largest = 0;
  for (size_t i = 0; i < diff.size(); ++i) {
    const Vec3 d = abs(a.pixels[i] - b.pixels[i]);
    diff[i] = (d.x + d.y + d.z) / 3.0f;
    if (std::isfinite(diff[i])) largest = std::max(largest, diff[i]);
  }
  if (scale <= 0) scale = largest > 0 ? largest : 1.0f;
  // A short piecewise-linear ramp: black, blue, cyan, green, yellow, red.
  static constexpr std::array<Vec3, 6> ramp = {Vec3{0, 0, 0}, Vec3{0, 0, 1}, Vec3{0, 1, 1},
                                               Vec3{0, 1, 0}, Vec3{1, 1, 0}, Vec3{1, 0, 0}};
  Image out(a.width, a.height);
  for (size_t i = 0; i < diff.size(); ++i) {
    // NaN or inf (a broken pixel on either side): the top of the ramp, not int(NaN).
    const float s = (std::isfinite(diff[i]) ? std::clamp(diff[i] / scale, 0.0f, 1.0f) : 1.0f) * float(ramp.size() - 1);
    const int k = std::min(int(s), int(ramp.size()) - 2);
    const float f = s - float(k);
    // ramp colours are display values: decode so that write_image's sRGB encoding restores them
    const Vec3 c = ramp[k] * (1.0f - f) + ramp[k + 1] * f;
    out.pixels[i] = {srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z)};
  }
  return out;
}

}  // namespace rayscout
