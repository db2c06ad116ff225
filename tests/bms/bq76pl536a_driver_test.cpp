// packsim's BQ76PL536A driver against the stack model, through the firmware contract
// (ChainTestBoard): power-up and configuration, read-out accuracy, per-device comm
// faults, CRC retries, clearing latches, balancing, and the read-out time.
#include <bms/afe/bq76pl536a_driver.hpp>
#include <bms/afe/bq76pl536a_regs.h>
#include <gtest/gtest.h>

#include <cmath>

#include "models/afe/bq76pl536a.hpp"
#include "tests/models/chain_test_board.hpp"

namespace packsim {
namespace {

constexpr double kLsb_V = 6.25 / 16383.0;
constexpr int kCells = 16;  // 6 + 6 + 4

MonitorConfig modelConfig() {
  MonitorConfig c;
  c.devices = 3;
  c.cells_per_device = 6;
  c.thermistors_per_device = 2;
  c.cell_adc.lsb = kLsb_V;
  c.cell_adc.code_max = 16383;
  return c;
}

bms::Bq536Config driverConfig() {
  bms::Bq536Config c{};
  c.bus = PSFW_BUS_MONITOR(0);
  c.deviceCount = 3;
  c.cellsPerDevice = 6;
  c.cellCount = kCells;
  c.thermistorsPerDevice = 2;
  c.cellLsb_uV = static_cast<float>(kLsb_V * 1e6);
  c.crcRetries = 3;
  c.conversionPerChannel_us = 6;
  c.protectionEnabled = true;
  c.cov_mV = 4200;
  c.covDelay_us = 500000;
  c.cuv_mV = 2800;
  c.cuvDelay_us = 300;
  c.ot_C = 60;
  c.otDelay_ms = 200;
  return c;
}

double cellTruth_V(int cell) { return 3.30 + 0.05 * cell; }

struct Rig {
  Bq76pl536aChain chain;
  test::ChainTestBoard board;
  bms::Bq536Config cfg = driverConfig();
  bms::Bq536State st{};
  bms::DeviceReading out[bms::kMaxDevices]{};
  bms::FrameResult res[bms::kMaxDevices]{};

  explicit Rig(const MonitorConfig& mc, uint64_t seed = 3) : chain(mc, kCells, seed), board(chain) {
    for (int d = 0; d < chain.deviceCount(); ++d) {
      DeviceAnalog& a = chain.analog(d);
      for (int c = 0; c < chain.cellsOf(d); ++c) a.cell_V[static_cast<size_t>(c)] = cellTruth_V(d * 6 + c);
      a.therm_C = {20.0 + d, 30.0 + d};
    }
  }
  bool init() { return bms::bq536Init(cfg, st, board.board(), board.api()); }
  void readAll() { bms::bq536ReadAll(cfg, st, board.board(), board.api(), out, res); }
};

TEST(Bq536Driver, InitAddressesAndProgramsTheProtectionBehindTheShadowKey) {
  Rig r(modelConfig());
  ASSERT_TRUE(r.init());
  EXPECT_EQ(r.st.addressed, 3);
  EXPECT_EQ(r.st.configured, 3);
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(r.chain.peek(d, BQ536_ADDRESS_CONTROL), 0x80 | (d + 1));
    // 4.20 V = 2.0 + 44·50 mV; 0.5 s = 5 × 100 ms; 2.8 V = 0.7 + 21·0.1; 300 µs = 3 × 100 µs;
    // 60 °C = 35 + 5·5 on both inputs; 200 ms = 20 × 10 ms.
    EXPECT_EQ(r.chain.peek(d, BQ536_CONFIG_COV), 44);
    EXPECT_EQ(r.chain.peek(d, BQ536_CONFIG_COVT), 0x80 | 5);
    EXPECT_EQ(r.chain.peek(d, BQ536_CONFIG_CUV), 21);
    EXPECT_EQ(r.chain.peek(d, BQ536_CONFIG_CUVT), 3);
    EXPECT_EQ(r.chain.peek(d, BQ536_CONFIG_OT), 0x55);
    EXPECT_EQ(r.chain.peek(d, BQ536_CONFIG_OTT), 20);
    EXPECT_EQ(r.chain.peek(d, BQ536_FAULT_STATUS), 0);  // POR cleared
    EXPECT_EQ(r.chain.peek(d, BQ536_ALERT_STATUS), 0);  // AR cleared
  }
  // A second init (firmware restart) re-addresses the stack the same way.
  EXPECT_TRUE(r.init());
  EXPECT_EQ(r.chain.peek(2, BQ536_ADDRESS_CONTROL), 0x83);
}

TEST(Bq536Driver, ReadOutReturnsTheTruthWithinQuantisationAndConfiguredError) {
  MonitorConfig mc = modelConfig();
  mc.cell_adc.gain_error = 0.002;
  mc.cell_adc.offset = -1.5e-3;
  mc.channel_gain_sd = 5e-4;
  mc.channel_offset_sd_V = 1e-3;
  Rig r(mc);
  ASSERT_TRUE(r.init());
  r.readAll();
  Rng unused(0);
  for (int d = 0; d < 3; ++d) {
    ASSERT_EQ(r.res[d], bms::FrameResult::Ok) << d;
    double sum_V = 0.0;
    for (int c = 0; c < r.chain.cellsOf(d); ++c) {
      const int cell = d * 6 + c;
      const double v = cellTruth_V(cell);
      sum_V += v;
      const double expect_V =
          v * (1.0 + mc.cell_adc.gain_error + r.chain.channelGain(cell)) + mc.cell_adc.offset + r.chain.channelOffset_V(cell);
      // half an LSB of the ADC plus half a mV of the driver's rounding to mV
      EXPECT_NEAR(r.out[d].cell_mV[c] * 1e-3, expect_V, kLsb_V / 2 + 0.5e-3 + 1e-9) << cell;
    }
    EXPECT_NEAR(r.out[d].stack_mV * 1e-3, sum_V, 3 * kLsb_V + 0.5e-3);
    EXPECT_EQ(r.out[d].thermCode[0], mc.thermistor.code(20.0 + d, unused));
    EXPECT_EQ(r.out[d].thermCode[1], mc.thermistor.code(30.0 + d, unused));
    EXPECT_FALSE(r.out[d].fault);
  }
  EXPECT_EQ(r.out[2].cell_mV[4], 0);  // the last device holds 4 cells
}

// The core's conversion of a thermistor input (DeviceReading::thermConverted, set by
// bms::measure) survives a read-out that brings the same code and is dropped, for that
// input alone, by one that brings another.
TEST(Bq536Driver, AChangedThermistorCodeDropsOnlyItsKeptConversion) {
  Rig r(modelConfig());
  ASSERT_TRUE(r.init());
  r.readAll();
  for (int d = 0; d < 3; ++d) r.out[d].thermConverted = 0x03;  // as measure leaves them
  r.readAll();
  for (int d = 0; d < 3; ++d) EXPECT_EQ(r.out[d].thermConverted, 0x03) << d;
  r.chain.analog(1).therm_C = {45.0, 31.0};  // device 1's first input warms
  r.readAll();
  Rng unused(0);
  EXPECT_EQ(r.out[1].thermCode[0], modelConfig().thermistor.code(45.0, unused));
  EXPECT_EQ(r.out[1].thermConverted, 0x02);
  EXPECT_EQ(r.out[1].thermCode[1], modelConfig().thermistor.code(31.0, unused));
  EXPECT_EQ(r.out[0].thermConverted, 0x03);
  EXPECT_EQ(r.out[2].thermConverted, 0x03);
}

TEST(Bq536Driver, SilentDeviceTimesOutAloneAndStuckDevicesNeverReadPlausible) {
  Rig r(modelConfig());
  ASSERT_TRUE(r.init());
  r.chain.setCommFault(1, MonitorDeviceFault{true, 0.0, -1});
  r.readAll();
  EXPECT_EQ(r.res[0], bms::FrameResult::Ok);
  EXPECT_EQ(r.res[1], bms::FrameResult::Timeout);
  EXPECT_EQ(r.res[2], bms::FrameResult::Ok);
  for (int stuck : {0x00, 0xFF}) {
    r.chain.setCommFault(1, MonitorDeviceFault{false, 0.0, stuck});
    r.readAll();
    EXPECT_TRUE(r.res[1] == bms::FrameResult::BadCrc || r.res[1] == bms::FrameResult::BadHeader) << stuck;
    EXPECT_EQ(r.res[0], bms::FrameResult::Ok);
    EXPECT_EQ(r.res[2], bms::FrameResult::Ok);
  }
  // A broken link above device 0 loses the two devices above it.
  r.chain.setCommFault(1, MonitorDeviceFault{});
  r.chain.setBrokenLinkAbove(0);
  r.readAll();
  EXPECT_EQ(r.res[0], bms::FrameResult::Ok);
  EXPECT_EQ(r.res[1], bms::FrameResult::Timeout);
  EXPECT_EQ(r.res[2], bms::FrameResult::Timeout);
}

TEST(Bq536Driver, CrcErrorsAreRetried) {
  Rig r(modelConfig());
  ASSERT_TRUE(r.init());
  r.chain.setCommFault(0, MonitorDeviceFault{false, 0.2, -1});
  int ok = 0;
  for (int k = 0; k < 20; ++k) {
    r.board.wait(0.1);
    r.readAll();
    ok += r.res[0] == bms::FrameResult::Ok;
  }
  EXPECT_EQ(ok, 20);
  EXPECT_GT(r.st.crcRetries, 0u);
  // Without retries some read-outs fail their CRC.
  r.cfg.crcRetries = 0;
  int bad = 0;
  for (int k = 0; k < 20; ++k) {
    r.board.wait(0.1);
    r.readAll();
    bad += r.res[0] == bms::FrameResult::BadCrc;
  }
  EXPECT_GT(bad, 0);
}

TEST(Bq536Driver, ClearingFaultsWorksOnlyOnceTheConditionIsGone) {
  Rig r(modelConfig());
  ASSERT_TRUE(r.init());
  r.chain.analog(0).cell_V[3] = 4.25;  // over the 4.20 V the driver programmed
  r.board.wait(0.1);
  r.board.wait(0.5);  // the programmed 0.5 s
  EXPECT_TRUE(r.chain.faultLine());
  r.readAll();
  ASSERT_EQ(r.res[0], bms::FrameResult::Ok);
  EXPECT_TRUE(r.out[0].fault);
  EXPECT_NE(r.out[0].safetyA & BQ536_FS_COV, 0);
  EXPECT_FALSE(r.out[1].fault);
  bms::bq536ClearFaults(r.cfg, r.board.board(), r.board.api());
  r.readAll();
  EXPECT_TRUE(r.out[0].fault);  // still over
  r.chain.analog(0).cell_V[3] = 4.1;
  r.board.wait(0.1);
  bms::bq536ClearFaults(r.cfg, r.board.board(), r.board.api());
  r.readAll();
  EXPECT_FALSE(r.out[0].fault);
  EXPECT_FALSE(r.chain.faultLine());
}

TEST(Bq536Driver, BalancingReachesTheDevicesAndExpires) {
  Rig r(modelConfig());
  ASSERT_TRUE(r.init());
  uint32_t mask[bms::kBalanceWords] = {};
  mask[0] = (1u << 0) | (1u << 7) | (1u << 15);  // device 0 cell 0, device 1 cell 1, device 2 cell 3
  bms::bq536SetBalance(r.cfg, r.board.board(), r.board.api(), mask, 5);
  EXPECT_TRUE(r.chain.balancing(0, 0));
  EXPECT_TRUE(r.chain.balancing(1, 1));
  EXPECT_TRUE(r.chain.balancing(2, 3));
  EXPECT_FALSE(r.chain.balancing(1, 0));
  r.board.wait(4.9);
  EXPECT_TRUE(r.chain.balancing(1, 1));
  r.board.wait(0.2);
  EXPECT_FALSE(r.chain.balancing(0, 0));
  EXPECT_FALSE(r.chain.balancing(1, 1));
  EXPECT_FALSE(r.chain.balancing(2, 3));
  // 90 s: whole minutes beyond 63 s, rounded up -> 2 min on the device.
  bms::bq536SetBalance(r.cfg, r.board.board(), r.board.api(), mask, 90);
  EXPECT_EQ(r.chain.peek(1, BQ536_CB_TIME), BQ536_CBT_MINUTES | 2);
}

TEST(Bq536Driver, ReadOutTakesTheTimeTheLinkAllows) {
  MonitorConfig mc = modelConfig();
  mc.baud = 1e6;
  Rig r(mc);
  ASSERT_TRUE(r.init());
  const double t0 = r.board.t_s;
  r.readAll();
  // convert (4 bytes), the conversion wait (9 channels × 6 µs), then per device the
  // results (3 + 19 + 1 bytes) and flags (3 + 4 + 1 bytes), 8 bits a byte at 1 MHz.
  const double expect_s = 4 * 8e-6 + 9 * 6e-6 + 3 * (23 + 8) * 8e-6;
  EXPECT_NEAR(r.board.t_s - t0, expect_s, 1e-12);
}

TEST(Bq536Driver, ResultsCountOnlyOnceDataReadySays) {
  MonitorConfig mc = modelConfig();
  mc.conversion_s_per_channel = 1e-3;  // a slow ADC: 9 channels take 9 ms
  Rig slow(mc);
  ASSERT_TRUE(slow.init());
  slow.cfg.conversionPerChannel_us = 1000;  // the driver waits the real conversion time
  const double t0 = slow.board.t_s;
  slow.readAll();
  for (int d = 0; d < 3; ++d) EXPECT_EQ(slow.res[d], bms::FrameResult::Ok) << d;
  EXPECT_GE(slow.board.t_s - t0, 9e-3);
  // A driver that waits too little reads old results with DRDY clear: no reading
  // (a fast link, so the whole read-out ends before the 9 ms conversion).
  mc.baud = 1e7;
  Rig hasty(mc);
  ASSERT_TRUE(hasty.init());
  hasty.cfg.conversionPerChannel_us = 100;
  hasty.readAll();
  for (int d = 0; d < 3; ++d) EXPECT_EQ(hasty.res[d], bms::FrameResult::Timeout) << d;
}

}  // namespace
}  // namespace packsim
