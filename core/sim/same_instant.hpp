// When two instants of simulated time are one. Tick times k·T and the breakpoints a
// scenario writes (a load step at 0.7 s, a fault at 300 s, a 10 Hz logger's rows)
// differ in their last bits: 70 · 0.01 = 0.7000000000000001. CVODE refuses to integrate
// across a few ulps ("tout too close to t0", flag -27), and such a sliver carries no
// physics, so a breakpoint that close to a tick is taken at the tick.
// 1e-12 · t is ~4,500 ulps of t (far above rounding) and 0.1 µs at 28 h (far below any
// tick or any input a scenario can time).
#pragma once
#include <algorithm>
#include <cmath>

namespace packsim {

inline double sameInstantTol_s(double t_s) { return 1e-12 * std::max(1.0, std::fabs(t_s)); }

// t has reached `mark` (is at it or after it, up to rounding).
inline bool reached(double t_s, double mark_s) { return t_s >= mark_s - sameInstantTol_s(mark_s); }

}  // namespace packsim
