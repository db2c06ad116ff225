// Code -> firmware-unit conversions against hand-computed values.
#include <bms/bms_measure.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace {

bms::SensorScaling scaling() {
  bms::SensorScaling s{};
  s.cellLsb_uV = 6250000.0f / 16383.0f;
  s.currentZeroCode = 32768.0f;
  s.currentLsb_mA = 1.0f;
  s.thermFullScaleCode = 4095.0f;
  s.thermPullup_ohm = 10000.0f;
  s.thermR25_ohm = 10000.0f;
  s.thermBeta_K = 3435.0f;
  return s;
}

TEST(Measure, CellCodeUsesDatasheetLsb) {
  // BQ76PL536A: mV = code * 6250 / 16383.
  EXPECT_EQ(bms::cellCodeToMillivolts(scaling(), 9700), static_cast<uint16_t>(std::lround(9700 * 6250.0 / 16383.0)));
  EXPECT_EQ(bms::cellCodeToMillivolts(scaling(), 0), 0);
}

TEST(Measure, CurrentIsSignedAroundZeroCode) {
  EXPECT_EQ(bms::currentCodeToMilliamps(scaling(), 32768 + 1500), 1500);
  EXPECT_EQ(bms::currentCodeToMilliamps(scaling(), 32768 - 1500), -1500);
}

TEST(Measure, ThermistorAt25CAndRails) {
  // Equal pull-up and R25: half scale reads 25.0 C.
  EXPECT_NEAR(bms::thermistorCodeToDeciCelsius(scaling(), 2048), 250, 1);
  EXPECT_EQ(bms::thermistorCodeToDeciCelsius(scaling(), 4095), bms::kTempInvalid_dC);  // open
  EXPECT_EQ(bms::thermistorCodeToDeciCelsius(scaling(), 0), bms::kTempInvalid_dC);     // short
}

TEST(Measure, ThermistorBetaModelAt60C) {
  const double r = 10000.0 * std::exp(3435.0 * (1.0 / 333.15 - 1.0 / 298.15));
  const auto code = static_cast<uint16_t>(std::lround(4095.0 * r / (10000.0 + r)));
  EXPECT_NEAR(bms::thermistorCodeToDeciCelsius(scaling(), code), 600, 3);
}

}  // namespace
