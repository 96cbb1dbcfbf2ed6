// Ray files: round trips of RAYS/HITS/OCCL and every malformed-file error.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <sys/stat.h>

#include "generated_scenes.h"
#include "rayscout/core/accelerator.h"
#include "rayscout/core/input_error.h"
#include "core/private/little_endian.h"
#include "rayscout/core/ray_file.h"

namespace rayscout {
namespace {

namespace fs = std::filesystem;

class RayFileTest : public ::testing::Test {
 protected:
  fs::path dir_;
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rayscout_ray_file_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path path(const std::string& name) const { return dir_ / name; }

  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  static void dump(const fs::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  }
  // The InputError message of f(), or "" when it did not throw.
  template <class F>
  static std::string error_of(F&& f) {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(RayFileTest, RaysRoundTripBitExactly) {
  RayBatch rays = testing::random_rays(1000, 5);
  rays.tmin[3] = 0.25f;
  rays.tmax[4] = 1e-30f;
  rays.dx[5] = -0.0f;
  write_rays(path("r.rays"), rays);
  EXPECT_EQ(fs::file_size(path("r.rays")), 16u + 32u * 1000u);
  const RayBatch back = read_rays(path("r.rays"));
  ASSERT_EQ(back.size(), rays.size());
  for (auto member : {&RayBatch::ox, &RayBatch::oy, &RayBatch::oz, &RayBatch::tmin, &RayBatch::dx,
                      &RayBatch::dy, &RayBatch::dz, &RayBatch::tmax})
    EXPECT_EQ(std::memcmp((back.*member).data(), (rays.*member).data(), rays.size() * 4), 0);
  const std::string e = error_of([&] { read_results(path("r.rays")); });
  EXPECT_NE(e.find("a RAYS file, expected a HITS or OCCL file"), std::string::npos) << e;
}

TEST_F(RayFileTest, LayoutIsLittleEndianAsSpecified) {
  RayBatch rays;
  rays.push_back({{1.0f, 2.0f, 3.0f}, 0.5f, {0.0f, 0.0f, -1.0f}, kInfinity});
  write_rays(path("one.rays"), rays);
  const std::string b = slurp(path("one.rays"));
  ASSERT_EQ(b.size(), 48u);
  EXPECT_EQ(b.substr(0, 4), "RAYS");
  EXPECT_EQ(b.substr(4, 4), std::string("\x01\x00\x00\x00", 4));
  EXPECT_EQ(b.substr(8, 8), std::string("\x01\x00\x00\x00\x00\x00\x00\x00", 8));
  EXPECT_EQ(b.substr(16, 4), std::string("\x00\x00\x80\x3f", 4));  // 1.0f
  EXPECT_EQ(b.substr(28, 4), std::string("\x00\x00\x00\x3f", 4));  // tmin 0.5f
  EXPECT_EQ(b.substr(44, 4), std::string("\x00\x00\x80\x7f", 4));  // tmax +inf
}

TEST_F(RayFileTest, HitsRoundTripWithMisses) {
  HitBatch hits;
  hits.reset(4);
  hits.set(0, {1.5f, 7, 0.25f, 0.5f});
  hits.set(2, {0.0f, 0, 0.0f, 1.0f});
  hits.set(3, {2.0f, kInvalidId, 0.5f, 0.5f});  // a miss is written as +inf, 0xFFFFFFFF, 0, 0
  write_hits(path("h.hits"), hits);
  const std::string b = slurp(path("h.hits"));
  ASSERT_EQ(b.size(), 16u + 4 * 16u);
  EXPECT_EQ(b.substr(0, 4), "HITS");
  EXPECT_EQ(b.substr(32, 8), std::string("\x00\x00\x80\x7f\xff\xff\xff\xff", 8));  // miss: +inf, 0xFFFFFFFF
  EXPECT_EQ(b.substr(64, 16), b.substr(32, 16));
  const HitBatch back = read_hits(path("h.hits"));
  ASSERT_EQ(back.size(), 4u);
  EXPECT_EQ(back.t[0], 1.5f);
  EXPECT_EQ(back.prim[0], 7u);
  EXPECT_EQ(back.u[0], 0.25f);
  EXPECT_EQ(back.v[0], 0.5f);
  EXPECT_EQ(back.prim[1], kInvalidId);
  EXPECT_EQ(back.t[1], kInfinity);
  EXPECT_EQ(back.prim[2], 0u);
  EXPECT_EQ(back.t[2], 0.0f);
  const ResultFile r = read_results(path("h.hits"));
  EXPECT_EQ(r.kind, RayFileKind::Hits);
  EXPECT_EQ(r.hits.t, back.t);
  EXPECT_EQ(r.hits.prim, back.prim);
}

// Found by fuzzing: for a ray with a denormal direction (1e-45) the hit distance overflows,
// and every accelerator (brute force too) reports the hit at t = +-inf within tmin = -inf,
// tmax = inf. trace wrote such a HITS file and compare-hits refused to read it back ("hit with
// non-finite t"). A hit at an infinite t reads back; a hit with a NaN t is still refused.
TEST_F(RayFileTest, HitsAtAnInfiniteDistanceRoundTripAndNaNIsRefused) {
  const std::vector<Triangle> triangle = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
  const BruteForce brute(triangle);
  RayBatch rays;
  rays.push_back({{0.25f, 0.25f, 1.0f}, -kInfinity, {0.0f, 0.0f, -1e-45f}, kInfinity});
  rays.push_back({{0.25f, 0.25f, -1.0f}, -kInfinity, {0.0f, 0.0f, -1e-45f}, kInfinity});
  HitBatch hits;
  brute.intersect(rays, hits);
  ASSERT_EQ(hits.prim, (std::vector<uint32_t>{0, 0}));
  ASSERT_EQ(hits.t, (std::vector<float>{kInfinity, -kInfinity}));
  write_hits(path("inf.hits"), hits);
  const HitBatch back = read_hits(path("inf.hits"));
  EXPECT_EQ(back.prim, hits.prim);
  EXPECT_EQ(back.t, hits.t);

  std::string b = slurp(path("inf.hits"));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&b[16 + 16], &nan, 4);  // record 1: a hit with t = NaN
  dump(path("nan.hits"), b);
  const std::string e = error_of([&] { read_hits(path("nan.hits")); });
  EXPECT_NE(e.find("nan.hits: record 1: hit with t = nan"), std::string::npos) << e;
}

TEST_F(RayFileTest, OcclusionRoundTrip) {
  const std::vector<uint8_t> occ = {1, 0, 0, 1, 1};
  write_occlusion(path("o.occl"), occ);
  EXPECT_EQ(slurp(path("o.occl")), std::string("OCCL\x01\0\0\0\x05\0\0\0\0\0\0\0\x01\0\0\x01\x01", 21));
  EXPECT_EQ(read_occlusion(path("o.occl")), occ);
  const ResultFile r = read_results(path("o.occl"));
  EXPECT_EQ(r.kind, RayFileKind::Occlusion);
  EXPECT_EQ(r.occluded, occ);
}

// A pipe cannot be sized by seeking: `trace --rays /dev/stdin` and `compare-hits <(...) <(...)`
// read their files in one sequential pass.
TEST_F(RayFileTest, PipesAreReadInOnePass) {
  write_rays(path("r.rays"), testing::random_rays(70000, 3));  // 2.2 MB: more than one read chunk
  write_hits(path("h.hits"), HitBatch{});
  for (const char* name : {"r.rays", "h.hits"}) {
    const fs::path fifo = path(std::string(name) + ".fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string bytes = slurp(path(name));
    std::thread writer([&] { dump(fifo, bytes); });
    if (std::string(name) == "r.rays") {
      const RayBatch rays = read_rays(fifo);
      EXPECT_EQ(rays.size(), 70000u);
      EXPECT_EQ(rays.tmax, read_rays(path(name)).tmax);
    } else {
      EXPECT_EQ(read_results(fifo).kind, RayFileKind::Hits);
    }
    writer.join();
  }
}

TEST_F(RayFileTest, EmptyFilesRoundTrip) {
  write_rays(path("e.rays"), RayBatch{});
  EXPECT_EQ(fs::file_size(path("e.rays")), 16u);
  EXPECT_EQ(read_rays(path("e.rays")).size(), 0u);
}

TEST_F(RayFileTest, MissingFileNamesTheFile) {
  const std::string e = error_of([&] { read_rays(path("nope.rays")); });
  EXPECT_NE(e.find("nope.rays"), std::string::npos) << e;
  EXPECT_NE(e.find("cannot open ray file: No such file or directory"), std::string::npos) << e;
}

TEST_F(RayFileTest, BadMagicIsNamed) {
  write_hits(path("h.hits"), HitBatch{});
  const std::string e = error_of([&] { read_rays(path("h.hits")); });
  EXPECT_NE(e.find("h.hits"), std::string::npos) << e;
  EXPECT_NE(e.find("bad magic 'HITS', expected 'RAYS'"), std::string::npos) << e;
  dump(path("junk"), std::string("\x89PNG\r\n\x1a\n\0\0\0\0\0\0\0\0", 16));
  const std::string e2 = error_of([&] { read_results(path("junk")); });
  EXPECT_NE(e2.find("bad magic '\\x89PNG'"), std::string::npos) << e2;
}

TEST_F(RayFileTest, ControlBytesInTheFileNameAreEscaped) {
  // The name is input: printed raw, "<ESC>[2J" in it would clear the terminal.
  const std::string e = error_of([&] { read_rays(path("no\x1b[2Jpe.rays")); });
  EXPECT_NE(e.find("no\\x1b[2Jpe.rays: cannot open ray file"), std::string::npos) << e;
  EXPECT_EQ(e.find('\x1b'), std::string::npos) << e;
}

TEST_F(RayFileTest, BadVersionIsNamed) {
  write_rays(path("r.rays"), testing::random_rays(3, 1));
  std::string b = slurp(path("r.rays"));
  b[4] = 2;
  dump(path("v2.rays"), b);
  const std::string e = error_of([&] { read_rays(path("v2.rays")); });
  EXPECT_NE(e.find("v2.rays"), std::string::npos) << e;
  EXPECT_NE(e.find("unsupported RAYS version 2, expected 1"), std::string::npos) << e;
  EXPECT_NE(error_of([&] { read_results(path("v2.rays")); }).find("version 2"), std::string::npos);
  b[4] = 0;
  dump(path("v0.rays"), b);
  EXPECT_NE(error_of([&] { read_rays(path("v0.rays")); }).find("unsupported RAYS version 0"), std::string::npos);
}

TEST_F(RayFileTest, TruncatedHeaderAndBodyAreNamed) {
  write_rays(path("r.rays"), testing::random_rays(10, 1));
  const std::string b = slurp(path("r.rays"));
  dump(path("head.rays"), b.substr(0, 10));
  std::string e = error_of([&] { read_rays(path("head.rays")); });
  EXPECT_NE(e.find("truncated header: 10 bytes, expected 16"), std::string::npos) << e;
  // Four bytes hold the magic: it is checked (and named) before the header's length.
  dump(path("magic.hits"), "HITS");
  e = error_of([&] { read_rays(path("magic.hits")); });
  EXPECT_NE(e.find("bad magic 'HITS', expected 'RAYS'"), std::string::npos) << e;
  e = error_of([&] { read_results(path("magic.hits")); });
  EXPECT_NE(e.find("truncated header: 4 bytes, expected 16 (HITS header)"), std::string::npos) << e;
  dump(path("empty.rays"), "");
  e = error_of([&] { read_rays(path("empty.rays")); });
  EXPECT_NE(e.find("truncated header: 0 bytes"), std::string::npos) << e;
  dump(path("body.rays"), b.substr(0, b.size() - 5));
  e = error_of([&] { read_rays(path("body.rays")); });
  EXPECT_NE(e.find("body.rays"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated: header says 10 records of 32 bytes = 320 bytes after the header, file has 315"),
            std::string::npos) << e;
}

TEST_F(RayFileTest, HugeCountIsTruncationNotAnAllocation) {
  std::string b("RAYS\x01\0\0\0", 8);
  b += std::string("\xff\xff\xff\xff\xff\xff\xff\x7f", 8);
  b += std::string(64, '\0');
  dump(path("huge.rays"), b);
  const std::string e = error_of([&] { read_rays(path("huge.rays")); });
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  EXPECT_NE(e.find("too many"), std::string::npos) << e;
}

// The count's high word is read (and written) as the high word: counts below 2^31 do not tell.
TEST_F(RayFileTest, CountAbove32BitsIsRead) {
  std::string b("RAYS\x01\0\0\0", 8);
  put_u64(b, (uint64_t(1) << 32) + 1);
  EXPECT_EQ(b.substr(8), std::string("\x01\0\0\0\x01\0\0\0", 8));
  EXPECT_EQ(get_u64(b.data() + 8), (uint64_t(1) << 32) + 1);
  dump(path("big.rays"), b);
  const std::string e = error_of([&] { read_rays(path("big.rays")); });
  EXPECT_NE(e.find("header says 4294967297 records of 32 bytes = 137438953504 bytes"), std::string::npos) << e;
}

TEST_F(RayFileTest, TrailingBytesAreAnError) {
  write_occlusion(path("o.occl"), {1, 0});
  dump(path("long.occl"), slurp(path("o.occl")) + "xyz");
  const std::string e = error_of([&] { read_occlusion(path("long.occl")); });
  EXPECT_NE(e.find(": 3 trailing bytes: header says 2 records"), std::string::npos) << e;
}

TEST_F(RayFileTest, InvalidRecordsAreNamed) {
  write_occlusion(path("o.occl"), {1, 0, 1});
  std::string b = slurp(path("o.occl"));
  b[16 + 1] = 7;
  dump(path("bad.occl"), b);
  std::string e = error_of([&] { read_occlusion(path("bad.occl")); });
  EXPECT_NE(e.find("record 1: byte 7, expected 0 or 1"), std::string::npos) << e;
  b[16 + 2] = 2;
  b[16 + 1] = 0;
  dump(path("two.occl"), b);
  e = error_of([&] { read_occlusion(path("two.occl")); });
  EXPECT_NE(e.find("record 2: byte 2, expected 0 or 1"), std::string::npos) << e;

  HitBatch hits;
  hits.reset(2);
  write_hits(path("h.hits"), hits);
  b = slurp(path("h.hits"));
  std::memset(&b[16 + 16], 0, 4);  // record 1: miss id with t = 0
  dump(path("bad.hits"), b);
  e = error_of([&] { read_hits(path("bad.hits")); });
  EXPECT_NE(e.find("record 1: miss (id 0xFFFFFFFF) with t 0.0"), std::string::npos) << e;
  // A miss with t = NaN is refused too (it was read back as a miss).
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&b[16 + 16], &nan, 4);
  dump(path("nan.hits"), b);
  e = error_of([&] { read_hits(path("nan.hits")); });
  EXPECT_NE(e.find("record 1: miss (id 0xFFFFFFFF) with t nan"), std::string::npos) << e;
}

}  // namespace
}  // namespace rayscout
