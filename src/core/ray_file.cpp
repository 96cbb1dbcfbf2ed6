// Ray files (RAYS, HITS, OCCL v1): little-endian binary I/O with errors naming the file.
#include "rayscout/core/ray_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "rayscout/core/input_error.h"
#include "core/private/little_endian.h"
#include "rayscout/core/output_path.h"

namespace rayscout {
namespace {

/// What tells the kinds apart: magic, name in messages, record size.
struct KindInfo {
  const char* magic;
  const char* what;
  uint64_t record_bytes;
};
constexpr KindInfo kKinds[] = {{"RAYS", "ray file", 32}, {"HITS", "hit file", 16}, {"OCCL", "occlusion file", 1}};
const KindInfo& info(RayFileKind kind) { return kKinds[size_t(kind)]; }
const char* magic_of(RayFileKind kind) { return info(kind).magic; }
const char* what_of(RayFileKind kind) { return info(kind).what; }

// The file name is quoted as input: a control byte in it must not reach the terminal.
[[noreturn]] void fail(const std::filesystem::path& file, const std::string& message) {
  throw InputError(printable(file.string()) + ": " + message);
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

// Checks the first `got` bytes of a file (the magic as soon as there are 4, then the length
// and the version) and returns the record count. `kind`: the kind expected, or nullopt for
// whichever the magic names (then set).
uint64_t parse_header(const std::filesystem::path& file, const char* head, size_t got,
                      std::optional<RayFileKind>& kind) {
  if (!kind && got >= 4)
    for (RayFileKind k : {RayFileKind::Rays, RayFileKind::Hits, RayFileKind::Occlusion})
      if (std::memcmp(head, magic_of(k), 4) == 0) kind = k;
  if (got >= 4 && (!kind || std::memcmp(head, magic_of(*kind), 4) != 0))
    fail(file, "bad magic '" + printable(std::string_view(head, 4)) + "', expected " +
                   (kind ? std::string("'") + magic_of(*kind) + "' (" + what_of(*kind) + ")"
                         : std::string("'RAYS', 'HITS' or 'OCCL'")));
  if (got < kRayFileHeaderBytes)
    fail(file, "truncated header: " + std::to_string(got) + " bytes, expected " +
                   std::to_string(kRayFileHeaderBytes) + (kind ? std::string(" (") + magic_of(*kind) + " header)" : ""));
  const uint32_t version = get_u32(head + 4);
  if (version != kRayFileVersion)
    fail(file, std::string("unsupported ") + magic_of(*kind) + " version " + std::to_string(version) +
                   ", expected " + std::to_string(kRayFileVersion));
  return get_u64(head + 8);
}

// Reads the rest of `in`, which must be exactly count records of `kind`. The buffer grows with
// the bytes that arrive, so a corrupt count cannot ask for terabytes.
std::string read_body(const std::filesystem::path& file, std::ifstream& in, RayFileKind kind, uint64_t count) {
  const uint64_t rec = info(kind).record_bytes;
  const bool too_many = count > UINT64_MAX / rec;
  const uint64_t want = too_many ? UINT64_MAX : count * rec;
  std::string data;
  std::error_code ec;
  // Reserve what the file holds, never what a corrupt count says (nor file_size's error value).
  if (std::filesystem::is_regular_file(file, ec))
    if (const uint64_t size = std::filesystem::file_size(file, ec); !ec) data.reserve(size_t(std::min(want, size)));
  uint64_t body = 0;  // bytes after the header; beyond `want` only counted
  std::vector<char> chunk(size_t(1) << 20);
  while (in.read(chunk.data(), std::streamsize(chunk.size())) || in.gcount() > 0) {
    const uint64_t n = uint64_t(in.gcount());
    if (body < want) data.append(chunk.data(), size_t(std::min(n, want - body)));
    body += n;
  }
  if (in.bad()) fail(file, "read failed");
  if (body != want) {
    const std::string expected = std::to_string(count) + " records of " + std::to_string(rec) + " bytes = " +
                                 (too_many ? std::string("too many") : std::to_string(want)) + " bytes after the header";
    if (body < want) fail(file, "truncated: header says " + expected + ", file has " + std::to_string(body));
    fail(file, std::to_string(body - want) + " trailing bytes: header says " + expected + ", file has " +
                   std::to_string(body));
  }
  return data;
}

// Reads a whole ray file in one sequential pass, so that pipes work too, and returns its
// records. `kind` as in parse_header.
std::string read_records(const std::filesystem::path& file, std::optional<RayFileKind>& kind, uint64_t& count) {
  check_not_directory(file);
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, std::string("cannot open ") + (kind ? what_of(*kind) : "ray file") + ": " + std::strerror(errno));
  char head[kRayFileHeaderBytes];
  in.read(head, kRayFileHeaderBytes);
  count = parse_header(file, head, size_t(in.gcount()), kind);
  return read_body(file, in, *kind, count);
}

std::string read_records(const std::filesystem::path& file, RayFileKind kind, uint64_t& count) {
  std::optional<RayFileKind> expected = kind;
  return read_records(file, expected, count);
}

HitBatch hits_from(const std::filesystem::path& file, const std::string& data, uint64_t count) {
  HitBatch hits;
  hits.reset(count);
  const char* p = data.data();
  for (size_t i = 0; i < count; ++i, p += 16) {
    const Hit h{get_f32(p), get_u32(p + 4), get_f32(p + 8), get_f32(p + 12)};
    // A hit's t may be infinite: the accelerators report a hit at t = +-inf for a direction so
    // short (1e-45) that the distance overflows, within tmin = -inf or tmax = inf.
    if (h.hit() ? std::isnan(h.t) : !(h.t == std::numeric_limits<float>::infinity()))
      fail(file, "record " + std::to_string(i) + ": " +
                     (h.hit() ? "hit with t = nan" : "miss (id 0xFFFFFFFF) with t " + std::to_string(h.t)) +
                     " (a miss must be t=+inf, id=0xFFFFFFFF)");
    hits.set(i, h);
  }
  return hits;
}

std::vector<uint8_t> occlusion_from(const std::filesystem::path& file, const std::string& data, uint64_t count) {
  std::vector<uint8_t> occ(count);
  for (size_t i = 0; i < count; ++i) {
    occ[i] = uint8_t(data[i]);
    if (occ[i] > 1)
      fail(file, "record " + std::to_string(i) + ": byte " + std::to_string(occ[i]) + ", expected 0 or 1");
  }
  return occ;
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
  write_file(file, out, what_of(RayFileKind::Hits));
}

HitBatch read_hits(const std::filesystem::path& file) {
  uint64_t count = 0;
  const std::string data = read_records(file, RayFileKind::Hits, count);
  return hits_from(file, data, count);
}

void write_occlusion(const std::filesystem::path& file, const std::vector<uint8_t>& occluded) {
  std::string out = header(RayFileKind::Occlusion, occluded.size());
  for (uint8_t o : occluded) out.push_back(char(o ? 1 : 0));
  write_file(file, out, what_of(RayFileKind::Occlusion));
}

std::vector<uint8_t> read_occlusion(const std::filesystem::path& file) {
  uint64_t count = 0;
  const std::string data = read_records(file, RayFileKind::Occlusion, count);
  return occlusion_from(file, data, count);
}

ResultFile read_results(const std::filesystem::path& file) {
  std::optional<RayFileKind> kind;
  uint64_t count = 0;
  const std::string data = read_records(file, kind, count);
  ResultFile r{*kind, {}, {}};
  if (r.kind == RayFileKind::Rays) fail(file, "a RAYS file, expected a HITS or OCCL file");
  if (r.kind == RayFileKind::Hits) r.hits = hits_from(file, data, count);
  else r.occluded = occlusion_from(file, data, count);
  return r;
}

}  // namespace rayscout
