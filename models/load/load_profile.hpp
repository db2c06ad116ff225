// A load demand over time -- current [A] or power [W] -- constant, or a piecewise
// profile of (time_s, value) points repeated for a number of laps. Positive values
// discharge the pack; negative values are regeneration / charging.
//
//   step:   the current of point k holds on [t_k, t_k+1)
//   linear: linear interpolation between points
//
// A lap ends at the last point's time. The integrator is handed one Segment at a
// time (a linear piece between two breakpoints), so no step straddles a jump.
#pragma once
#include <limits>
#include <vector>

namespace packsim {

struct LoadSegment {
  double t0_s = 0.0;
  double t1_s = std::numeric_limits<double>::infinity();
  double i0_A = 0.0;
  double slope_A_per_s = 0.0;
  double current_A(double t) const { return i0_A + slope_A_per_s * (t - t0_s); }  // or W for a power load
};

struct LoadProfile {
  enum class Interp { Step, Linear };
  enum class Quantity { Current_A, Power_W };
  Quantity quantity = Quantity::Current_A;
  std::vector<double> t_s;  // t_s[0] == 0, strictly increasing
  std::vector<double> i_A;
  Interp interp = Interp::Step;
  int laps = 1;

  static LoadProfile constant(double current_A);
  bool isConstant() const { return t_s.size() == 1; }
  double lap_s() const { return t_s.back(); }
  // Total length of the profile; infinite for a constant load.
  double duration_s() const;
  // The piece that contains t (right-continuous at breakpoints). Past the end of
  // the last lap the current is zero.
  LoadSegment segmentAt(double t) const;
  // Integral of current from 0 to t [A·s] (for checks and reports).
  double chargeUntil_As(double t) const;
};

}  // namespace packsim
