// The temperatures a noiseless thermistor conversion turns into one code: a range
// [lo_C, hi_C] such that Thermistor::codeOf(idealCode(T)) is `code` for every T in it
// (noise_codes_rms 0: no draw), bit for bit as computing it.
//
//   around(ntc, T, c)   the range of code c, found from T (whose code is c): its two edges
//                       from the divider's inverse (Thermistor::temperatureAt_K at the
//                       codes c ± 0.5), each
//                       moved kInset_K inwards, then checked forwards
//   holds(T)            lo_C <= T <= hi_C (NaN: never)
//   bounded             the range was checked (not T alone): every T in it has its
//                       computed idealCode strictly within (code - 0.5, code + 0.5), so a
//                       comparator's threshold outside that window is decided by it
//
// Why the check suffices: idealCode is monotone in T above -273.15 °C (r25 · exp(β (1/(T
// + 273.15) - 1/298.15)) through the divider: decreasing for β > 0), and its computed
// value is that within a few ulps (a code of 4095 or less: some 1e-11 codes). Where both
// edges' computed codes are c and lie more than kMargin (1e-6 codes) from the rounding
// points c ± 0.5, every temperature's between them rounds to c too. An edge that fails
// the check (the inverse's own rounding, a code at the rails, an odd divider) leaves the
// range at T alone (which still converts alike: the same bits, the same computation).
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>

#include "models/sensors/round_even.hpp"
#include "models/sensors/thermistor.hpp"

namespace packsim {

struct ThermistorCodeRange {
  static constexpr double kMargin = 1e-6;  // codes: the computed code's error is some 1e-11
  static constexpr double kInset_K = 1e-4;  // the edges moved in: some 4e-3 codes at 25 °C

  double lo_C = std::numeric_limits<double>::quiet_NaN(), hi_C = std::numeric_limits<double>::quiet_NaN();
  int64_t code = 0;
  bool bounded = false;

  bool holds(double temp_C) const { return temp_C >= lo_C && temp_C <= hi_C; }

  static ThermistorCodeRange around(const Thermistor& ntc, double temp_C, int64_t c) {
    ThermistorCodeRange r{temp_C, temp_C, c, false};
    if (!(ntc.beta_K > 0.0 && ntc.r25_ohm > 0.0 && ntc.pullup_ohm > 0.0) || c < 1 || c >= ntc.fullScaleCode()) return r;
    // Higher codes at lower temperatures: code c from T(c + 0.5) up to T(c - 0.5).
    const double lo = ntc.temperatureAt_K(static_cast<double>(c) + 0.5) - 273.15 + kInset_K;
    const double hi = ntc.temperatureAt_K(static_cast<double>(c) - 0.5) - 273.15 - kInset_K;
    if (!(lo > -273.15 && lo <= temp_C && temp_C <= hi) || !convertsClear(ntc, lo, c) || !convertsClear(ntc, hi, c))
      return r;
    r.lo_C = lo;
    r.hi_C = hi;
    r.bounded = true;
    return r;
  }

 private:
  // T's computed code rounds to c, more than kMargin from a rounding point.
  static bool convertsClear(const Thermistor& ntc, double temp_C, int64_t c) {
    const double x = ntc.idealCode(temp_C);
    const double nearest = roundHalfEven(x);
    return nearest == static_cast<double>(c) && std::fabs(x - nearest) < 0.5 - kMargin;
  }
};

}  // namespace packsim
