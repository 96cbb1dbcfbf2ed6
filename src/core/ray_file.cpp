// Ray files (RAYS, HITS, OCCL v1): little-endian binary I/O with errors naming the file.
#include "rayscout/core/ray_file.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>

#include "rayscout/core/accelerator_options.h"
#include "rayscout/core/output_path.h"

namespace rayscout {
namespace {

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big);

// Little-endian encoding of 4-byte words, independent of the host byte order.
void put_u32(std::string& out, uint32_t x) {
  for (int b = 0; b < 4; ++b) out.push_back(char((x >> (8 * b)) & 0xFF));
}
void put_f32(std::string& out, float f) { put_u32(out, std::bit_cast<uint32_t>(f)); }
void put_u64(std::string& out, uint64_t x) {
  put_u32(out, uint32_t(x));
  put_u32(out, uint32_t(x >> 32));
}
uint32_t get_u32(const char* p) {
  uint32_t x = 0;
  for (int b = 0; b < 4; ++b) x |= uint32_t(uint8_t(p[b])) << (8 * b);
  return x;
}
float get_f32(const char* p) { return std::bit_cast<float>(get_u32(p)); }
uint64_t get_u64(const char* p) { return uint64_t(get_u32(p)) | (uint64_t(get_u32(p + 4)) << 32); }

const char* magic_of(RayFileKind kind) {
  switch (kind) {
    case RayFileKind::Rays: return "RAYS";
    case RayFileKind::Hits: return "HITS";
    case RayFileKind::Occlusion: return "OCCL";
  }
  return "????";
}
const char* what_of(RayFileKind kind) {
  switch (kind) {
    case RayFileKind::Rays: return "ray file";
    case RayFileKind::Hits: return "hit file";
    case RayFileKind::Occlusion: return "occlusion file";
  }
  return "file";
}
size_t record_bytes(RayFileKind kind) {
  switch (kind) {
    case RayFileKind::Rays: return 32;
    case RayFileKind::Hits: return 16;
    case RayFileKind::Occlusion: return 1;
  }
  return 0;
}

std::string printable(const char* magic) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const unsigned char c = static_cast<unsigned char>(magic[i]);
    if (c >= 32 && c < 127) s.push_back(char(c));
    else { char buf[8]; std::snprintf(buf, sizeof buf, "\\x%02X", c); s += buf; }
  }
  return s;
}

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& message) {
  throw InputError(file.string() + ": " + message);
}

std::string header(RayFileKind kind, uint64_t count) {
  std::string out(magic_of(kind), 4);
  put_u32(out, kRayFileVersion);
  put_u64(out, count);
  return out;
}

// An ifstream opens a directory and reads 0 bytes from it: say what it is instead.
void check_not_directory(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) fail(file, "is a directory, not a ray file");
}

// Reads the whole file after checking its header against `kind`; returns the records and count.
std::string read_records(const std::filesystem::path& file, RayFileKind kind, uint64_t& count) {
  check_not_directory(file);
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, std::string("cannot open ") + what_of(kind));
  char head[kRayFileHeaderBytes];
  in.read(head, kRayFileHeaderBytes);
  const size_t got = size_t(in.gcount());
  if (got >= 4 && std::memcmp(head, magic_of(kind), 4) != 0)
    fail(file, std::string("bad magic '") + printable(head) + "', expected '" + magic_of(kind) +
                   "' (" + what_of(kind) + ")");
  if (got < kRayFileHeaderBytes)
    fail(file, "truncated header: " + std::to_string(got) + " bytes, expected " +
                   std::to_string(kRayFileHeaderBytes) + " (" + magic_of(kind) + " header)");
  const uint32_t version = get_u32(head + 4);
  if (version != kRayFileVersion)
    fail(file, std::string("unsupported ") + magic_of(kind) + " version " + std::to_string(version) +
                   ", expected " + std::to_string(kRayFileVersion));
  count = get_u64(head + 8);
  const size_t rec = record_bytes(kind);
  in.seekg(0, std::ios::end);
  const uint64_t body = uint64_t(in.tellg()) - kRayFileHeaderBytes;
  // Compare sizes before allocating, so a corrupt count cannot ask for terabytes.
  if (count > body / rec || body != count * rec) {
    const std::string expected = std::to_string(count) + " records of " + std::to_string(rec) +
                                 " bytes = " + (count > UINT64_MAX / rec ? std::string("too many")
                                                                         : std::to_string(count * rec)) +
                                 " bytes after the header";
    if (count > body / rec)
      fail(file, "truncated: header says " + expected + ", file has " + std::to_string(body));
    fail(file, std::to_string(body - count * rec) + " trailing bytes: header says " + expected +
                   ", file has " + std::to_string(body));
  }
  std::string data(size_t(body), '\0');
  in.seekg(kRayFileHeaderBytes);
  in.read(data.data(), std::streamsize(body));
  if (uint64_t(in.gcount()) != body) fail(file, "read failed");
  return data;
}

}  // namespace

void write_rays(const std::filesystem::path& file, const RayBatch& rays) {
  std::string out = header(RayFileKind::Rays, rays.size());
  out.reserve(out.size() + rays.size() * 32);
  for (size_t i = 0; i < rays.size(); ++i)
    for (float f : {rays.ox[i], rays.oy[i], rays.oz[i], rays.tmin[i], rays.dx[i], rays.dy[i], rays.dz[i], rays.tmax[i]})
      put_f32(out, f);
  write_file(file, out, "ray file");
}

RayBatch read_rays(const std::filesystem::path& file) {
  uint64_t count = 0;
  const std::string data = read_records(file, RayFileKind::Rays, count);
  RayBatch rays;
  rays.resize(count);
  const char* p = data.data();
  for (size_t i = 0; i < count; ++i, p += 32) {
    rays.ox[i] = get_f32(p); rays.oy[i] = get_f32(p + 4); rays.oz[i] = get_f32(p + 8); rays.tmin[i] = get_f32(p + 12);
    rays.dx[i] = get_f32(p + 16); rays.dy[i] = get_f32(p + 20); rays.dz[i] = get_f32(p + 24); rays.tmax[i] = get_f32(p + 28);
  }
  return rays;
}

void write_hits(const std::filesystem::path& file, const HitBatch& hits) {
  std::string out = header(RayFileKind::Hits, hits.size());
  out.reserve(out.size() + hits.size() * 16);
  for (size_t i = 0; i < hits.size(); ++i) {
    const bool hit = hits.prim[i] != kInvalidId;
    put_f32(out, hit ? hits.t[i] : kInfinity);
    put_u32(out, hits.prim[i]);
    put_f32(out, hit ? hits.u[i] : 0.0f);
    put_f32(out, hit ? hits.v[i] : 0.0f);
  }
  write_file(file, out, "ray file");
}

HitBatch read_hits(const std::filesystem::path& file) {
  uint64_t count = 0;
  const std::string data = read_records(file, RayFileKind::Hits, count);
  HitBatch hits;
  hits.reset(count);
  const char* p = data.data();
  for (size_t i = 0; i < count; ++i, p += 16) {
    const Hit h{get_f32(p), get_u32(p + 4), get_f32(p + 8), get_f32(p + 12)};
    if (h.hit() != std::isfinite(h.t))
      fail(file, "record " + std::to_string(i) + ": " +
                     (h.hit() ? "hit with non-finite t" : "miss (id 0xFFFFFFFF) with finite t " + std::to_string(h.t)) +
                     " (a miss must be t=+inf, id=0xFFFFFFFF)");
    hits.set(i, h);
  }
  return hits;
}

void write_occlusion(const std::filesystem::path& file, const std::vector<uint8_t>& occluded) {
  std::string out = header(RayFileKind::Occlusion, occluded.size());
  for (uint8_t o : occluded) out.push_back(char(o ? 1 : 0));
  write_file(file, out, "ray file");
}

std::vector<uint8_t> read_occlusion(const std::filesystem::path& file) {
  uint64_t count = 0;
  const std::string data = read_records(file, RayFileKind::Occlusion, count);
  std::vector<uint8_t> occ(count);
  for (size_t i = 0; i < count; ++i) {
    occ[i] = uint8_t(data[i]);
    if (occ[i] > 1)
      fail(file, "record " + std::to_string(i) + ": byte " + std::to_string(occ[i]) + ", expected 0 or 1");
  }
  return occ;
}

RayFileKind ray_file_kind(const std::filesystem::path& file) {
  check_not_directory(file);
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open");
  char head[kRayFileHeaderBytes];
  in.read(head, kRayFileHeaderBytes);
  if (size_t(in.gcount()) < kRayFileHeaderBytes)
    fail(file, "truncated header: " + std::to_string(in.gcount()) + " bytes, expected 16");
  for (RayFileKind kind : {RayFileKind::Rays, RayFileKind::Hits, RayFileKind::Occlusion}) {
    if (std::memcmp(head, magic_of(kind), 4) != 0) continue;
    const uint32_t version = get_u32(head + 4);
    if (version != kRayFileVersion)
      fail(file, std::string("unsupported ") + magic_of(kind) + " version " + std::to_string(version) +
                     ", expected " + std::to_string(kRayFileVersion));
    return kind;
  }
  fail(file, "bad magic '" + printable(head) + "', expected 'RAYS', 'HITS' or 'OCCL'");
}

}  // namespace rayscout
