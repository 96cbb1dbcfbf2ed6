// Image files (PNG, EXR, PFM) round trip; error metrics on images with known answers.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

// stb's decoder of our own, to read written PNGs without rayscout's reader.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "rayscout/core/input_error.h"
#include "rayscout/image/image.h"

namespace rayscout {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("rayscout_image_test_" + std::to_string(::getpid()) + "_" + name);
}

// A non-square gradient with values beyond [0, 1] and exact binary fractions.
Image test_image() {
  Image img(7, 5);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.at(x, y) = {x / 6.0f, y / 4.0f, 0.1f * float(x + 7 * y) - 1.5f};
  img.at(3, 2) = {1e6f, 1e-20f, 3.25f};
  return img;
}

// The data of a 2x1 PFM (little-endian floats, as the header's -1.0 says): 0.1, 0.2, ... 0.6.
std::string two_pixel_pfm_data() {
  std::string px(24, '\0');
  const float values[6] = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};
  std::memcpy(px.data(), values, sizeof values);
  return px;
}

bool bit_equal(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

TEST(ImageIo, FloatFormatsRoundTripExactly) {
  const Image img = test_image();
  for (const char* ext : {".exr", ".pfm", ".PFM"}) {
    const fs::path p = temp_file(std::string("float") + ext);
    write_image(img, p);
    EXPECT_TRUE(bit_equal(read_image(p), img)) << ext;
    fs::remove(p);
  }
}

TEST(ImageIo, PngIsClampedSrgbWithin8Bits) {
  const Image img = test_image();
  const fs::path p = temp_file("ldr.png");
  write_image(img, p);
  const Image back = read_image(p);
  ASSERT_EQ(back.width, img.width);
  ASSERT_EQ(back.height, img.height);
  for (size_t i = 0; i < img.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float expected = std::clamp(img.pixels[i][c], 0.0f, 1.0f);
      // half a code value in sRGB space, mapped back to linear
      EXPECT_NEAR(linear_to_srgb(back.pixels[i][c]), linear_to_srgb(expected), 0.5f / 255.0f + 1e-6f);
    }
  fs::remove(p);
}

// As write_image documents: a PNG stores NaN as black and +inf as white; EXR and PFM keep them.
TEST(ImageIo, NonFinitePixelsInEachFormat) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  Image img(3, 1);
  img.at(0, 0) = Vec3(nan);
  img.at(1, 0) = Vec3(inf);
  img.at(2, 0) = Vec3(-inf);
  for (const char* ext : {".png", ".exr", ".pfm"}) {
    const fs::path p = temp_file(std::string("nonfinite") + ext);
    write_image(img, p);
    const Image back = read_image(p);
    fs::remove(p);
    ASSERT_EQ(back.pixels.size(), 3u) << ext;
    if (std::string(ext) == ".png") {
      EXPECT_EQ(back.at(0, 0), Vec3(0.0f)) << ext;
      EXPECT_EQ(back.at(1, 0), Vec3(1.0f)) << ext;
      EXPECT_EQ(back.at(2, 0), Vec3(0.0f)) << ext;
    } else {
      EXPECT_TRUE(std::isnan(back.at(0, 0).x)) << ext;
      EXPECT_EQ(back.at(1, 0), Vec3(inf)) << ext;
      EXPECT_EQ(back.at(2, 0), Vec3(-inf)) << ext;
    }
  }
}

// The files themselves, read without rayscout's readers (so a flip on both sides of the round
// trips above cannot pass): PNG and EXR store the top row first, PFM the bottom row first.
TEST(ImageIo, TopRowIsWhereEachFileFormatPutsIt) {
  Image img(2, 2);
  img.at(0, 0) = Vec3{1, 0, 0};  // top left red
  {
    const fs::path p = temp_file("orient_raw.png");
    write_image(img, p);
    int w = 0, h = 0, n = 0;
    unsigned char* px = stbi_load(p.string().c_str(), &w, &h, &n, 3);
    ASSERT_NE(px, nullptr);
    EXPECT_EQ(w, 2);
    EXPECT_EQ(h, 2);
    EXPECT_EQ(px[0], 255);      // first row, first pixel, red
    EXPECT_EQ(px[2 * 3], 0);    // second row, first pixel
    stbi_image_free(px);
    fs::remove(p);
  }
  {
    const fs::path p = temp_file("orient_raw.exr");
    write_image(img, p);
    Imf::InputFile in(p.string().c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    ASSERT_EQ(dw.max.x - dw.min.x + 1, 2);
    ASSERT_EQ(dw.max.y - dw.min.y + 1, 2);
    float red[4] = {-1, -1, -1, -1};
    Imf::FrameBuffer fb;
    fb.insert("R", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(red - dw.min.x - 2 * dw.min.y), sizeof(float),
                              2 * sizeof(float)));
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    EXPECT_EQ(red[0], 1.0f);  // row dw.min.y: the top
    EXPECT_EQ(red[2], 0.0f);
    fs::remove(p);
  }
  {
    const fs::path p = temp_file("orient_raw.pfm");
    write_image(img, p);
    std::ifstream in(p, std::ios::binary);
    std::string magic, scale;
    int w = 0, h = 0;
    in >> magic >> w >> h >> scale;
    in.get();  // the one whitespace byte after the scale
    ASSERT_EQ(magic, "PF");
    ASSERT_EQ(scale, "-1.0");  // little endian
    float rgb[12];
    ASSERT_TRUE(in.read(reinterpret_cast<char*>(rgb), sizeof(rgb)));
    EXPECT_EQ(rgb[0], 0.0f);  // first stored row: the bottom one
    EXPECT_EQ(rgb[6], 1.0f);  // second stored row, first pixel, red: the top one
    fs::remove(p);
  }
}

TEST(ImageIo, SrgbCurveKnownValues) {
  EXPECT_FLOAT_EQ(linear_to_srgb(0.0f), 0.0f);
  EXPECT_FLOAT_EQ(linear_to_srgb(1.0f), 1.0f);
  EXPECT_NEAR(linear_to_srgb(0.18f), 0.4614f, 1e-4f);
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.2140f, 1e-4f);
  EXPECT_FLOAT_EQ(linear_to_srgb(5.0f), 1.0f);
  EXPECT_FLOAT_EQ(linear_to_srgb(std::nanf("")), 0.0f);
  // Either side of each curve's knee (0.0031308 linear, 0.04045 encoded): a knee at the other
  // curve's value, or a slope of 12 for 12.92, passed the values above.
  EXPECT_NEAR(linear_to_srgb(0.002f), 12.92f * 0.002f, 1e-7f);
  EXPECT_NEAR(linear_to_srgb(0.01f), 0.099853f, 1e-5f);
  EXPECT_NEAR(srgb_to_linear(0.02f), 0.02f / 12.92f, 1e-8f);
  EXPECT_NEAR(srgb_to_linear(0.05f), 0.0039359f, 1e-6f);
}

TEST(ImageIo, BadInputThrows) {
  EXPECT_THROW(read_image(temp_file("missing.exr")), InputError);
  EXPECT_THROW(write_image(test_image(), temp_file("x.bmp")), InputError);
  EXPECT_THROW(write_image(Image(), temp_file("empty.png")), InputError);
  const fs::path junk = temp_file("junk.pfm");
  std::ofstream(junk) << "P6\n1 1\n255\nabc";
  EXPECT_THROW(read_image(junk), InputError);
  std::ofstream(junk) << "PF\n4 4\n-1.0\nshort";
  EXPECT_THROW(read_image(junk), InputError);
  const fs::path bad_exr = temp_file("junk.exr"), bad_png = temp_file("junk.png");
  std::ofstream(bad_exr) << "not an exr";
  std::ofstream(bad_png) << "not a png";
  EXPECT_THROW(read_image(bad_exr), InputError);
  EXPECT_THROW(read_image(bad_png), InputError);
  for (const auto& p : {junk, bad_exr, bad_png}) fs::remove(p);
}

// The InputError message of reading p (empty if it reads), then removes p.
std::string read_error(const fs::path& p) {
  std::string msg;
  try {
    read_image(p);
  } catch (const InputError& e) {
    msg = e.what();
  }
  fs::remove(p);
  return msg;
}

// PFM files as other programs write them: big endian (a positive scale) and greyscale ("Pf",
// one float per pixel), rows bottom to top. Bytes spelled out, not written by write_image.
TEST(ImageIo, BigEndianAndGreyscalePfmFilesRead) {
  auto floats = [](std::initializer_list<float> values, bool big_endian) {
    std::string bytes;
    for (float f : values) {
      uint32_t u = std::bit_cast<uint32_t>(f);
      if (big_endian) u = __builtin_bswap32(u);
      bytes.append(reinterpret_cast<const char*>(&u), 4);
    }
    return bytes;
  };
  const fs::path p = temp_file("be.pfm");
  std::ofstream(p, std::ios::binary) << "PF\n2 2\n1.0\n"
                                     << floats({1, 2, 3, 4, 5, 6, 0.5f, -7, 1e6f, 8, 9, 10}, true);
  Image img = read_image(p);
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 2);
  EXPECT_EQ(img.at(0, 1), Vec3(1, 2, 3));  // the file's first row is the bottom one
  EXPECT_EQ(img.at(1, 1), Vec3(4, 5, 6));
  EXPECT_EQ(img.at(0, 0), Vec3(0.5f, -7, 1e6f));
  EXPECT_EQ(img.at(1, 0), Vec3(8, 9, 10));
  std::ofstream(p, std::ios::binary) << "Pf\n3 1\n-1.0\n" << floats({0.25f, 2, -3}, false);
  img = read_image(p);
  ASSERT_EQ(img.width, 3);
  ASSERT_EQ(img.height, 1);
  EXPECT_EQ(img.at(0, 0), Vec3(0.25f));
  EXPECT_EQ(img.at(1, 0), Vec3(2));
  EXPECT_EQ(img.at(2, 0), Vec3(-3));
  fs::remove(p);
}

// An EXR whose data window starts off the origin, (3, 5) to (5, 6), with channels R and B only:
// read_image returns the 3 x 2 pixels of the window, top row first, and 0 for the missing G.
TEST(ImageIo, ExrDataWindowOffTheOriginAndMissingChannels) {
  const fs::path p = temp_file("window.exr");
  const int w = 3, h = 2;
  std::vector<float> r(w * h), b(w * h);
  for (int i = 0; i < w * h; ++i) r[size_t(i)] = float(i) + 0.5f, b[size_t(i)] = -float(i) - 1;
  {
    const Imath::Box2i display({0, 0}, {9, 9}), data({3, 5}, {5, 6});
    Imf::Header header(display, data);
    header.channels().insert("R", Imf::Channel(Imf::FLOAT));
    header.channels().insert("B", Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(p.string().c_str(), header);
    Imf::FrameBuffer fb;
    // Slices are addressed by absolute pixel coordinates: base shifted to the window's corner.
    const ptrdiff_t shift = 3 + 5 * w;
    fb.insert("R", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(r.data() - shift), sizeof(float), sizeof(float) * w));
    fb.insert("B", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(b.data() - shift), sizeof(float), sizeof(float) * w));
    file.setFrameBuffer(fb);
    file.writePixels(h);
  }
  const Image img = read_image(p);
  ASSERT_EQ(img.width, w);
  ASSERT_EQ(img.height, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y * w + x);
      EXPECT_EQ(img.at(x, y), Vec3(r[i], 0.0f, b[i])) << x << " " << y;
    }
  fs::remove(p);
}

// A grey EXR (channel Y alone) reads as grey; one with none of R, G, B, Y (a layer's
// "diffuse.R") is refused naming its channels, instead of reading as black.
TEST(ImageIo, ExrGreyReadsAsGreyAndLayersOnlyAreRefused) {
  auto write_one_channel = [](const fs::path& p, const char* name, float value) {
    const int w = 2, h = 1;
    std::vector<float> c(w * h, value);
    Imf::Header header(w, h);
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(p.string().c_str(), header);
    Imf::FrameBuffer fb;
    fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(c.data()), sizeof(float), sizeof(float) * w));
    file.setFrameBuffer(fb);
    file.writePixels(h);
  };
  const fs::path grey = temp_file("grey.exr"), layer = temp_file("layer.exr");
  write_one_channel(grey, "Y", 0.25f);
  const Image img = read_image(grey);
  ASSERT_EQ(img.width, 2);
  EXPECT_EQ(img.at(0, 0), Vec3(0.25f));
  EXPECT_EQ(img.at(1, 0), Vec3(0.25f));
  fs::remove(grey);
  // Any one of R, G, B makes an RGB file (not only R): G alone reads as (0, G, 0).
  const fs::path green = temp_file("green.exr");
  write_one_channel(green, "G", 0.5f);
  EXPECT_EQ(read_image(green).at(1, 0), Vec3(0.0f, 0.5f, 0.0f));
  fs::remove(green);
  write_one_channel(layer, "diffuse.R", 0.5f);
  EXPECT_NE(read_error(layer).find("EXR without any of the channels R, G, B or Y; it has: diffuse.R"), std::string::npos);
}

// A device has no size to check a header against: refused, not read until memory runs out.
TEST(ImageIo, DeviceIsNotAnImage) {
  const fs::path link = temp_file("zero.pfm");
  fs::remove(link);
  fs::create_symlink("/dev/zero", link);
  EXPECT_NE(read_error(link).find("is not a regular file"), std::string::npos);
}

// Found by fuzzing: the PFM header's size was allocated (up to 51 GB) before the data was read.
TEST(ImageIo, PfmHugeHeaderIsCheckedAgainstTheFileSize) {
  const fs::path p = temp_file("huge.pfm");
  std::ofstream(p, std::ios::binary) << "PF\n32768 32768\n-1.0\n0123456789ab";
  const std::string msg = read_error(p);
  EXPECT_NE(msg.find("huge.pfm: truncated PFM data: 32768x32768 pixels need 12884901888 bytes, the file has 12"),
            std::string::npos)
      << msg;
}

// Found by fuzzing: a PFM holding more bytes than its header's pixels was read without a word,
// and a header with Windows line ends (CR LF) left the LF as the first data byte, so every
// float was shifted by a byte (values near 1e8 instead of 0.1 ... 0.6).
TEST(ImageIo, PfmWithMoreDataThanItsPixelsIsRefused) {
  const std::string px = two_pixel_pfm_data();
  const fs::path crlf = temp_file("crlf.pfm"), extra = temp_file("extra.pfm"), ok = temp_file("ok.pfm");
  std::ofstream(crlf, std::ios::binary) << "PF\r\n2 1\r\n-1.0\r\n" << px;
  std::ofstream(extra, std::ios::binary) << "PF\n2 1\n-1.0\n" << px << "abcd";
  std::ofstream(ok, std::ios::binary) << "PF\n2 1\n-1.0\n" << px;
  std::string msg = read_error(crlf);
  EXPECT_NE(msg.find("crlf.pfm: 1 byte more than 2x1 pixels need (24): the header ends in CR LF"), std::string::npos)
      << msg;
  msg = read_error(extra);
  EXPECT_NE(msg.find("extra.pfm: 4 bytes more than 2x1 pixels need (24)"), std::string::npos) << msg;
  const Image image = read_image(ok);
  fs::remove(ok);
  ASSERT_EQ(image.pixels.size(), 2u);
  EXPECT_EQ(image.pixels[1].z, 0.6f);
}

// Found by review: PFM allowed 65536 pixels a side where PNG and EXR stop at rayscout's
// largest image, 32768; a well-formed 40000x1 PFM read, the same image as EXR did not.
TEST(ImageIo, PfmSidesAreLimitedAsPngAndExr) {
  const fs::path p = temp_file("wide.pfm");
  write_image(Image(40000, 1), p);
  const std::string msg = read_error(p);
  EXPECT_NE(msg.find("wide.pfm: PFM of 40000x1 pixels: not an image rayscout reads (1 to 32768 pixels a side)"),
            std::string::npos)
      << msg;
}

// Found by review: the byte after the scale was taken as the separator whatever it was, so a
// header "-1.0X" read, and one with no separator at all said "truncated PFM data" (the first
// data byte had gone as the separator), not what was wrong.
TEST(ImageIo, PfmScaleMustBeFollowedByWhitespace) {
  const std::string px = two_pixel_pfm_data();
  const fs::path letter = temp_file("letter.pfm"), none = temp_file("none.pfm");
  std::ofstream(letter, std::ios::binary) << "PF\n2 1\n-1.0X" << px;
  std::ofstream(none, std::ios::binary) << "PF\n2 1\n-1.0" << px;
  for (const fs::path& p : {letter, none}) {
    const std::string name = p.filename().string(), msg = read_error(p);
    EXPECT_NE(msg.find(name + ": not a PFM file (bad header: no whitespace after the scale)"), std::string::npos)
        << msg;
  }
}

// An EXR's data window is checked before its pixels are allocated: a corrupt header of a
// small file asked for 1.2 GB and more. A well-formed file beyond rayscout's largest image
// (32768 a side) meets the same check.
TEST(ImageIo, ExrDataWindowIsCheckedBeforeAllocating) {
  const fs::path p = temp_file("wide.exr");
  write_image(Image(40000, 1), p);
  const std::string msg = read_error(p);
  EXPECT_NE(msg.find("wide.exr: EXR data window of 40000x1 pixels"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("cannot read EXR"), std::string::npos) << "said once, not wrapped: " << msg;
}

// Found by review: a 389 KB PNG of 20000x20000 pixels decoded to 6 GB; the header is checked
// first, as for EXR. And stb's PNG writer sizes its rows in an int: a render of 32768x21846
// would have ended in "cannot encode PNG" (and signed overflow), so the path check says so.
TEST(ImageIo, PngSizesAreCheckedBeforeTheWork) {
  const fs::path p = temp_file("wide.png");
  write_image(Image(40000, 1), p);
  EXPECT_NE(read_error(p).find("wide.png: PNG of 40000x1 pixels: not an image rayscout reads"), std::string::npos);
  fs::remove(p);
  auto expect_refused = [](const std::string& name, int w, int h) {
    try {
      check_image_path(temp_file(name), w, h);
      ADD_FAILURE() << name << ": no error";
    } catch (const InputError& e) {
      const std::string size = std::to_string(w) + "x" + std::to_string(h);
      EXPECT_NE(std::string(e.what()).find(name + ": a PNG of " + size + " pixels is beyond stb's PNG writer"),
                std::string::npos) << e.what();
    }
  };
  expect_refused("big.png", 32768, 21846);
  EXPECT_NO_THROW(check_image_path(temp_file("big.png"), 32768, 21845));
  // Each row has a filter byte: 21845 x 32768 is 3 w h = 2^31 - 32768 bytes of pixels, but
  // (3 w + 1) h = 2^31 with them (a limit on 3 w h alone passed it).
  expect_refused("tall.png", 21845, 32768);
  EXPECT_NO_THROW(check_image_path(temp_file("big.exr"), 32768, 32768));
}

// A corrupt 8x8 file whose header claims 10000x10000 pixels (padded with zeros, where the
// missing line offsets would be) is refused before 1.2 GB of pixels are allocated.
TEST(ImageIo, ExrClaimingMorePixelsThanItHoldsIsIncomplete) {
  const fs::path p = temp_file("claims.exr");
  write_image(Image(8, 8), p);
  std::string bytes;
  {
    std::ifstream in(p, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string attr("dataWindow\0box2i\0", 17);
  const size_t at = bytes.find(attr);
  ASSERT_NE(at, std::string::npos);
  const int32_t max_xy = 9999;
  std::memcpy(&bytes[at + attr.size() + 4 + 8], &max_xy, 4);  // after the size and (xmin, ymin)
  std::memcpy(&bytes[at + attr.size() + 4 + 12], &max_xy, 4);
  bytes.append(80000, '\0');
  std::ofstream(p, std::ios::binary) << bytes;
  const std::string msg = read_error(p);
  EXPECT_NE(msg.find("claims.exr: incomplete EXR"), std::string::npos) << msg;
}

// Found by fuzzing: for this corrupt IDAT stream stb returns no failure reason (null).
TEST(ImageIo, PngWithoutFailureReason) {
  const fs::path p = temp_file("corrupt.png");
  static const char bytes[] =
      "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52"
      "\x00\x00\x00\x05\x00\x00\x00\x04\x08\x02\x00\x00\x00\xc9\x51\x62"
      "\x17\x00\x00\x00\x18\x49\x44\x41\x54\x78\x5e\x7f\x58\xa1\x2f\xea"
      "\xeb\xa0\xfc\xe7\x5a\xc3\x00\x00\x00\x80\xff\x7f\x5d\x95\xf1\x80"
      "\x5f\x43\xb9\x05\xd2\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60"
      "\x82";
  std::ofstream(p, std::ios::binary).write(bytes, sizeof bytes - 1);
  const std::string msg = read_error(p);
  EXPECT_NE(msg.find("corrupt.png: cannot read PNG (corrupt data)"), std::string::npos) << msg;
}

TEST(ImageCompare, RmsePsnrRelativeMseAndMaxErrorByHand) {
  Image a(4, 2), b(4, 2);
  for (auto& p : b.pixels) p = Vec3{0.5f};
  ImageError e = compare_images(a, b);
  EXPECT_DOUBLE_EQ(e.rmse, 0.5);
  EXPECT_DOUBLE_EQ(e.max_abs, 0.5);
  EXPECT_NEAR(e.psnr, 10 * std::log10(4.0), 1e-12);  // mse 0.25
  EXPECT_NEAR(e.rel_mse, 0.25 / 0.26, 1e-12);

  // one channel of one pixel off by 0.3: mse = 0.09 / 24
  Image c = b;
  c.at(2, 1).y += 0.3f;
  e = compare_images(c, b);
  EXPECT_NEAR(e.rmse, std::sqrt(0.09 / 24), 1e-7);
  EXPECT_NEAR(e.max_abs, 0.3, 1e-7);
  EXPECT_NEAR(e.rel_mse, 0.09 / 0.26 / 24, 1e-7);

  e = compare_images(b, b);
  EXPECT_EQ(e.rmse, 0.0);
  EXPECT_TRUE(std::isinf(e.psnr));
  EXPECT_THROW(compare_images(a, Image(2, 4)), InputError);
}

// The ramp's colours by hand (display values: black, blue, cyan, green, yellow, red at
// 0, 1/5, ..., 1 of the scale, linear between), for the mean of the channels' differences:
// with scale 2, (0, 0, 1.5) has mean 0.5, a quarter of the way from blue to cyan. NaN and
// inf pixels are red; the automatic scale is the largest finite difference, so an inf pixel
// leaves the others coloured.
TEST(ImageCompare, DifferenceImageColoursByHand) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  Image a(7, 1), b(7, 1);
  const Vec3 in[7] = {Vec3(0.0f), Vec3(0.0f, 0.0f, 1.5f), Vec3(1.0f), Vec3(1.4f), Vec3(5.0f), Vec3(nan, 0, 0),
                      Vec3(0, inf, 0)};
  for (int x = 0; x < 7; ++x) a.at(x, 0) = in[x];
  b.at(4, 0) = Vec3(1.0f);  // |a - b| = 4: beyond the scale, clamped to red
  const Vec3 fixed[7] = {{0, 0, 0}, {0, 0.25f, 1}, {0, 1, 0.5f}, {0.5f, 1, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  auto expect_colours = [](const Image& d, const Vec3* want, int n, const char* what) {
    for (int x = 0; x < n; ++x)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(linear_to_srgb(d.at(x, 0)[c]), want[x][c], 1e-5f) << what << " pixel " << x << " channel " << c;
  };
  expect_colours(difference_image(a, b, 2.0f), fixed, 7, "scale 2");
  // Automatic scale: the largest finite difference is 4 (pixel 4); 1 is then 1/4 of it.
  const Vec3 automatic[7] = {{0, 0, 0}, {0, 0, 0.625f}, {0, 0.25f, 1}, {0, 0.75f, 1}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  expect_colours(difference_image(a, b), automatic, 7, "automatic scale");
}

// A NaN or infinite pixel must not pass for a close image, nor break the picture.
TEST(ImageCompare, NonFinitePixels) {
  Image a(2, 1), b(2, 1);
  a.at(1, 0).y = std::numeric_limits<float>::quiet_NaN();
  ImageError e = compare_images(a, b);
  EXPECT_TRUE(std::isnan(e.rmse));
  EXPECT_TRUE(std::isnan(e.max_abs));
  EXPECT_EQ(e.nonfinite, 1u);
  EXPECT_EQ(compare_images(b, a).nonfinite, 1u);  // in the reference too
  a.at(1, 0).y = std::numeric_limits<float>::infinity();
  e = compare_images(a, b);
  EXPECT_TRUE(std::isinf(e.rmse));
  EXPECT_TRUE(std::isinf(e.psnr) && e.psnr < 0);
  const Image d = difference_image(a, b);
  EXPECT_EQ(d.at(0, 0), Vec3(0.0f));                    // no difference: black
  EXPECT_FLOAT_EQ(linear_to_srgb(d.at(1, 0).x), 1.0f);  // broken pixel: red
  EXPECT_FLOAT_EQ(d.at(1, 0).y, 0.0f);
  EXPECT_THROW(difference_image(a, b, std::numeric_limits<float>::quiet_NaN()), InputError);
}

}  // namespace
}  // namespace rayscout
