// The plant's inputs taken over from this tick's hardware state, and whether any changed:
// dst[i] = src[i] for i < n, true when some dst[i] != src[i] before (C++ !=: a NaN differs
// from everything, -0.0 equals 0.0).
//
// Why its own functions: the balancing hardware takes over every group's switch and duty
// each tick. One loop over both, a byte and a double per turn with a compare each, cost
// some 16 instructions a group; these take eight switches per word compare and two duties
// per SSE2 compare (x86-64's baseline), the same results (tests: against the plain loop).
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace packsim {

inline bool takeOverBytes(uint8_t* dst, const uint8_t* src, size_t n) {
  uint64_t diff = 0;
  size_t i = 0;
  for (; i + 8 <= n; i += 8) {  // bytes are equal exactly when their words are
    uint64_t a, b;
    std::memcpy(&a, dst + i, 8);
    std::memcpy(&b, src + i, 8);
    diff |= a ^ b;
    std::memcpy(dst + i, &b, 8);
  }
  for (; i < n; ++i) {
    diff |= static_cast<uint64_t>(dst[i] ^ src[i]);
    dst[i] = src[i];
  }
  return diff != 0;
}

inline bool takeOverDoubles(double* dst, const double* src, size_t n) {
  size_t i = 0;
  bool diff = false;
#if defined(__SSE2__)
  __m128d ne = _mm_setzero_pd();
  for (; i + 2 <= n; i += 2) {
    const __m128d b = _mm_loadu_pd(src + i);
    ne = _mm_or_pd(ne, _mm_cmpneq_pd(_mm_loadu_pd(dst + i), b));  // unordered or unequal: C++ !=
    _mm_storeu_pd(dst + i, b);
  }
  diff = _mm_movemask_pd(ne) != 0;
#endif
  for (; i < n; ++i) {
    diff |= dst[i] != src[i];
    dst[i] = src[i];
  }
  return diff;
}

}  // namespace packsim
