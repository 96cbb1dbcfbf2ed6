// Ray files: binary, little-endian ray sets, closest hits and occlusion results.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "rayscout/core/ray.h"

namespace rayscout {

/// What a ray file holds, from its 4-byte magic.
enum class RayFileKind { Rays, Hits, Occlusion };

/// Every file starts with a 16-byte header: 4 ASCII magic bytes ("RAYS", "HITS" or "OCCL"),
/// uint32 version (1), uint64 record count; all little endian.
inline constexpr uint32_t kRayFileVersion = 1;
inline constexpr size_t kRayFileHeaderBytes = 16;

/// RAYS v1: per ray 8 float32 ox oy oz tmin dx dy dz tmax (32 bytes).
void write_rays(const std::filesystem::path& file, const RayBatch& rays);
/// Reads a RAYS file; throws InputError naming the file for a missing file, a bad magic or
/// version, or a size that does not match the count (truncated or trailing bytes).
RayBatch read_rays(const std::filesystem::path& file);

/// HITS v1: per ray float32 t (+inf on a miss), uint32 triangle id (0xFFFFFFFF on a
/// miss), float32 u, float32 v (16 bytes). A hit's t may be +-inf (a direction so short that
/// the distance overflows float, within tmin = -inf or tmax = inf).
void write_hits(const std::filesystem::path& file, const HitBatch& hits);
/// Reads a HITS file; errors as read_rays, plus a miss with a finite t or a hit with a
/// NaN t.
HitBatch read_hits(const std::filesystem::path& file);

/// OCCL v1: one byte per ray, 1 = occluded, 0 = clear.
void write_occlusion(const std::filesystem::path& file, const std::vector<uint8_t>& occluded);
/// Reads an OCCL file; errors as read_rays, plus a byte other than 0 or 1.
std::vector<uint8_t> read_occlusion(const std::filesystem::path& file);

/// A HITS or OCCL file, whichever its magic names, read in one pass (so a pipe works too):
/// `hits` for HITS, `occluded` for OCCL. Errors as read_hits / read_occlusion, plus a RAYS file.
struct ResultFile {
  RayFileKind kind;
  HitBatch hits;
  std::vector<uint8_t> occluded;
};
ResultFile read_results(const std::filesystem::path& file);

}  // namespace rayscout
