// Code -> firmware-unit conversions against hand-computed values.
#include <bms/bms_afe_driver.hpp>
#include <bms/bms_config.hpp>
#include <bms/bms_measure.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

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

// A ratiometric part's inputs keep their conversion while the code stays: over ticks of
// random read-outs (some inputs unchanged, some changed, rails, reads that fail and leave
// the reading as it was, ticks without a read-out), every channel still equals a fresh
// conversion of the code its device holds. A code written past afeSetThermCodes shows
// the kept value, so the test sees the reuse happen. measure() says whether a
// temperature moved (two MCU channels moving now and then as well): exactly when one did.
TEST(Measure, KeptThermistorConversionsEqualFreshOnes) {
  const uint8_t devices = 3, perDevice = 4, mcu = 2;
  bms::Config cfg = bms::defaultConfig(static_cast<uint16_t>(devices * 2), static_cast<uint8_t>(devices * perDevice + mcu));
  ASSERT_EQ(bms::afeDriver(cfg.afe.part)->api->temperature_dC, bms::afeRatiometricTemp_dC);
  cfg.afe.deviceCount = devices;
  cfg.afe.cellsPerDevice = 2;
  cfg.afe.thermistorsPerDevice = perDevice;
  cfg.scaling = scaling();
  bms::AcquisitionState a{};
  bms::acquisitionReset(a);
  bms::Inputs in{};
  bms::Telemetry tm{};
  int32_t quantity[bms::kQuantityCount];
  std::mt19937 rng(7);
  uint32_t kept = 0, converted = 0, stillTicks = 0;
  for (int tick = 0; tick < 3000; ++tick) {
    bms::FrameResult res[bms::kMaxDevices];
    const bool readout = tick % 3 != 2;
    for (uint8_t d = 0; d < devices; ++d) {
      res[d] = rng() % 7 == 0 ? bms::FrameResult::Timeout : bms::FrameResult::Ok;
      if (!readout || res[d] != bms::FrameResult::Ok) continue;
      uint16_t codes[bms::kMaxThermPerDevice] = {};
      for (uint8_t i = 0; i < perDevice; ++i) {
        const uint32_t roll = rng() % 10;
        codes[i] = a.device[d].thermCode[i];
        if (roll == 0) codes[i] = 0;
        else if (roll == 1) codes[i] = 4095;
        else if (roll < 5) codes[i] = static_cast<uint16_t>(1000 + rng() % 2000);
      }
      bms::afeSetThermCodes(a.device[d], codes);
    }
    if (readout) bms::acquireResults(cfg, a, res, true);
    for (uint8_t d = 0; d < devices; ++d)
      for (uint8_t i = 0; i < perDevice; ++i) {
        const bool held = (a.device[d].thermConverted >> i) & 1u;
        kept += held ? 1u : 0u;
        converted += held ? 0u : 1u;
      }
    for (uint8_t m = 0; m < mcu; ++m)
      if (rng() % 8 == 0) in.mcuThermistorCode[m] = static_cast<uint16_t>(rng() % 5 == 0 ? 0 : 1500 + rng() % 4);
    int16_t before[bms::kMaxThermistors];
    std::memcpy(before, tm.temperature_dC, sizeof before);
    const bool moved = bms::measure(cfg, in, a, tm, quantity);
    ASSERT_EQ(moved, std::memcmp(before, tm.temperature_dC, sizeof before) != 0) << "tick " << tick;
    stillTicks += moved ? 0u : 1u;
    for (uint8_t k = 0; k < devices * perDevice; ++k) {
      const uint8_t d = static_cast<uint8_t>(k / perDevice), i = static_cast<uint8_t>(k % perDevice);
      const int16_t want = a.seen[d] ? bms::thermistorCodeToDeciCelsius(cfg.scaling, a.device[d].thermCode[i])
                                     : bms::kTempInvalid_dC;
      ASSERT_EQ(tm.temperature_dC[k], want) << "tick " << tick << ", channel " << int(k);
    }
  }
  EXPECT_GT(kept, 10000u);  // most inputs kept their conversion...
  EXPECT_GT(converted, 3000u);  // ... and the changed ones were converted again
  EXPECT_GT(stillTicks, 100u);   // ticks where no temperature moved

  // The reuse is real: a code written around afeSetThermCodes is not seen.
  const int16_t before = tm.temperature_dC[0];
  ASSERT_EQ(a.device[0].thermCode[0] == 2600, false);
  a.device[0].thermCode[0] = 2600;
  bms::measure(cfg, in, a, tm, quantity);
  EXPECT_EQ(tm.temperature_dC[0], before);
  uint16_t codes[bms::kMaxThermPerDevice] = {};
  for (uint8_t i = 0; i < bms::kMaxThermPerDevice; ++i) codes[i] = a.device[0].thermCode[i];
  codes[0] = 2601;
  bms::afeSetThermCodes(a.device[0], codes);  // through the setter it is converted
  bms::measure(cfg, in, a, tm, quantity);
  EXPECT_EQ(tm.temperature_dC[0], bms::thermistorCodeToDeciCelsius(cfg.scaling, 2601));
  // A reading built afresh holds no conversion.
  a.device[0] = bms::DeviceReading{};
  a.device[0].thermCode[0] = 2600;
  bms::measure(cfg, in, a, tm, quantity);
  EXPECT_EQ(tm.temperature_dC[0], bms::thermistorCodeToDeciCelsius(cfg.scaling, 2600));
}

TEST(Measure, SetThermCodesClearsOnlyTheChangedInputs) {
  bms::DeviceReading r{};
  r.thermCode[2] = 1234;
  r.thermConverted = 0xFF;
  uint16_t codes[bms::kMaxThermPerDevice] = {0, 0, 1234};
  bms::afeSetThermCodes(r, codes);
  EXPECT_EQ(r.thermConverted, 0xFF);
  codes[2] = 1235;
  codes[7] = 9;
  bms::afeSetThermCodes(r, codes);
  EXPECT_EQ(r.thermConverted, 0x7B);
  EXPECT_EQ(r.thermCode[2], 1235);
  EXPECT_EQ(r.thermCode[7], 9);
  EXPECT_EQ(r.thermCode[0], 0);
}


// A call that read nothing (FrameResult::NotRead: the driver recovered its chain instead)
// leaves each device's standing as it was -- its bad-read count, its last result, whether
// it was ever seen -- and makes no reading new; a read of one device alone is a read.
TEST(Measure, ACallThatReadNothingChangesNoDevicesStanding) {
  bms::Config cfg = bms::defaultConfig(4, 2);
  cfg.afe.deviceCount = 2;
  bms::AcquisitionState a{};
  bms::acquisitionReset(a);
  bms::FrameResult res[bms::kMaxDevices] = {bms::FrameResult::Ok, bms::FrameResult::Timeout};
  bms::acquireResults(cfg, a, res, true);
  a.fresh = false;
  const bms::FrameResult none[bms::kMaxDevices] = {bms::FrameResult::NotRead, bms::FrameResult::NotRead};
  bms::acquireResults(cfg, a, none, true);
  EXPECT_FALSE(a.fresh);
  EXPECT_EQ(a.bad[0], 0);
  EXPECT_EQ(a.bad[1], 1);
  EXPECT_EQ(a.last[0], bms::FrameResult::Ok);
  EXPECT_EQ(a.last[1], bms::FrameResult::Timeout);
  EXPECT_TRUE(a.seen[0]);
  EXPECT_FALSE(a.seen[1]);
  const bms::FrameResult one[bms::kMaxDevices] = {bms::FrameResult::NotRead, bms::FrameResult::Timeout};
  bms::acquireResults(cfg, a, one, true);
  EXPECT_EQ(a.bad[1], 2);
  EXPECT_FALSE(a.fresh);  // device 1 has not delivered cells yet
  const bms::FrameResult other[bms::kMaxDevices] = {bms::FrameResult::NotRead, bms::FrameResult::Ok};
  bms::acquireResults(cfg, a, other, true);
  EXPECT_TRUE(a.fresh);  // device 0's cells of the first call are still new to the estimators
}

// The estimators take a reading once every device's cells are new since they last took
// one: a device that failed holds the cells they used, and so does a part whose own
// measurement loop has not run again since the previous read-out (sameLoop).
TEST(Measure, AReadingIsFreshOnceEveryDeviceHasNewCells) {
  bms::Config cfg = bms::defaultConfig(4, 2);
  cfg.afe.deviceCount = 2;
  bms::AcquisitionState a{};
  bms::acquisitionReset(a);
  using R = bms::FrameResult;
  const auto take = [&](R r0, R r1) {
    const R res[bms::kMaxDevices] = {r0, r1};
    bms::acquireResults(cfg, a, res, true);
    const bool fresh = a.fresh;
    a.fresh = false;  // the core takes it
    return fresh;
  };
  a.device[0].sameLoop = true;  // the first cells a device gives are new, whichever loop
  EXPECT_TRUE(take(R::Ok, R::Ok));
  a.device[0].sameLoop = false;
  EXPECT_FALSE(take(R::Ok, R::BadCrc));  // device 1's cells are the ones taken
  EXPECT_TRUE(take(R::Timeout, R::Ok));  // device 0's of the call before are new
  a.device[0].sameLoop = true;           // its part's loop has not run again
  EXPECT_FALSE(take(R::Ok, R::Ok));
  a.device[0].sameLoop = false;
  EXPECT_TRUE(take(R::Ok, R::NotRead));  // device 1's of the call before are new
  EXPECT_TRUE(take(R::Ok, R::Ok));  // a part converting on command: every read-out is new
  EXPECT_TRUE(take(R::Ok, R::Ok));
  // An alert poll brings no cells.
  const R ok[bms::kMaxDevices] = {R::Ok, R::Ok};
  bms::acquireResults(cfg, a, ok, false);
  EXPECT_FALSE(a.fresh);
}

// The current the cells were measured under: every device's loop current (their mean),
// else none (the MCU's current of the tick is theirs).
TEST(Measure, TheLoopCurrentIsKnownOnlyWhereEveryDeviceMeasuredOne) {
  bms::Config cfg = bms::defaultConfig(4, 2);
  cfg.afe.deviceCount = 2;
  bms::AcquisitionState a{};
  bms::acquisitionReset(a);
  int32_t mA = 12345;
  EXPECT_FALSE(bms::loopCurrent(cfg, a, mA));
  EXPECT_EQ(mA, 12345);
  a.device[0].loopCurrent = a.device[1].loopCurrent = true;
  a.device[0].current_mA = 3000;
  a.device[1].current_mA = 3011;
  ASSERT_TRUE(bms::loopCurrent(cfg, a, mA));
  EXPECT_EQ(mA, 3005);
  a.device[1].loopCurrent = false;  // its register at a rail
  EXPECT_FALSE(bms::loopCurrent(cfg, a, mA));
}

}  // namespace
