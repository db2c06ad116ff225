// Code -> firmware-unit conversions against hand-computed values.
#include <bms/bms_config.hpp>
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

// Every temperature channel lands where its device and input say: the first
// deviceCount x thermistorsPerDevice channels are the monitors' inputs in device order,
// the rest the MCU's, each converted from its own code (a device not yet read reports
// invalid). Expectation by division, as the channel numbering is documented.
TEST(Measure, TemperatureChannelsMapToTheirDeviceAndInput) {
  for (const uint8_t perDevice : {1, 2, 3}) {
    for (const uint8_t mcu : {0, 2}) {
      const uint8_t devices = 5;
      bms::Config cfg = bms::defaultConfig(static_cast<uint16_t>(devices * 2), static_cast<uint8_t>(devices * perDevice + mcu));
      cfg.afe.deviceCount = devices;
      cfg.afe.cellsPerDevice = 2;
      cfg.afe.thermistorsPerDevice = perDevice;
      cfg.scaling = scaling();
      bms::AcquisitionState a{};  // every reading zeroed: the test sets what it reads
      bms::acquisitionReset(a);
      for (uint8_t d = 0; d < devices; ++d) {
        a.seen[d] = d != 3;  // device 3 has not answered yet
        a.bad[d] = 0;
        a.last[d] = bms::FrameResult::Ok;
        for (uint8_t i = 0; i < perDevice; ++i) a.device[d].thermCode[i] = static_cast<uint16_t>(900 + 97 * d + 31 * i);
      }
      bms::Inputs in{};
      for (uint8_t m = 0; m < mcu; ++m) in.mcuThermistorCode[m] = static_cast<uint16_t>(2500 + 50 * m);
      bms::Telemetry tm{};
      int32_t quantity[bms::kQuantityCount];
      bms::measure(cfg, in, a, tm, quantity);
      for (uint8_t k = 0; k < cfg.thermistorCount; ++k) {
        int16_t want;
        if (k < devices * perDevice) {
          const uint8_t d = static_cast<uint8_t>(k / perDevice), i = static_cast<uint8_t>(k % perDevice);
          want = a.seen[d] ? bms::thermistorCodeToDeciCelsius(cfg.scaling, a.device[d].thermCode[i]) : bms::kTempInvalid_dC;
        } else {
          want = bms::thermistorCodeToDeciCelsius(cfg.scaling, in.mcuThermistorCode[k - devices * perDevice]);
        }
        ASSERT_EQ(tm.temperature_dC[k], want) << "channel " << int(k) << ", " << int(perDevice) << " per device";
        ASSERT_NE(want, bms::kTempInvalid_dC * (k < devices * perDevice && k / perDevice == 3 ? 0 : 1)) << int(k);
      }
    }
  }
}

}  // namespace
