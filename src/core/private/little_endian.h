// Little-endian 4- and 8-byte words, independent of the host byte order (ray files, glTF's
// binary container).
#pragma once

#include <bit>
#include <cstdint>
#include <string>

namespace rayscout {

inline void put_u32(std::string& out, uint32_t x) {
  for (int b = 0; b < 4; ++b) out.push_back(char((x >> (8 * b)) & 0xFF));
}
inline void put_f32(std::string& out, float f) { put_u32(out, std::bit_cast<uint32_t>(f)); }
inline void put_u64(std::string& out, uint64_t x) {
  put_u32(out, uint32_t(x));
  put_u32(out, uint32_t(x >> 32));
}
inline uint32_t get_u32(const char* p) {
  uint32_t x = 0;
  for (int b = 0; b < 4; ++b) x |= uint32_t(uint8_t(p[b])) << (8 * b);
  return x;
}
inline float get_f32(const char* p) { return std::bit_cast<float>(get_u32(p)); }
inline uint64_t get_u64(const char* p) { return uint64_t(get_u32(p)) | (uint64_t(get_u32(p + 4)) << 32); }

}  // namespace rayscout
