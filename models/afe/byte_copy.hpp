// Copies and clears of a run-time number of bytes on the per-tick path (bus frames, the
// firmware's outputs): up to 32 bytes in place (copyShortBytes), more through the C
// library's memcpy / memset.
//
// Why: GCC (x86-64, generic tuning) expands a memcpy or memset whose length it can bound
// -- a frame buffer's size, a struct's -- into an inline `rep movsq` / `rep stosq`, whose
// start-up (some 30 cycles) costs more than the whole copy of a frame of a few bytes,
// and more than the library's vector code for a struct of a kilobyte. Hiding the
// length's bound from the optimiser (an empty asm that "may change" it) makes it call
// the library. The bytes written are the same: only how they are copied changes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace packsim {

// Up to kShortBytes bytes (a frame's few, a device's results) without a library call:
// two pieces of a fixed size that overlap to cover them (the first and the last 16, 8,
// 4, 2 bytes; fixed-size memcpy is a plain load and store), both loaded before either
// is stored. The call and the library's own dispatch cost more than this for a few bytes.
// (Up to 128 bytes, with pieces of 32 and 64, was tried: GCC then stopped inlining the
// copy, and forced inline grew its callers; more instructions a tick either way.)
constexpr size_t kShortBytes = 32;

template <size_t K>
inline void copyOverlapping(uint8_t* d, const uint8_t* s, size_t n) {  // K <= n <= 2K
  unsigned char head[K], tail[K];
  std::memcpy(head, s, K);
  std::memcpy(tail, s + n - K, K);
  std::memcpy(d, head, K);
  std::memcpy(d + n - K, tail, K);
}

inline void copyShortBytes(void* dst, const void* src, size_t n) {  // n <= kShortBytes
  uint8_t* d = static_cast<uint8_t*>(dst);
  const uint8_t* s = static_cast<const uint8_t*>(src);
  if (n >= 16) return copyOverlapping<16>(d, s, n);
  if (n >= 8) return copyOverlapping<8>(d, s, n);
  if (n >= 4) return copyOverlapping<4>(d, s, n);
  if (n >= 2) return copyOverlapping<2>(d, s, n);
  if (n == 1) d[0] = s[0];
}

inline void copyBytes(void* dst, const void* src, size_t n) {
  if (n <= kShortBytes) return copyShortBytes(dst, src, n);
#if defined(__GNUC__)
  __asm__("" : "+r"(n));  // the length's bound unknown: a library call, not rep movs
#endif
  std::memcpy(dst, src, n);
}

inline void zeroBytes(void* dst, size_t n) {
  if (n <= kShortBytes) {  // (the same pieces, of zeros)
    static constexpr uint8_t kZeros[kShortBytes] = {};
    return copyShortBytes(dst, kZeros, n);
  }
#if defined(__GNUC__)
  __asm__("" : "+r"(n));
#endif
  std::memset(dst, 0, n);
}

// n values (the chain's per-cell and per-thermistor inputs): one or two by assignment,
// where the library call's set-up would cost several times the copy (a stack of one
// cell, a device's two thermistors), else copyBytes.
template <class T>
inline void copyValues(T* dst, const T* src, size_t n) {
  static_assert(std::is_trivially_copyable<T>::value, "copied as bytes");
  if (n <= 2) {  // (no loop: GCC would make one a library call again)
    if (n > 0) dst[0] = src[0];
    if (n > 1) dst[1] = src[1];
    return;
  }
  copyBytes(dst, src, n * sizeof(T));
}

}  // namespace packsim
