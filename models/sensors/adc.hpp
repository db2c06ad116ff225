// Analog-to-digital conversion shared by the sensor models: an ideal converter with
// gain and offset error and Gaussian noise, rounding to the nearest code and
// saturating at the rails.
//
//   code = clamp(round((x·(1 + gain_error) + offset + noise) / lsb), code_min, code_max)
//   noise ~ N(0, noise_rms)
#pragma once
#include <cmath>
#include <cstdint>

#include "models/random/random.hpp"  // Rng, standardNormalLazy
#include "models/sensors/round_even.hpp"

namespace packsim {

struct AdcChannel {
  double lsb = 1.0;          // input units per code
  double gain_error = 0.0;   // relative: 0.055 reads 5.5 % high
  double offset = 0.0;       // input units
  double noise_rms = 0.0;    // input units
  int64_t code_min = 0;
  int64_t code_max = 65535;

  int64_t convert(double x, Rng& rng) const { return convertWith(gain_error, offset, x, rng); }
  // The same conversion with this gain error and offset instead of the channel's own
  // (a monitor input's: the part's plus the channel's drawn and injected errors), without
  // copying the channel. Inline (always: also into a part's SSE4.1 build, whose rounding
  // is Round, round_even.hpp): several conversions per tick and cell.
  template <class Round = RoundHalfEven>
  [[gnu::always_inline]] int64_t convertWith(double gainError, double offsetIn, double x, Rng& rng) const {
    const double v = x * (1.0 + gainError) + offsetIn;
    if (!(noise_rms > 0.0)) return codeOf<Round>(v);
    return noisyCodeOf<Round>(v, standardNormalLazy(rng), rng);
  }

  // The code of v at the input.
  template <class Round = RoundHalfEven>
  [[gnu::always_inline]] int64_t codeOf(double v) const { return clampedCode(Round::of(v / lsb)); }

  // codeOf(v + noise_rms·n), noise_rms > 0, n just drawn from rng. The quotient is
  // monotonic in n (each step rounds monotonically; the division by lsb keeps or reverses
  // the order, whatever its sign), and so is its rounding: where both ends of n's bracket
  // round to one value q, n's own value rounds to q too, and the libm's sincos is not
  // needed (nearly every draw: the bracket spans some 1e-12 of the noise, a code some
  // 1e-3). The other end rounds to q where it lies within half a code of q: its distance
  // rounds to below 0.5 only if it is below 0.5 (a subtraction and a compare, not a
  // second rounding). Else (a tie, NaN, or the bracket across a code's edge) the normal's
  // value decides. The same code as drawing n with standardNormal.
  template <class Round = RoundHalfEven>
  [[gnu::always_inline]] int64_t noisyCodeOf(double v, const NormalBracket& n, const Rng& rng) const {
    const double lo = Round::of((v + noise_rms * n.lo) / lsb);
    if (std::fabs((v + noise_rms * n.hi) / lsb - lo) < 0.5) return clampedCode(lo);
    return codeOf<Round>(v + noise_rms * lazyNormalValue(rng, n));
  }

  // A rounded quotient as a code, saturating at the rails.
  int64_t clampedCode(double code) const {
    if (!(code > static_cast<double>(code_min))) return code_min;  // also catches NaN
    if (code > static_cast<double>(code_max)) return code_max;
    return static_cast<int64_t>(code);
  }
};

}  // namespace packsim
