// The CRC of the short frames a monitor-IC model sees again and again, kept with the
// bytes it was computed from: the host repeats the same requests every tick (a broadcast
// conversion start, a status or results request) and a device's flags reply seldom
// changes, while the model checks or makes each one's CRC (which the firmware does too).
//
//   FrameCrcMemo<Crc, crc>::of(p, n)   crc(p, n): for a frame of up to 16 bytes the
//       same as the last one asked, the value crc gave for it; any other computed (and a
//       short one kept). One per stream of frames that repeat: a device's replies (a
//       results reply, longer, passes by without displacing its flags reply).
//
// A frame of up to 16 bytes is keyed by its length and two words that overlap to cover
// it (ShortFrame): equal keys, equal bytes. Reading it so takes a few loads, where a CRC
// of even three bytes is a call and some 20 instructions.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace packsim {

struct ShortFrame {
  static constexpr size_t kMaxBytes = 16;
  uint64_t lo = 0, hi = 0;
  size_t n = ~size_t{0};  // no frame

  // The n <= kMaxBytes bytes at p.
  static ShortFrame of(const uint8_t* p, size_t n) {
    ShortFrame k;
    k.n = n;
    if (n >= 8) {  // the first eight and the last eight
      std::memcpy(&k.lo, p, 8);
      std::memcpy(&k.hi, p + n - 8, 8);
    } else if (n >= 4) {  // the first four and the last four
      uint32_t a, b;
      std::memcpy(&a, p, 4);
      std::memcpy(&b, p + n - 4, 4);
      k.lo = a;
      k.hi = b;
    } else if (n > 0) {  // bytes 0, n/2 and n-1: each of one to three
      k.lo = p[0] | (uint64_t{p[n / 2]} << 8) | (uint64_t{p[n - 1]} << 16);
    }
    return k;
  }
  bool operator==(const ShortFrame& o) const { return lo == o.lo && hi == o.hi && n == o.n; }
};

template <typename Crc, Crc (*crc)(const uint8_t*, size_t)>
class FrameCrcMemo {
 public:
  Crc of(const uint8_t* p, size_t n) {
    if (n > ShortFrame::kMaxBytes) return crc(p, n);
    const ShortFrame k = ShortFrame::of(p, n);
    if (!(k == key_)) key_ = k, crc_ = crc(p, n);
    return crc_;
  }

 private:
  ShortFrame key_;  // the last short frame asked
  Crc crc_ = 0;
};

}  // namespace packsim
