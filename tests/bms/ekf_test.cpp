// The EKF per series group against an independent 1-RC cell integrated here in double
// (exact exponential update), with the firmware configured to the same model: it must
// converge from a wrong initial SOC and then track; the OCV table helpers agree with
// the table; the covariance stays positive.
#include <bms/bms_ekf.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace {

// OCV 3000 mV (empty) .. 4200 mV (full) in 3 points, 2000 mAh, r0 30 mOhm empty and
// 20 mOhm from half full up, r1 10 mOhm, 30 s.
bms::SocConfig config() {
  bms::SocConfig c{};
  c.capacity_mAh = 2000.0f;
  c.ocvPoints = 3;
  c.ocv_mV[0] = 3000;
  c.ocv_mV[1] = 3500;
  c.ocv_mV[2] = 4200;
  c.restCurrent_mA = 100;
  c.rest_ms = 10000;
  c.ekf = bms::EkfConfig{{30.0f, 20.0f, 20.0f}, 10.0f, 30.0f, 5.0f, 1.7e-4f, 1.0f, -1.0f, 0.05f};
  return c;
}

double ocvTrue_mV(double soc) {  // the same piecewise-linear curves, in double
  return soc < 0.5 ? 3000.0 + soc * 1000.0 : 3500.0 + (soc - 0.5) * 1400.0;
}
double r0True_ohm(double soc) { return soc < 0.5 ? 0.030 - soc * 0.020 : 0.020; }

TEST(Ekf, OcvTableValueAndSlope) {
  const bms::SocConfig c = config();
  EXPECT_NEAR(bms::ocvAt_mV(c, 0.25f), 3250.0f, 1e-3f);
  EXPECT_NEAR(bms::ocvAt_mV(c, 0.75f), 3850.0f, 1e-3f);
  EXPECT_NEAR(bms::ocvSlope_mV(c, 0.25f), 1000.0f, 1e-3f);
  EXPECT_NEAR(bms::ocvSlope_mV(c, 0.75f), 1400.0f, 1e-3f);
  EXPECT_NEAR(bms::ocvAt_mV(c, 1.2f), 4200.0f, 1e-3f);  // clamped
  EXPECT_NEAR(bms::r0At_mOhm(c, 0.25f), 25.0f, 1e-4f);
  EXPECT_NEAR(bms::r0Slope_mOhm(c, 0.25f), -20.0f, 1e-4f);
  EXPECT_NEAR(bms::r0Slope_mOhm(c, 0.75f), 0.0f, 1e-4f);
}

// A pulsed discharge of a 1-RC cell from 0.9 to about 0.35 (into the rising R0); the
// EKF starts at 0.5 although the cell is at 0.9.
TEST(Ekf, ConvergesFromAWrongInitialSocAndTracks) {
  bms::SocConfig c = config();
  c.ekf.initialSoc = 0.5f;
  c.ekf.initialSocSd = 0.3f;
  bms::EkfState s;
  bms::ekfReset(s);
  double soc = 0.9, v1_mV = 0.0;
  const double cap_As = 2.0 * 3600.0, r1 = 0.010, tau = 30.0, dt = 0.1;
  uint32_t t_ms = 0;
  double worstAfter60s = 0.0;
  for (int k = 0; k <= 36000; ++k, t_ms += 100) {  // one hour at 100 ms
    const double i_A = (k / 300) % 2 == 0 ? 2.0 : 0.2;  // 30 s at 1C, 30 s at 0.1C
    const uint16_t v = static_cast<uint16_t>(std::lround(ocvTrue_mV(soc) - v1_mV - r0True_ohm(soc) * i_A * 1e3));
    const int32_t i_mA = static_cast<int32_t>(std::lround(i_A * 1e3));
    bms::ekfUpdate(c, s, 1, true, &v, i_mA, t_ms);
    if (k == 0) EXPECT_EQ(s.group[0].soc, 0.5f);  // started where it was told
    if (t_ms >= 60000) worstAfter60s = std::fmax(worstAfter60s, std::fabs(s.group[0].soc - soc));
    EXPECT_GE(s.group[0].p00, 0.0f);
    EXPECT_GE(s.group[0].p00 * s.group[0].p11 - s.group[0].p01 * s.group[0].p01, -1e-3f);
    // The plant: exact update over the tick with the current held.
    const double a = std::exp(-dt / tau);
    v1_mV = a * v1_mV + r1 * i_A * 1e3 * (1.0 - a);
    soc -= i_A * dt / cap_As;
  }
  EXPECT_LT(worstAfter60s, 0.01);
  EXPECT_NEAR(bms::ekfPackSoc(s, 1), soc, 0.005);
}

// Without a complete reading it only predicts: coulomb counting at the model's capacity.
TEST(Ekf, PredictsByChargeWithoutReadings) {
  bms::SocConfig c = config();
  bms::EkfState s;
  bms::ekfReset(s);
  const uint16_t v[2] = {3500, 3500};
  bms::ekfUpdate(c, s, 2, true, v, 0, 0);  // starts from the OCV: 0.5
  EXPECT_NEAR(bms::ekfPackSoc(s, 2), 0.5f, 1e-4f);
  for (uint32_t t = 100; t <= 360000; t += 100) bms::ekfUpdate(c, s, 2, false, v, 1000, t);
  // 1 A for 360 s from 2000 mAh: -0.05.
  EXPECT_NEAR(bms::ekfPackSoc(s, 2), 0.45f, 1e-4f);
}

}  // namespace
