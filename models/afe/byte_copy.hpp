// Copies and clears of a run-time number of bytes on the per-tick path (bus frames, the
// firmware's outputs), made through the C library's memcpy / memset.
//
// Why: GCC (x86-64, generic tuning) expands a memcpy or memset whose length it can bound
// -- a frame buffer's size, a struct's -- into an inline `rep movsq` / `rep stosq`, whose
// start-up (some 30 cycles) costs more than the whole copy of a frame of a few bytes,
// and more than the library's vector code for a struct of a kilobyte. Hiding the
// length's bound from the optimiser (an empty asm that "may change" it) makes it call
// the library. The bytes written are the same: only how they are copied changes.
#pragma once
#include <cstddef>
#include <cstring>
#include <type_traits>

namespace packsim {

inline void copyBytes(void* dst, const void* src, size_t n) {
#if defined(__GNUC__)
  __asm__("" : "+r"(n));  // the length's bound unknown: a library call, not rep movs
#endif
  std::memcpy(dst, src, n);
}

inline void zeroBytes(void* dst, size_t n) {
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
