// Rounding to the nearest integer, ties to even: std::nearbyint in the default rounding
// mode (packsim never changes it), bit for bit, inline.
//
// Why: without SSE4.1 in the build's baseline (x86-64), std::nearbyint is a call into
// libm through the PLT, once per ADC conversion -- several per tick. For |v| < 2^52,
// |v| + 2^52 lies in [2^52, 2^53), where the spacing of doubles is exactly 1, so the
// addition itself rounds |v| to the nearest integer, ties to even (2^52 is even); taking
// 2^52 away again is exact. The sign is put back (so -0.3 gives -0.0, as nearbyint does).
// From 2^52 on every double is already an integer; inf and NaN pass through.
#pragma once
#include <cmath>

namespace packsim {

inline double roundHalfEven(double v) {
  constexpr double kTwo52 = 0x1p52;
  const double a = std::fabs(v);
  if (!(a < kTwo52)) return v;
  return std::copysign((a + kTwo52) - kTwo52, v);
}

// The same rounding as a policy, for conversion code built twice (AdcChannel's
// conversions, a part's startConversion): RoundHalfEven is the formula above, for any
// x86-64; RoundNearbyint is std::nearbyint itself, which GCC makes the one instruction
// roundsd (current mode, no inexact flag) inside a function built for SSE4.1
// (target("sse4.1")), some 10 instructions less a conversion than the formula;
// elsewhere it is libm's call. Both give the same bits.
struct RoundHalfEven {
  [[gnu::always_inline]] static double of(double v) { return roundHalfEven(v); }
};
struct RoundNearbyint {
  [[gnu::always_inline]] static double of(double v) { return std::nearbyint(v); }
};

namespace detail {
extern bool gNativeRounding;  // round_even.cpp
}

// Whether code with both builds takes its SSE4.1 one (RoundNearbyint): the CPU has
// SSE4.1, asked once at start-up. Inline: read at every conversion.
inline bool nativeRounding() { return detail::gNativeRounding; }
// Tests: the SSE4.1 builds off (false) or back on where the CPU has them; returns the
// setting before.
bool useNativeRounding(bool on);

}  // namespace packsim
