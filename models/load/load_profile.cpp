#include "models/load/load_profile.hpp"

#include <algorithm>
#include <cmath>

namespace packsim {

LoadProfile LoadProfile::constant(double current_A) {
  LoadProfile p;
  p.t_s = {0.0};
  p.i_A = {current_A};
  return p;
}

double LoadProfile::duration_s() const {
  if (isConstant()) return std::numeric_limits<double>::infinity();
  return lap_s() * laps;
}

LoadSegment LoadProfile::segmentAt(double t) const {
  LoadSegment s;
  if (isConstant()) {
    s.i0_A = i_A[0];
    return s;
  }
  const double lap = lap_s();
  const double end = duration_s();
  if (t >= end) {
    s.t0_s = end;
    return s;  // zero current after the last lap
  }
  const double lapIndex = std::floor(t / lap);
  double offset = lapIndex * lap;
  const double tl = std::max(0.0, t - offset);
  // k: last point with t_s[k] <= tl
  size_t k = static_cast<size_t>(std::upper_bound(t_s.begin(), t_s.end(), tl) - t_s.begin()) - 1;
  // t - offset rounds: at a breakpoint of a later lap (120 + 0.07 - 120 = 0.0699999...)
  // the lookup can land on the piece that ends at t. The piece that contains t ends
  // after it, as the caller computes its end (offset + t_s[k + 1]).
  while (k + 1 < t_s.size() && offset + t_s[k + 1] <= t) ++k;
  if (k >= t_s.size() - 1) {  // t sits at the lap's end: the next lap's first piece
    offset += lap;
    k = 0;
    if (offset >= end) {
      s.t0_s = end;
      return s;
    }
  }
  s.t0_s = offset + t_s[k];
  s.t1_s = offset + t_s[k + 1];
  s.i0_A = i_A[k];
  if (interp == Interp::Linear) s.slope_A_per_s = (i_A[k + 1] - i_A[k]) / (t_s[k + 1] - t_s[k]);
  return s;
}

double LoadProfile::chargeUntil_As(double t) const {
  double q = 0.0, tc = 0.0;
  while (tc < t) {
    const LoadSegment s = segmentAt(tc);
    const double te = std::min(s.t1_s, t);
    q += 0.5 * (s.current_A(tc) + s.current_A(te)) * (te - tc);
    if (!std::isfinite(s.t1_s) || te >= t) break;
    tc = te;
  }
  return q;
}

}  // namespace packsim
