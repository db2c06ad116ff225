#include "models/load/load_profile.hpp"

#include <gtest/gtest.h>

namespace packsim {
namespace {

LoadProfile lap(LoadProfile::Interp interp) {
  LoadProfile p;
  p.t_s = {0, 10, 30, 40};
  p.i_A = {5, 20, 0, 0};
  p.interp = interp;
  p.laps = 3;
  return p;
}

TEST(LoadProfile, StepHoldsUntilNextPointAndRepeats) {
  const LoadProfile p = lap(LoadProfile::Interp::Step);
  EXPECT_DOUBLE_EQ(p.duration_s(), 120.0);
  EXPECT_DOUBLE_EQ(p.segmentAt(9.99).current_A(9.99), 5.0);
  EXPECT_DOUBLE_EQ(p.segmentAt(10.0).current_A(10.0), 20.0);  // right-continuous
  EXPECT_DOUBLE_EQ(p.segmentAt(85.0).current_A(85.0), 5.0);   // third lap
  EXPECT_DOUBLE_EQ(p.segmentAt(95.0).current_A(95.0), 20.0);
  EXPECT_DOUBLE_EQ(p.segmentAt(95.0).t1_s, 110.0);
  EXPECT_DOUBLE_EQ(p.segmentAt(130.0).current_A(130.0), 0.0);  // after the race
}

// A 100 Hz logger's lap repeated: walking from breakpoint to breakpoint always moves on,
// although t - offset rounds below a breakpoint in later laps (120 + 0.07 - 120 is
// 0.0699999...; the lookup once returned the piece ending at t, and the loop stepping
// the plant across breakpoints hung there).
TEST(LoadProfile, EveryPieceEndsAfterTheBreakpointItStartsAt) {
  LoadProfile p;
  for (int k = 0; k <= 12000; ++k) {
    p.t_s.push_back(static_cast<double>(k) / 100.0);
    p.i_A.push_back(static_cast<double>(k % 7));
  }
  p.laps = 4;
  long pieces = 0;
  for (double t = 0.0; t < p.duration_s(); ++pieces) {
    const LoadSegment s = p.segmentAt(t);
    ASSERT_GT(s.t1_s, t) << "piece at t = " << t;
    ASSERT_LE(s.t0_s, t + 1e-9) << "piece at t = " << t;
    t = s.t1_s;
  }
  EXPECT_EQ(pieces, 4 * 12000);
}

TEST(LoadProfile, LinearInterpolates) {
  const LoadProfile p = lap(LoadProfile::Interp::Linear);
  EXPECT_DOUBLE_EQ(p.segmentAt(5.0).current_A(5.0), 12.5);
  EXPECT_DOUBLE_EQ(p.segmentAt(20.0).current_A(20.0), 10.0);
}

TEST(LoadProfile, ChargeIntegralIsExact) {
  EXPECT_DOUBLE_EQ(lap(LoadProfile::Interp::Step).chargeUntil_As(120.0), 3 * (5 * 10 + 20 * 20));
  EXPECT_DOUBLE_EQ(lap(LoadProfile::Interp::Linear).chargeUntil_As(40.0), 12.5 * 10 + 10 * 20);
}

}  // namespace
}  // namespace packsim
