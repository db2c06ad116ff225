// The cells a monitor's comparators see outside their window: bit c of `over` is
// v[c] > hi, bit c of `under` is v[c] < lo (a NaN is neither), for c < n (n <= 32).
//
// Why its own function: every part's comparators look at every cell at each frame after
// the pins changed (each tick); two cells per SSE2 compare and mask (x86-64's baseline)
// cost about half the scalar loop's instructions. The bits are the same: the vector
// compares are the same ordered comparisons of the same doubles (windowMasksScalar, the
// plain loop, is the reference the tests hold it to). codeWindowMasks16: the same for a
// part's ADC result codes against its UV/OV code thresholds, at each conversion landing.
#pragma once
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace packsim {

inline void windowMasksScalar(const double* v, int n, double lo, double hi, uint32_t& over, uint32_t& under) {
  uint32_t o = 0, u = 0;
  for (int c = 0; c < n; ++c) {
    o |= static_cast<uint32_t>(v[c] > hi) << c;  // (no branches)
    u |= static_cast<uint32_t>(v[c] < lo) << c;
  }
  over = o;
  under = u;
}

inline void windowMasks(const double* v, int n, double lo, double hi, uint32_t& over, uint32_t& under) {
#if defined(__SSE2__)
  const __m128d loV = _mm_set1_pd(lo), hiV = _mm_set1_pd(hi);
  uint32_t o = 0, u = 0;
  int c = 0;
  for (; c + 1 < n; c += 2) {
    const __m128d x = _mm_loadu_pd(v + c);
    o |= static_cast<uint32_t>(_mm_movemask_pd(_mm_cmpgt_pd(x, hiV))) << c;
    u |= static_cast<uint32_t>(_mm_movemask_pd(_mm_cmplt_pd(x, loV))) << c;
  }
  if (c < n) {  // an odd count's last cell
    o |= static_cast<uint32_t>(v[c] > hi) << c;
    u |= static_cast<uint32_t>(v[c] < lo) << c;
  }
  over = o;
  under = u;
#else
  windowMasksScalar(v, n, lo, hi, over, under);
#endif
}

// The same window on a part's 16 result codes (unsigned 16 bit): bit c of `over` is
// code[c] > hi, bit c of `under` is code[c] < lo. SSE2 has signed 16-bit compares only:
// codes and thresholds are offset by 0x8000 (a flip of the top bit), which keeps their order.
inline void codeWindowMasks16Scalar(const uint16_t* code, uint16_t lo, uint16_t hi, uint32_t& over,
                                    uint32_t& under) {
  uint32_t o = 0, u = 0;
  for (unsigned c = 0; c < 16; ++c) {
    o |= static_cast<uint32_t>(code[c] > hi) << c;
    u |= static_cast<uint32_t>(code[c] < lo) << c;
  }
  over = o;
  under = u;
}

inline void codeWindowMasks16(const uint16_t* code, uint16_t lo, uint16_t hi, uint32_t& over, uint32_t& under) {
#if defined(__SSE2__)
  const __m128i flip = _mm_set1_epi16(static_cast<short>(0x8000));
  const __m128i a = _mm_xor_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(code)), flip);
  const __m128i b = _mm_xor_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(code + 8)), flip);
  const __m128i loV = _mm_set1_epi16(static_cast<short>(lo ^ 0x8000u)), hiV = _mm_set1_epi16(static_cast<short>(hi ^ 0x8000u));
  // each lane 0 or -1; packed to bytes in code order (a's eight, then b's), one bit each
  over = static_cast<uint32_t>(_mm_movemask_epi8(_mm_packs_epi16(_mm_cmpgt_epi16(a, hiV), _mm_cmpgt_epi16(b, hiV))));
  under = static_cast<uint32_t>(_mm_movemask_epi8(_mm_packs_epi16(_mm_cmplt_epi16(a, loV), _mm_cmplt_epi16(b, loV))));
#else
  codeWindowMasks16Scalar(code, lo, hi, over, under);
#endif
}

}  // namespace packsim
