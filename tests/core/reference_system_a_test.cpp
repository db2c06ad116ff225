// Reference system A as its team built it: the 30 A fuse blows on any sustained
// current above 30 A (their report), and holds at or below it.
#include <gtest/gtest.h>

#include <cmath>

#include "core/scenario/load_scenario.hpp"
#include "models/hw/fuse.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

TEST(ReferenceSystemA, TheFuseBlowsOnSustainedCurrentAboveThirtyAmpsOnly) {
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/eco_marathon_12s.yaml");
  const FuseConfig& f = s.hardware.fuse;
  ASSERT_TRUE(f.present);
  EXPECT_TRUE(std::isinf(fuseBlowTime_s(f, 30.0)));
  const double t31 = fuseBlowTime_s(f, 31.0);
  ASSERT_TRUE(std::isfinite(t31));
  EXPECT_NEAR(t31, f.i2t_A2s / (31.0 * 31.0 - 30.0 * 30.0), 1e-9);
  // Integrated at the BMS tick, the same current blows it at that time (within a tick).
  FuseState st;
  double t = 0.0;
  while (!st.blown && t < 120.0) {
    fuseStep(f, st, 31.0, 0.01);
    t += 0.01;
  }
  EXPECT_TRUE(st.blown);
  EXPECT_NEAR(t, t31, 0.011);
  // 30 A for an hour: never.
  FuseState held;
  for (int k = 0; k < 360000; ++k) fuseStep(f, held, 30.0, 0.01);
  EXPECT_FALSE(held.blown);
}

}  // namespace
}  // namespace packsim
