// The SOC estimate: OCV table lookup, coulomb counting between anchors, and the
// re-anchoring to the OCV after a rest (not before).
#include <bms/bms_soc.hpp>
#include <gtest/gtest.h>

#include <cmath>

#include "soc_fixture.hpp"

namespace {

// A straight OCV line 3000 mV (empty) .. 4200 mV (full), 2000 mAh, rest 10 s below 100 mA.
bms::SocConfig config() { return bms_test::socConfig(3600); }

TEST(Soc, OcvTableIsLinearAndClamped) {
  const bms::SocConfig c = config();
  EXPECT_NEAR(bms::socFromOcv(c, 3600), 0.5f, 1e-6);
  EXPECT_NEAR(bms::socFromOcv(c, 3300), 0.25f, 1e-6);
  EXPECT_NEAR(bms::socFromOcv(c, 2500), 0.0f, 1e-6);
  EXPECT_NEAR(bms::socFromOcv(c, 4500), 1.0f, 1e-6);
}

TEST(Soc, CountsChargeAndReanchorsAfterRest) {
  const bms::SocConfig c = config();
  bms::SocState s;
  bms::socReset(s);
  uint32_t t = 0;
  // Anchored at the first complete measurement: 3600 mV -> 0.5.
  bms::socUpdate(c, s, true, 3600, 0, t);
  EXPECT_NEAR(bms::socValue(c, s), 0.5f, 1e-6);
  // 1000 mA for 30 min from a 2000 mAh pack: -0.25 (the voltage sags, but under load
  // the estimate must not follow it).
  for (int k = 0; k < 180000; ++k) bms::socUpdate(c, s, true, 3350, 1000, t += 10);
  EXPECT_NEAR(bms::socValue(c, s), 0.25f, 1e-4);
  // At rest the cells relax to 3420 mV (0.35 by the table). Not re-anchored before
  // 10 s of rest, re-anchored after.
  for (int k = 0; k < 990; ++k) bms::socUpdate(c, s, true, 3420, 20, t += 10);
  EXPECT_NEAR(bms::socValue(c, s), 0.25f, 1e-3);
  for (int k = 0; k < 20; ++k) bms::socUpdate(c, s, true, 3420, 20, t += 10);
  EXPECT_NEAR(bms::socValue(c, s), 0.35f, 1e-3);
}

// Capacity from charge between two rested OCV points: 600 mAh moved the OCV from 0.5 to
// 0.2, so the capacity is 2000 mAh -- whatever capacity the firmware was configured with.
TEST(Soc, EstimatesCapacityBetweenTwoRests) {
  bms::SocConfig c = config();
  c.capacity_mAh = 1500.0f;  // configured wrong
  c.sohMinDeltaSoc = 0.2f;
  bms::SocState s;
  bms::socReset(s);
  uint32_t t = 0;
  bms::socUpdate(c, s, true, 3600, 0, t);  // rested at start: 0.5
  EXPECT_EQ(s.capacityEstimate_mAh, 0.0f);
  for (int k = 0; k < 216000; ++k) bms::socUpdate(c, s, true, 3300, 1000, t += 10);  // 600 mAh
  EXPECT_EQ(s.capacityEstimate_mAh, 0.0f);
  for (int k = 0; k < 1100; ++k) bms::socUpdate(c, s, true, 3240, 0, t += 10);  // rest: 0.2 by the table
  EXPECT_NEAR(s.capacityEstimate_mAh, 2000.0f, 1.0f);
  EXPECT_NEAR(bms::socValue(c, s), 0.2f, 1e-3f);
}

// The same discharge from a cell with an RC branch (20 mOhm, 30 s: 20 mV at 1 A), its
// readings computed here as OCV - v1 - R0·I, rested 1.5 tau1 before the anchor: the
// branch still holds 20 mV · e^-1.5 = 4.5 mV, 0.37 % SOC on the table's 1200 mV per unit.
// Anchored on the reading plus the model's RC voltage, the anchor is the cell's SOC (0.2)
// within the reading's 1 mV and the capacity 2000 mAh within 0.2 %; on the reading alone
// the anchor was 0.197 and the capacity 1978 mAh.
TEST(Soc, RestAnchorAddsTheRcVoltageTheModelStillHolds) {
  bms::SocConfig c = config();
  c.sohMinDeltaSoc = 0.2f;
  c.ekf.r1_mOhm = 20.0f;
  c.ekf.tau1_s = 30.0f;
  c.rest_ms = 45000;  // 1.5 tau1
  bms::SocState s;
  bms::socReset(s);
  double soc = 0.5, v1_mV = 0.0;
  const double r0_mOhm = 30.0, cap_mAs = 2000.0 * 3600.0, tau_s = 30.0, dt_s = 0.1;
  uint32_t t = 0;
  for (int k = 0; k <= 21600 + 600; ++k, t += 100) {  // rested, 36 min at 1 A (600 mAh), 60 s at rest
    const double i_mA = k >= 1 && k <= 21600 ? 1000.0 : 0.0;
    const uint16_t v = static_cast<uint16_t>(std::lround(3000.0 + soc * 1200.0 - v1_mV - r0_mOhm * i_mA * 1e-3));
    bms::socUpdate(c, s, true, v, static_cast<int32_t>(i_mA), t);
    const double a = std::exp(-dt_s / tau_s);  // the plant over the tick that follows
    v1_mV = a * v1_mV + 20.0 * i_mA * 1e-3 * (1.0 - a);
    soc -= i_mA * dt_s * 1.0 / cap_mAs;
  }
  EXPECT_NEAR(bms::socValue(c, s), 0.2f, 1e-3f);
  EXPECT_NEAR(s.capacityEstimate_mAh, 2000.0f, 4.0f);
}

// A change below sohMinDeltaSoc gives no estimate (the OCV error would dominate).
TEST(Soc, NoCapacityFromASmallSocChange) {
  bms::SocConfig c = config();
  c.sohMinDeltaSoc = 0.3f;
  bms::SocState s;
  bms::socReset(s);
  uint32_t t = 0;
  bms::socUpdate(c, s, true, 3600, 0, t);
  for (int k = 0; k < 72000; ++k) bms::socUpdate(c, s, true, 3400, 1000, t += 10);  // 200 mAh = 0.1
  for (int k = 0; k < 1100; ++k) bms::socUpdate(c, s, true, 3480, 0, t += 10);
  EXPECT_EQ(s.capacityEstimate_mAh, 0.0f);
}

// reference system C display: < 3.3 V one bar, one per 0.1 V up to 3.9 V, > 4.0 V eight.
TEST(Soc, DisplayBarsFollowTheSystemCTable) {
  bms::SocConfig c = config();
  const uint16_t bars[bms::kDisplayBars - 1] = {3300, 3400, 3500, 3600, 3700, 3800, 4001};
  for (int i = 0; i + 1 < bms::kDisplayBars; ++i) c.displayBars_mV[i] = bars[i];
  EXPECT_EQ(bms::socDisplayBars(c, 3000), 1);
  EXPECT_EQ(bms::socDisplayBars(c, 3299), 1);
  EXPECT_EQ(bms::socDisplayBars(c, 3300), 2);
  EXPECT_EQ(bms::socDisplayBars(c, 3450), 3);
  EXPECT_EQ(bms::socDisplayBars(c, 3750), 6);
  EXPECT_EQ(bms::socDisplayBars(c, 3899), 7);
  EXPECT_EQ(bms::socDisplayBars(c, 4000), 7);
  EXPECT_EQ(bms::socDisplayBars(c, 4001), 8);
  EXPECT_EQ(bms::socDisplayBars(c, 4200), 8);
}

}  // namespace
