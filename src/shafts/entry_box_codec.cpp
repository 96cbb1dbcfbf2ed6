// EntryBoxCodec: the encoder's exact planes and the decoder's float constants of one grid box.
#include "entry_box_codec.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rayscout::detail {

EntryBoxCodec::EntryBoxCodec(const Bounds3& grid_box) : box_(grid_box) {
  const Bounds3& b = box_;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a) {
    const double lo = b.lo[a], step = (double(b.hi[a]) - lo) / 255.0;
    for (int q = 0; q < 256; ++q) {
      const double x = q == 255 ? double(b.hi[a]) : lo + step * q;
      float down = float(x), up = float(x);
      if (double(down) > x) down = std::nextafter(down, -kInf);
      if (double(up) < x) up = std::nextafter(up, kInf);
      plane_down_[a][q] = q == 0 ? std::min(down, b.lo[a]) : down;
      plane_up_[a][q] = q == 255 ? std::max(up, b.hi[a]) : up;
    }
    base_[a] = b.lo[a];
    step_[a] = (b.hi[a] - b.lo[a]) / 255.0f;
  }
  // Rounding of lo + q step stays within a few ulps of the largest coordinate.
  const float largest_coord = max_component(max(abs(b.lo), abs(b.hi)));
  margin_ = (largest_coord + max_component(b.diagonal())) * (1.0f / 1048576.0f);
}

QBox EntryBoxCodec::encode(const Bounds3& box) const {
  QBox q{};
  const Bounds3& g = box_;
  for (int a = 0; a < 3; ++a) {
    const double ext = double(g.hi[a]) - g.lo[a];
    int lo = 0, hi = 255;
    if (ext > 0) {
      lo = std::clamp(int(std::floor((double(box.lo[a]) - g.lo[a]) / ext * 255.0)), 0, 255);
      hi = std::clamp(int(std::ceil((double(box.hi[a]) - g.lo[a]) / ext * 255.0)), 0, 255);
    }
    while (lo > 0 && plane_down_[a][lo] > box.lo[a]) --lo;  // the decoded box must contain box
    while (hi < 255 && plane_up_[a][hi] < box.hi[a]) ++hi;
    q.lo[a] = uint8_t(lo);
    q.hi[a] = uint8_t(hi);
  }
  return q;
}

}  // namespace rayscout::detail
