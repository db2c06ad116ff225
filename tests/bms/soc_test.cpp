// The SOC estimate: OCV table lookup, coulomb counting between anchors, and the
// re-anchoring to the OCV after a rest (not before).
#include <bms/bms_soc.hpp>
#include <gtest/gtest.h>

namespace {

// A straight OCV line 3000 mV (empty) .. 4200 mV (full), 2000 mAh, rest 10 s below 100 mA.
bms::SocConfig config() {
  bms::SocConfig c{};
  c.capacity_mAh = 2000.0f;
  c.ocvPoints = 3;
  c.ocv_mV[0] = 3000;
  c.ocv_mV[1] = 3600;
  c.ocv_mV[2] = 4200;
  c.restCurrent_mA = 100;
  c.rest_ms = 10000;
  return c;
}

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

}  // namespace
