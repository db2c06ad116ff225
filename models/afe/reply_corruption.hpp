// A device's comm fault acting on the reply bytes it sends: a stuck device drives every
// byte to its value; a CRC error rate flips one bit with that probability (random draws
// only where the rate is set, so a healthy link draws nothing). Shared by the parts.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "models/afe/device_faults.hpp"
#include "models/random/random.hpp"

namespace packsim {

inline void corruptReply(const MonitorDeviceFault& f, Rng& rng, uint8_t* bytes, size_t n) {
  if (n == 0) return;
  if (f.stuck_byte >= 0) {
    std::fill(bytes, bytes + n, static_cast<uint8_t>(f.stuck_byte));
  } else if (f.crc_error_rate > 0.0) {
    const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    if (u < f.crc_error_rate) {
      const uint64_t r = rng();
      bytes[r % n] ^= static_cast<uint8_t>(1u << ((r >> 32) % 8));
    }
  }
}

}  // namespace packsim
