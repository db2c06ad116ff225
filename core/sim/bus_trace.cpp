#include "core/sim/bus_trace.hpp"

namespace packsim {

namespace {
std::string hex(const uint8_t* p, size_t n) {
  static const char* d = "0123456789ABCDEF";
  std::string s;
  s.reserve(n * 3);
  for (size_t i = 0; i < n; ++i) {
    if (i) s += ' ';
    s += d[p[i] >> 4];
    s += d[p[i] & 0xF];
  }
  return s;
}
}  // namespace

BusTransfer TracedChain::transfer(double t, const uint8_t* tx, size_t txLen, uint8_t* rx, size_t rxLen) {
  const std::string what = part_->describe(tx, tx ? txLen : 0, rx ? rxLen : 0);
  sink_.push_back({t, bus_, true, static_cast<int>(tx ? txLen : 0), tx ? hex(tx, txLen) : std::string(), what});
  const BusTransfer r = part_->transfer(t, tx, txLen, rx, rxLen);
  if (rx != nullptr && rxLen > 0) {
    const size_t got = r.received > 0 ? std::min(static_cast<size_t>(r.received), rxLen) : 0;
    sink_.push_back({t + r.duration_s, bus_, false, r.received, hex(rx, got), r.received < 0 ? what + " (no answer)" : what});
  }
  return r;
}

}  // namespace packsim
