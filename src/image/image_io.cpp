// Image files: PNG through stb, EXR through OpenEXR, PFM by hand.
#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>

// stb is third-party code compiled here, privately (static), so its warnings are not ours.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb_image.h>
#pragma GCC diagnostic pop

#include "rayscout/core/file_extension.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/output_path.h"
#include "rayscout/image/image.h"

namespace rayscout {
namespace {

/// The largest image side rayscout renders (--width, --height) and reads.
constexpr int kMaxImageSide = 32768;

void check_size(const Image& image, const std::filesystem::path& path) {
  if (image.width <= 0 || image.height <= 0 || image.pixels.size() != size_t(image.width) * size_t(image.height))
    throw InputError(path.string() + ": image has no pixels or a wrong pixel count");
}

// Refuses an image whose header claims sides beyond rayscout's largest image, before its
// pixels are allocated (a small corrupt file can claim gigabytes). `what` names the header.
void check_side_lengths(const std::filesystem::path& path, const char* what, int64_t w, int64_t h) {
  if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
    throw InputError(path.string() + ": " + what + " of " + std::to_string(w) + "x" + std::to_string(h) +
                     " pixels: not an image rayscout reads (1 to " + std::to_string(kMaxImageSide) +
                     " pixels a side)");
}

void write_png(const Image& image, const std::filesystem::path& path) {
  std::vector<uint8_t> bytes(image.pixels.size() * 3);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c)
      bytes[3 * i + c] = uint8_t(std::lround(255.0f * linear_to_srgb(image.pixels[i][c])));
  // Encoded in memory and written by write_file: stb's own file writer ignores write errors.
  std::string png;
  auto append = [](void* out, void* data, int size) {
    static_cast<std::string*>(out)->append(static_cast<char*>(data), size_t(size));
  };
  if (!stbi_write_png_to_func(append, &png, image.width, image.height, 3, bytes.data(), image.width * 3))
    throw InputError(path.string() + ": cannot encode PNG");
  write_file(path, png, "image");
}

Image read_png(const std::filesystem::path& path) {
  int w = 0, h = 0, n = 0;
  // stb keeps its last failure reason until the next failure, and some corrupt data fails
  // without one: clear it (stb's own static in this file, no API) so that an earlier file's
  // error is never reported for this one.
  stbi__g_failure_reason = nullptr;
  auto fail = [&] {
    const char* why = stbi_failure_reason();  // null for some corrupt data: stb returns without a reason
    return InputError(path.string() + ": cannot read PNG (" + (why ? why : "corrupt data") + ")");
  };
  // The header first, as for EXR: a 389 KB PNG of 20000 x 20000 pixels decoded to 6 GB.
  if (!stbi_info(path.string().c_str(), &w, &h, &n)) throw fail();
  check_side_lengths(path, "PNG", w, h);
  std::unique_ptr<uint8_t, void (*)(void*)> data(stbi_load(path.string().c_str(), &w, &h, &n, 3), stbi_image_free);
  if (!data) throw fail();
  std::array<float, 256> linear;
  for (int v = 0; v < 256; ++v) linear[v] = srgb_to_linear(float(v) / 255.0f);
  Image image(w, h);
  for (size_t i = 0; i < image.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) image.pixels[i][c] = linear[data.get()[3 * i + c]];
  return image;
}

void write_exr(const Image& image, const std::filesystem::path& path) {
  // Encoded in memory and written by write_file: OpenEXR's own file flushes last in a
  // destructor that drops errors.
  Imf::StdOSStream stream;
  try {
    Imf::Header header(image.width, image.height);
    for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(stream, header);
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(const_cast<Vec3*>(image.pixels.data()));
    const size_t xs = sizeof(Vec3), ys = sizeof(Vec3) * size_t(image.width);
    fb.insert("R", Imf::Slice(Imf::FLOAT, base + offsetof(Vec3, x), xs, ys));
    fb.insert("G", Imf::Slice(Imf::FLOAT, base + offsetof(Vec3, y), xs, ys));
    fb.insert("B", Imf::Slice(Imf::FLOAT, base + offsetof(Vec3, z), xs, ys));
    file.setFrameBuffer(fb);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    throw InputError(path.string() + ": cannot write EXR: " + e.what());
  }
  write_file(path, stream.str(), "image");
}

Image read_exr(const std::filesystem::path& path) {
  try {
    Imf::InputFile file(path.string().c_str());
    const auto dw = file.header().dataWindow();
    // The header is checked before the pixels are allocated: a corrupt or hostile data window
    // of a small file could ask for gigabytes.
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    check_side_lengths(path, "EXR data window", w, h);
    // And a header that claims more scan lines than the file holds is caught here too.
    if (!file.isComplete()) throw InputError(path.string() + ": incomplete EXR: its pixel data is missing or cut short");
    Image image{int(w), int(h)};
    char* base = reinterpret_cast<char*>(image.pixels.data());
    const size_t xs = sizeof(Vec3), ys = sizeof(Vec3) * size_t(image.width);
    // OpenEXR addresses slices by absolute pixel coordinates: shift the base to the data window.
    base -= (ptrdiff_t(dw.min.x) * ptrdiff_t(xs) + ptrdiff_t(dw.min.y) * ptrdiff_t(ys));
    // R, G, B (one missing reads as 0), else a grey Y; a file with neither (only a layer's
    // "diffuse.R", say) would read as black, so it is refused naming the channels it has.
    const Imf::ChannelList& channels = file.header().channels();
    auto has = [&](const char* name) { return channels.findChannel(name) != nullptr; };
    const bool rgb = has("R") || has("G") || has("B");
    if (!rgb && !has("Y")) {
      std::string names;
      for (auto c = channels.begin(); c != channels.end(); ++c) names += (names.empty() ? "" : ", ") + std::string(c.name());
      throw InputError(path.string() + ": EXR without any of the channels R, G, B or Y; it has: " +
                       (names.empty() ? "none" : names));
    }
    Imf::FrameBuffer fb;
    fb.insert(rgb ? "R" : "Y", Imf::Slice(Imf::FLOAT, base + offsetof(Vec3, x), xs, ys, 1, 1, 0.0));
    if (rgb) {
      fb.insert("G", Imf::Slice(Imf::FLOAT, base + offsetof(Vec3, y), xs, ys, 1, 1, 0.0));
      fb.insert("B", Imf::Slice(Imf::FLOAT, base + offsetof(Vec3, z), xs, ys, 1, 1, 0.0));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    if (!rgb)
      for (Vec3& p : image.pixels) p = Vec3(p.x);
    return image;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path.string() + ": cannot read EXR: " + e.what());
  }
}

// PFM: "PF\n<w> <h>\n<scale>\n", then float RGB rows bottom to top; a negative scale means
// little endian.
void write_pfm(const Image& image, const std::filesystem::path& path) {
  std::string pfm = "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
  static_assert(std::endian::native == std::endian::little);
  const size_t row_bytes = sizeof(Vec3) * size_t(image.width);
  pfm.reserve(pfm.size() + row_bytes * size_t(image.height));
  for (int y = image.height - 1; y >= 0; --y) pfm.append(reinterpret_cast<const char*>(&image.at(0, y)), row_bytes);
  write_file(path, pfm, "image");
}

Image read_pfm(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open");
  std::string magic;
  int w = 0, h = 0;
  double scale = 0;
  in >> magic >> w >> h >> scale;
  if (!in || (magic != "PF" && magic != "Pf") || w <= 0 || h <= 0 || scale == 0)
    throw InputError(path.string() + ": not a PFM file (bad header)");
  check_side_lengths(path, "PFM", w, h);
  // One whitespace byte ends the header; any other byte would be taken from the pixels.
  const int separator = in.get();
  if (!std::isspace(separator))
    throw InputError(path.string() + ": not a PFM file (bad header: no whitespace after the scale)");
  const int channels = magic == "PF" ? 3 : 1;
  // Check the size before allocating: a header may claim 65536 x 65536 pixels (51 GB).
  const std::streamoff data_start = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff data_bytes = in.tellg() - data_start;
  const uint64_t need = uint64_t(w) * uint64_t(h) * uint64_t(channels) * sizeof(float);
  const std::string size = std::to_string(w) + "x" + std::to_string(h) + " pixels need ";
  if (data_start < 0 || data_bytes < 0 || uint64_t(data_bytes) < need)
    throw InputError(path.string() + ": truncated PFM data: " + size + std::to_string(need) + " bytes, the file has " +
                     std::to_string(std::max<std::streamoff>(data_bytes, 0)));
  // More data than the pixels is a wrong header, not padding. Windows line ends (CR LF) leave
  // the LF as a data byte: every float would be read one byte off.
  if (const uint64_t more = uint64_t(data_bytes) - need; more > 0)
    throw InputError(path.string() + ": " + std::to_string(more) + (more == 1 ? " byte" : " bytes") + " more than " +
                     size + "(" + std::to_string(need) + ")" +
                     (separator == '\r' ? ": the header ends in CR LF (PFM allows one whitespace byte after the scale)" : ""));
  in.seekg(data_start);
  std::vector<float> row(size_t(w) * channels);
  Image image(w, h);
  for (int y = h - 1; y >= 0; --y) {
    in.read(reinterpret_cast<char*>(row.data()), std::streamsize(row.size() * sizeof(float)));
    if (!in) throw InputError(path.string() + ": truncated PFM data");
    for (float& f : row)
      if (scale > 0) f = std::bit_cast<float>(__builtin_bswap32(std::bit_cast<uint32_t>(f)));
    for (int x = 0; x < w; ++x)
      image.at(x, y) = channels == 3 ? Vec3(row[3 * x], row[3 * x + 1], row[3 * x + 2]) : Vec3(row[x]);
  }
  return image;
}

}  // namespace

float linear_to_srgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);  // NaN falls through clamp unchanged; map it to black
  if (!(v == v)) return 0.0f;
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float srgb_to_linear(float e) {
  return e <= 0.04045f ? e / 12.92f : std::pow((e + 0.055f) / 1.055f, 2.4f);
}

// "unknown image format ''" told a user who wrote --out render nothing about what was missing.
static std::string unknown_format(const std::string& ext) {
  return ext.empty() ? "no file extension to tell the image format by (use .png, .exr or .pfm)"
                     : "unknown image format '" + ext + "' (use .png, .exr or .pfm)";
}

void check_image_path(const std::filesystem::path& path, int width, int height, const std::string& label) {
  const std::string name = label.empty() ? path.string() : label;
  std::error_code ec;
  if (path.empty()) throw InputError((label.empty() ? "" : label + ": ") + "no image file named (an empty path)");
  if (std::filesystem::is_directory(path, ec)) throw InputError(name + ": is a directory, not an image file");
  const std::string ext = lower_extension(path);
  if (ext != ".png" && ext != ".exr" && ext != ".pfm")
    throw InputError(name + ": " + unknown_format(ext));
  // stb's PNG writer sizes its filtered rows, (3 width + 1) height bytes, in an int.
  if (ext == ".png" && (3 * int64_t(width) + 1) * int64_t(height) > INT_MAX)
    throw InputError(name + ": a PNG of " + std::to_string(width) + "x" + std::to_string(height) +
                     " pixels is beyond stb's PNG writer (at most 2^31 bytes of rows, 32768x21845); write .exr or .pfm");
  check_output_path(path, name);
}

bool writes_srgb(const std::filesystem::path& path) { return lower_extension(path) == ".png"; }

void write_image(const Image& image, const std::filesystem::path& path) {
  check_size(image, path);
  check_image_path(path, image.width, image.height);
  const std::string ext = lower_extension(path);
  if (ext == ".png") return write_png(image, path);
  if (ext == ".exr") return write_exr(image, path);
  write_pfm(image, path);
}

Image read_image(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path.string() + ": no such file");
  // A device or pipe has no size to check a header against (/dev/zero as a .pfm was read
  // until memory ran out).
  if (std::filesystem::is_directory(path, ec)) throw InputError(path.string() + ": is a directory, not an image file");
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path.string() + ": is not a regular file (a device or a pipe), not an image file");
  const std::string ext = lower_extension(path);
  if (ext == ".png") return read_png(path);
  if (ext == ".exr") return read_exr(path);
  if (ext == ".pfm") return read_pfm(path);
  throw InputError(path.string() + ": " + unknown_format(ext));
}

}  // namespace rayscout
