// The MCU clock's nanoseconds from a time in seconds, rounded to the nearest (half-way
// away from zero) as std::llround rounds: called on every tick and bus transfer, so done
// inline where the arithmetic is exact, the library call only elsewhere.
#pragma once
#include <cmath>
#include <cstdint>

namespace packsim {

inline uint64_t toNs(double t_s) {
  const double x = t_s * 1e9;
  // Below 2^52 the fraction x - trunc(x) is exact, so comparing it with 0.5 decides as
  // llround does; negative, huge or NaN: llround itself.
  if (!(x >= 0.0 && x < 4503599627370496.0)) return static_cast<uint64_t>(std::llround(x));
  // Through int64_t: x is below 2^52, so the conversions are exact either way, and x86-64
  // converts signed integers in one instruction each (unsigned 64-bit ones take a branch
  // and several instructions each way).
  const int64_t whole = static_cast<int64_t>(x);
  return static_cast<uint64_t>(whole) + (x - static_cast<double>(whole) >= 0.5 ? 1u : 0u);
}

}  // namespace packsim
