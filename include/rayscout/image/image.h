// Image: a linear-RGB float picture, its file formats (PNG, EXR, PFM) and error metrics.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "rayscout/core/vec3.h"

namespace rayscout {

/// A width x height picture of linear RGB radiance, row-major, top row first.
struct Image {
  int width = 0, height = 0;
  std::vector<Vec3> pixels;

  Image() = default;
  /// A black image of the given size.
  Image(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h)) {}
  /// Pixel (x, y), y = 0 the top row.
  Vec3& at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
  const Vec3& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

/// Writes by extension: .png (clamped to [0, 1], sRGB-encoded, 8 bit, via stb; NaN as 0, +inf
/// as 1), .exr (32-bit float RGB, OpenEXR), .pfm (32-bit float RGB, little endian); the float
/// formats keep NaN and inf. Throws InputError for another extension or a file that cannot be
/// written.
void write_image(const Image& image, const std::filesystem::path& path);

/// Whether write_image sRGB-encodes the pixels for this path's format (.png, any case): a
/// value v is then stored as the 8-bit code of srgb(v), else as v itself.
bool writes_srgb(const std::filesystem::path& path);

/// Throws InputError when write_image could not write `path`: another extension than .png,
/// .exr or .pfm, a directory, a parent folder that does not exist, or (when width and height
/// are given) an image too large for the format. The message starts with `label` (e.g.
/// "--skip-image s.bmp"; empty: the path). Commands call it before their work, so a mistyped
/// --out never costs a finished render.
void check_image_path(const std::filesystem::path& path, int width = 0, int height = 0,
                      const std::string& label = "");

/// Reads .exr, .pfm or .png (8-bit sRGB decoded to linear). Throws InputError naming the file.
Image read_image(const std::filesystem::path& path);

/// Error of image a against reference b, over every pixel and channel. A NaN or infinite
/// channel value on either side makes rmse, rel_mse and max_abs NaN or +inf (and psnr NaN
/// or -inf): such an image never passes for a close one.
struct ImageError {
  double rmse = 0;       ///< sqrt(mean (a - b)^2)
  /// mean (a - b)^2 / (b^2 + 0.01): relative MSE as denoising papers use it, the 0.01 keeping
  /// dark pixels from dominating (pbrt-v4's MRSE divides by (b + 0.01)^2 instead)
  double rel_mse = 0;
  double psnr = 0;       ///< 10 log10(1 / mse), peak value 1; +inf for identical images
  double max_abs = 0;    ///< max |a - b|
  size_t nonfinite = 0;  ///< channel values that are NaN or infinite in a or b
};

/// Compares two images of equal size (throws InputError otherwise); b is the reference.
ImageError compare_images(const Image& a, const Image& b);

/// A false-colour picture of |a - b| (mean over channels), black = 0 through blue, green,
/// yellow to red = scale; scale <= 0 uses the largest finite difference. A pixel whose
/// difference is NaN or infinite is red. Throws InputError for a NaN or infinite scale.
Image difference_image(const Image& a, const Image& b, float scale = 0);

/// sRGB encoding of one linear channel value clamped to [0, 1] (IEC 61966-2-1).
float linear_to_srgb(float linear);
/// Linear value of one sRGB-encoded channel in [0, 1].
float srgb_to_linear(float encoded);

}  // namespace rayscout
