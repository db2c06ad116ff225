// Rounding to the nearest integer, ties away from zero: std::llround, bit for bit, inline.
//
// Why: std::llround is a call into libm (some 27 instructions with the call), and the
// MCU's millisecond clock is rounded from the simulated time once per tick
// (HwSensors::sample). For |v| < 2^52 the conversion to an integer truncates toward zero
// exactly, and v - trunc(v) is exact too (Sterbenz: for |v| >= 1 the two lie within a
// factor of 2 of each other; below, trunc(v) is 0), so comparing that remainder with
// ±0.5 rounds exactly as llround. Larger values, infinities and NaN go to std::llround.
#pragma once
#include <cmath>

namespace packsim {

inline long long roundHalfAway(double v) {
  if (!(std::fabs(v) < 0x1p52)) return std::llround(v);
  const long long i = static_cast<long long>(v);
  const double rest = v - static_cast<double>(i);
  return i + (rest >= 0.5 ? 1 : 0) - (rest <= -0.5 ? 1 : 0);
}

}  // namespace packsim
