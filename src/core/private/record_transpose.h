// Transposes 32-byte records (8 floats each: a DACRT RayRecord, a Bvh2Node's box and
// children) into one vector per field, for SIMD kernels that test many records at once.
// Cheaper than gathers: 24 shuffles instead of 8 gathered loads per field.
#pragma once

#if defined(__AVX2__)
#include <immintrin.h>

// g++ 12 reports a false "__Y may be used uninitialized" inside its own AVX-512 headers.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

namespace rayscout::detail {

#if defined(__AVX512F__)
/// f[j] lane k = float j of record(k), for k < 16; record(k) returns a const float* to 8 floats.
template <class Record>
inline void transpose_records16(Record record, __m512 f[8]) {
  __m512 r[8];
  for (int k = 0; k < 8; ++k)  // record k in the low half, record k + 8 in the high half
    r[k] = _mm512_insertf32x8(_mm512_castps256_ps512(_mm256_loadu_ps(record(k))), _mm256_loadu_ps(record(k + 8)), 1);
  __m512 s[8];
  for (int q = 0; q < 2; ++q) {  // records 4q..4q+3 (and + 8)
    const __m512 t0 = _mm512_unpacklo_ps(r[4 * q], r[4 * q + 1]), t1 = _mm512_unpackhi_ps(r[4 * q], r[4 * q + 1]);
    const __m512 t2 = _mm512_unpacklo_ps(r[4 * q + 2], r[4 * q + 3]), t3 = _mm512_unpackhi_ps(r[4 * q + 2], r[4 * q + 3]);
    s[4 * q + 0] = _mm512_shuffle_ps(t0, t2, 0x44);  // field f (lanes 0, 2) and f + 4 (lanes 1, 3)
    s[4 * q + 1] = _mm512_shuffle_ps(t0, t2, 0xEE);
    s[4 * q + 2] = _mm512_shuffle_ps(t1, t3, 0x44);
    s[4 * q + 3] = _mm512_shuffle_ps(t1, t3, 0xEE);
  }
  const __m512i lo_lanes = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27);
  const __m512i hi_lanes = _mm512_setr_epi32(4, 5, 6, 7, 20, 21, 22, 23, 12, 13, 14, 15, 28, 29, 30, 31);
  for (int k = 0; k < 4; ++k) {
    f[k] = _mm512_permutex2var_ps(s[k], lo_lanes, s[4 + k]);
    f[k + 4] = _mm512_permutex2var_ps(s[k], hi_lanes, s[4 + k]);
  }
}
#endif

/// f[j] lane k = float j of record(k), for k < 8.
template <class Record>
inline void transpose_records8(Record record, __m256 f[8]) {
  __m256 r[8];
  for (int k = 0; k < 8; ++k) r[k] = _mm256_loadu_ps(record(k));
  __m256 s[8];
  for (int q = 0; q < 2; ++q) {  // records 4q..4q+3: field f (low half) and f + 4 (high half)
    const __m256 t0 = _mm256_unpacklo_ps(r[4 * q], r[4 * q + 1]), t1 = _mm256_unpackhi_ps(r[4 * q], r[4 * q + 1]);
    const __m256 t2 = _mm256_unpacklo_ps(r[4 * q + 2], r[4 * q + 3]), t3 = _mm256_unpackhi_ps(r[4 * q + 2], r[4 * q + 3]);
    s[4 * q + 0] = _mm256_shuffle_ps(t0, t2, 0x44);
    s[4 * q + 1] = _mm256_shuffle_ps(t0, t2, 0xEE);
    s[4 * q + 2] = _mm256_shuffle_ps(t1, t3, 0x44);
    s[4 * q + 3] = _mm256_shuffle_ps(t1, t3, 0xEE);
  }
  for (int k = 0; k < 4; ++k) {
    f[k] = _mm256_permute2f128_ps(s[k], s[4 + k], 0x20);
    f[k + 4] = _mm256_permute2f128_ps(s[k], s[4 + k], 0x31);
  }
}

}  // namespace rayscout::detail

#pragma GCC diagnostic pop
#endif
