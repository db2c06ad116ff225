// The monitor-IC models as the firmware's frame parser sees them: datasheet LSBs per
// class, injected communication faults (CRC errors at a rate, stuck 0x00/0xFF, silent
// devices, a broken daisy-chain link), and the secondary protection's FAULT line that
// latches until the host clears it.
#include <bms/bms_afe.hpp>
#include <gtest/gtest.h>

#include <cmath>

#include "core/sim/simulation.hpp"
#include "models/afe/monitor_stack.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

Scenario stackScenario(const std::string& model, int series) {
  return test::scenarioFromYaml("name: afe\npack:\n  series: " + std::to_string(series) +
                                "\n  cell: {capacity_Ah: 5, ocv_V: 3.7, r0_ohm: 0.01}\n"
                                "hardware:\n  afe: {model: " + model + "}\n  cell_adc: {noise_mV_rms: 0}\n"
                                "load: {current_A: 0}\nrun: {duration_s: 1}\n");
}

struct Rig {
  Scenario s;
  MonitorStack stack;
  MonitorTruth truth;
  bms::Inputs in{};
  Rng rng{7};
  explicit Rig(const std::string& model, int series = 12)
      : s(stackScenario(model, series)), stack(s.hardware.afe, series, 7), truth(stack.makeTruth()) {
    for (double& v : truth.cell_V) v = 3.7;
  }
  void read(double t) {
    stack.update(t, truth);
    stack.read(t, truth, rng, in);
  }
  bms::FrameResult parse(int d, bms::DeviceReading& r, float lsb_uV) const {
    const MonitorConfig& a = s.hardware.afe;
    const bms::AfeConfig c{a.model, static_cast<uint8_t>(a.devices), static_cast<uint8_t>(a.cells_per_device),
                           static_cast<uint8_t>(a.thermistors_per_device), a.crc, 5};
    return bms::afeParse(c, static_cast<uint16_t>(stack.cellCount()), static_cast<uint8_t>(d), lsb_uV,
                         in.afe[d], r);
  }
};

struct LsbCase {
  const char* model;
  double lsb_V;  // datasheet
};

class Lsb : public ::testing::TestWithParam<LsbCase> {};

TEST_P(Lsb, CellCodesFollowTheDatasheetLsb) {
  const LsbCase c = GetParam();
  Rig rig(c.model);
  rig.truth.cell_V[0] = 3.7;
  rig.truth.cell_V[1] = 2.0123;
  rig.read(0.0);
  bms::DeviceReading r{};
  ASSERT_EQ(rig.parse(0, r, static_cast<float>(c.lsb_V * 1e6)), bms::FrameResult::Ok);
  for (int k = 0; k < 2; ++k) {
    const double v = rig.truth.cell_V[static_cast<size_t>(k)];
    // The code is the nearest LSB step; the firmware scales it back to mV.
    const double expect_mV = std::round(v / c.lsb_V) * c.lsb_V * 1e3;
    EXPECT_NEAR(r.cell_mV[k], expect_mV, 0.5 + 1e-9) << c.model << " cell " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Monitor, Lsb,
                         ::testing::Values(LsbCase{"bq76pl536a", 6.25 / 16383.0}, LsbCase{"bq76pl455a", 5.0 / 65535.0},
                                           LsbCase{"bq76952", 1e-3}),
                         [](const ::testing::TestParamInfo<LsbCase>& i) { return std::string(i.param.model); });

TEST(Monitor, CrcErrorsAtTheirRate) {
  Rig rig("bq76pl536a", 12);
  rig.truth.comm[1].crc_error_rate = 0.3;
  int bad = 0, badOther = 0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    rig.read(k * 0.01);
    bms::DeviceReading r{};
    bad += rig.parse(1, r, 381.47f) == bms::FrameResult::BadCrc;
    badOther += rig.parse(0, r, 381.47f) != bms::FrameResult::Ok;
  }
  // Binomial(4000, 0.3): sd = 29 frames; 5 sd either side.
  EXPECT_NEAR(bad, 0.3 * n, 5 * std::sqrt(n * 0.3 * 0.7));
  EXPECT_EQ(badOther, 0);
}

TEST(Monitor, StuckAndSilentDevicesAndABrokenLink) {
  Rig rig("bq76pl536a", 36);  // 6 devices of 6 cells
  rig.truth.comm[0].stuck_byte = 0xFF;
  rig.truth.comm[1].stuck_byte = 0x00;
  rig.truth.comm[2].silent = true;
  rig.read(0.0);
  bms::DeviceReading r{};
  EXPECT_NE(rig.parse(0, r, 381.47f), bms::FrameResult::Ok);
  for (uint8_t i = 0; i < rig.in.afe[0].length; ++i) ASSERT_EQ(rig.in.afe[0].bytes[i], 0xFF);
  EXPECT_NE(rig.parse(1, r, 381.47f), bms::FrameResult::Ok);
  EXPECT_EQ(rig.parse(2, r, 381.47f), bms::FrameResult::Timeout);
  EXPECT_EQ(rig.parse(3, r, 381.47f), bms::FrameResult::Ok);
  // A link broken above device 4 (index 3) silences 5 and 6 but not 1-4.
  rig.truth.comm.assign(6, MonitorDeviceFault{});
  rig.truth.broken_link_above = 3;
  rig.read(0.01);
  for (int d = 0; d < 6; ++d)
    EXPECT_EQ(rig.parse(d, r, 381.47f) == bms::FrameResult::Ok, d <= 3) << "device " << d + 1;
}

TEST(Monitor, SecondaryOverVoltageLatchesUntilTheHostClears) {
  Rig rig("bq76pl536a", 12);
  const SecondaryProtection& p = rig.s.hardware.afe.secondary;
  rig.truth.cell_V[7] = p.cov_V + 0.05;
  double t = 0.0;
  for (; t < p.cov_delay_s - 0.02; t += 0.01) rig.read(t);
  EXPECT_FALSE(rig.stack.faultLine()) << "before its delay";
  for (; t < p.cov_delay_s + 0.015; t += 0.01) rig.read(t);
  EXPECT_TRUE(rig.stack.faultLine());
  EXPECT_TRUE(rig.stack.deviceFault(1));
  EXPECT_FALSE(rig.stack.deviceFault(0));
  rig.truth.cell_V[7] = 3.7;  // condition gone: still latched
  for (double e = t + 1.0; t < e; t += 0.01) rig.read(t);
  EXPECT_TRUE(rig.stack.faultLine());
  bms::Outputs out{};
  out.afeClearFaults = true;
  rig.stack.hostWrite(t, out, rig.truth);
  rig.read(t);
  EXPECT_FALSE(rig.stack.faultLine());
  // The FAULT wire works without the link: a silent device still asserts it.
  rig.truth.comm[1].silent = true;
  rig.truth.cell_V[7] = p.cov_V + 0.05;
  for (double e = t + p.cov_delay_s + 0.05; t < e; t += 0.01) rig.read(t);
  EXPECT_TRUE(rig.stack.faultLine());
}

TEST(Monitor, Bq76952CoulombCounterIntegratesTheCurrent) {
  // 12 A for 10 s, then -4 A for 5 s: 100 As. The device converts every 250 ms, so the
  // counter steps in 0.25 s x I; the host reads it in the frame in mA·s.
  Rig rig("bq76952", 16);
  double t = 0.0;
  for (; t < 10.0 - 1e-9; t += 0.01) {
    rig.truth.current_A = 12.0;
    rig.read(t);
  }
  for (; t < 15.0 - 1e-9; t += 0.01) {
    rig.truth.current_A = -4.0;
    rig.read(t);
  }
  rig.read(t);  // the conversion at 15 s closes the last interval
  EXPECT_NEAR(rig.stack.chargeCounter_As(0), 12.0 * 10.0 - 4.0 * 5.0, 12.0 * 0.25 + 1e-9);
  bms::DeviceReading r{};
  ASSERT_EQ(rig.parse(0, r, 1000.0f), bms::FrameResult::Ok);
  EXPECT_NEAR(r.charge_mAs * 1e-3, rig.stack.chargeCounter_As(0), 1e-3);
}

TEST(Monitor, PerChannelErrorsAreDrawnFromTheSeedWithTheirSpread) {
  // 240 channels with channel_gain_sd 1 % and channel_offset_sd 2 mV: the sample spread
  // of 240 draws lies within ±15 % of the configured one (sd of an sd estimate ≈ 4.6 %),
  // and the same seed draws the same errors.
  Scenario s = stackScenario("bq76pl536a", 240);
  s.hardware.afe.channel_gain_sd = 0.01;
  s.hardware.afe.channel_offset_sd_V = 0.002;
  const MonitorStack a(s.hardware.afe, 240, 11), b(s.hardware.afe, 240, 11), c(s.hardware.afe, 240, 12);
  double g2 = 0.0, o2 = 0.0;
  bool differs = false;
  for (int k = 0; k < 240; ++k) {
    g2 += a.channelGain(k) * a.channelGain(k);
    o2 += a.channelOffset_V(k) * a.channelOffset_V(k);
    ASSERT_EQ(a.channelGain(k), b.channelGain(k));
    differs = differs || a.channelGain(k) != c.channelGain(k);
  }
  EXPECT_NEAR(std::sqrt(g2 / 240), 0.01, 0.0015);
  EXPECT_NEAR(std::sqrt(o2 / 240), 0.002, 0.0003);
  EXPECT_TRUE(differs);
}

TEST(Monitor, StackReadoutTimeFromFrameLengthAndLink) {
  // BQ76PL536A on 1 Mbit/s SPI: a 29-byte reply (10 bit times a byte) plus 9 conversions
  // (6 cells, 2 thermistors, the module) of 6 us: 344 us per device.
  const Scenario s = stackScenario("bq76pl536a", 12);
  EXPECT_NEAR(stackReadoutTime_s(s.hardware.afe, 12), 2 * (29 * 10 / 1e6 + 9 * 6e-6), 1e-12);
  // 60 cells = 10 devices = 3.44 ms: fine at a 10 ms tick, a warning at 2 ms.
  std::string yaml = "name: slow\npack:\n  series: 60\n  cell: {capacity_Ah: 5, ocv_V: 3.7, r0_ohm: 0.01}\n"
                     "hardware:\n  afe: {model: bq76pl536a}\nbms: {tick_ms: TICK}\nload: {current_A: 1}\n"
                     "run: {duration_s: 1}\n";
  const auto withTick = [&](const char* tick) {
    std::string y = yaml;
    y.replace(y.find("TICK"), 4, tick);
    return runScenario(test::scenarioFromYaml(y));
  };
  EXPECT_LT(test::eventTime(withTick("10"), "config_warning"), 0.0);
  EXPECT_EQ(test::eventTime(withTick("2"), "config_warning", "reading the 10-device monitor stack takes 3.4 ms"), 0.0);
}

}  // namespace
}  // namespace packsim
