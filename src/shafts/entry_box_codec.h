// EntryBoxCodec (private): the one encoding of list-entry boxes, encoder and decoder together.
#pragma once

#include <cstdint>

#include "rayscout/core/bounds3.h"

namespace rayscout::detail {

/// A list entry's box as 6 bytes: per axis the indices of two of the 256 planes that split
/// the grid box into 255 equal steps.
struct QBox {
  uint8_t lo[3], hi[3];
};

/// Quantises node boxes outward on the grid box and turns the stored bytes back into boxes
/// that contain them. Both sides live here because they must agree on the box, the step and
/// the rounding: encode() picks planes exactly (double, rounded outward to float), the
/// decoder evaluates base + q step in float and widens it by margin, which exceeds that
/// expression's rounding, so a decoded box always contains the encoded one.
class EntryBoxCodec {
 public:
  explicit EntryBoxCodec(const Bounds3& grid_box);

  /// The smallest QBox whose planes contain box (clamped to the grid box).
  QBox encode(const Bounds3& box) const;

  /// Decoding, as the entry filter evaluates it (per axis a): lo = base + q step - margin,
  /// hi = base + q step + margin.
  float base(int a) const { return base_[a]; }
  float step(int a) const { return step_[a]; }
  float margin() const { return margin_; }

 private:
  float base_[3], step_[3], margin_;
  Bounds3 box_;
  /// Plane q of axis a in exact arithmetic, rounded down / up to float (encode() only).
  float plane_down_[3][256], plane_up_[3][256];
};

}  // namespace rayscout::detail
