// Load-time checks of a cell curve over its whole domain: every state of charge in
// [0, 1] (mapped onto the curve's own axis with the preset's nominal capacity) at
// every temperature the curve distinguishes (the grid of a 2-D table; for an
// Arrhenius factor its reference and the ends of kCheckTemps_C). A failure is one
// message naming the SOC (and discharged Ah) and the temperature where it fails; the
// loader puts the curve's file:line:column in front.
#pragma once
#include <cmath>
#include <optional>
#include <string>

#include "models/cell/curve.hpp"

namespace packsim {

enum class CurveRule {
  Positive,    // a resistance, capacitance or time constant: > 0 and finite
  Finite,      // e.g. dOCV/dT: any sign, finite
  NonNegative, // e.g. a hysteresis amplitude
  Ocv,         // > 0, finite, strictly increasing in SOC (held-flat ends excepted;
               // a plain number is an ideal constant source and accepted)
};

// The first failure, or nothing if the curve holds over the whole domain. max_abs:
// the largest magnitude the curve may take as written (at its reference temperature or
// the rows of its table; an Arrhenius factor may carry it beyond at other temperatures).
std::optional<std::string> curveDomainError(const Curve& c, CurveRule rule, double axis_capacity_Ah,
                                            double max_abs = HUGE_VAL);

}  // namespace packsim
