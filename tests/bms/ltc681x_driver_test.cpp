// packsim's LTC6811-1 / LTC6813-1 driver against the daisy-chain model, through the
// firmware contract (ChainTestBoard): configuration, read-out accuracy within the 100 uV
// LSB, GPIO thermistors, the watchdog's sleep and the driver's recovery, PEC errors per
// device, a broken link, open-wire detection, balancing with the discharge timer, MUTE.
#include <bms/afe/ltc681x_driver.hpp>
#include <bms/afe/ltc681x_regs.h>
#include <gtest/gtest.h>

#include <cmath>

#include "models/afe/ltc681x.hpp"
#include "tests/models/chain_test_board.hpp"

namespace packsim {
namespace {

constexpr double kLsb_V = 100e-6;

Ltc681xConfig modelConfig(Ltc681xPart part, int devices) {
  Ltc681xConfig c;
  c.part = part;
  c.devices = devices;
  c.cells_per_device = part == Ltc681xPart::Ltc6813 ? 18 : 12;
  c.thermistors_per_device = 2;
  return c;
}

bms::LtcConfig driverConfig(const Ltc681xConfig& m, int cells) {
  bms::LtcConfig c{};
  c.bus = PSFW_BUS_MONITOR(0);
  c.part = m.part == Ltc681xPart::Ltc6813 ? bms::LtcPart::Ltc6813 : bms::LtcPart::Ltc6811;
  c.deviceCount = static_cast<uint8_t>(m.devices);
  c.cellsPerDevice = static_cast<uint8_t>(m.cells_per_device);
  c.cellCount = static_cast<uint16_t>(cells);
  c.thermistorsPerDevice = static_cast<uint8_t>(m.thermistors_per_device);
  c.adcMode = LTC681X_MD_NORMAL;
  c.adcopt = false;
  c.dischargePermitted = false;
  c.readStatus = true;
  c.ov_mV = 4200;
  c.uv_mV = 2800;
  c.readRetries = 3;
  c.period_us = 100000;  // a 100 ms read-out: a recovery and a read-out fit in one call
  return c;
}

double cellTruth_V(int cell) { return 3.30 + 0.013 * cell; }

struct Rig {
  Ltc681xChain chain;
  test::ChainTestBoard board;
  bms::LtcConfig cfg;
  bms::LtcState st{};
  bms::LtcReading out[bms::kMaxDevices]{};
  bms::FrameResult res[bms::kMaxDevices]{};

  Rig(const Ltc681xConfig& mc, int cells, uint64_t seed = 3)
      : chain(mc, cells, seed), board(chain), cfg(driverConfig(mc, cells)) {
    for (int d = 0; d < chain.deviceCount(); ++d) {
      DeviceAnalog& a = chain.analog(d);
      for (int c = 0; c < chain.cellsOf(d); ++c) a.cell_V[static_cast<size_t>(c)] = cellTruth_V(d * mc.cells_per_device + c);
      a.therm_C = {20.0 + d, 35.0 + d};
      a.die_C = 40.0;
    }
  }
  bool init() { return bms::ltcInit(cfg, st, board.board(), board.api()); }
  void readAll() { bms::ltcReadAll(cfg, st, board.board(), board.api(), out, res); }
};

TEST(LtcDriver, InitWakesAndConfiguresEveryDevice) {
  Rig r(modelConfig(Ltc681xPart::Ltc6811, 3), 36);
  ASSERT_TRUE(r.init());
  EXPECT_EQ(r.st.configured, 3);
  for (int d = 0; d < 3; ++d) {
    EXPECT_FALSE(r.chain.asleep(d));
    // REFON on, GPIO pull-downs off; 4.2 V = VOV 2625 x 1.6 mV; 2.8 V = (VUV 1749 + 1) x 1.6 mV.
    EXPECT_EQ(r.chain.cfga(d, 0), 0xFC);
    EXPECT_EQ(r.chain.cfga(d, 1), 1749 & 0xFF);
    EXPECT_EQ(r.chain.cfga(d, 2), ((2625 & 0xF) << 4) | (1749 >> 8));
    EXPECT_EQ(r.chain.cfga(d, 3), 2625 >> 4);
  }
  EXPECT_EQ(r.st.sleepWakeups, 1u);
  // A 6813 chain: CFGRB as well.
  Rig s(modelConfig(Ltc681xPart::Ltc6813, 2), 36);
  ASSERT_TRUE(s.init());
  EXPECT_EQ(s.chain.cfgb(1, 0), LTC6813_CFGRB0_DEFAULT);
}

TEST(LtcDriver, CellsReadTheTruthWithinOneLsbAndTheConfiguredErrors) {
  for (Ltc681xPart part : {Ltc681xPart::Ltc6811, Ltc681xPart::Ltc6813}) {
    Ltc681xConfig mc = modelConfig(part, 2);
    mc.cell_adc.gain_error = 0.001;
    mc.cell_adc.offset = -0.4e-3;
    mc.channel_gain_sd = 3e-4;
    mc.channel_offset_sd_V = 0.5e-3;
    const int cells = 2 * mc.cells_per_device - 1;  // the last device one short
    Rig r(mc, cells);
    ASSERT_TRUE(r.init());
    r.readAll();
    for (int d = 0; d < 2; ++d) {
      ASSERT_EQ(r.res[d], bms::FrameResult::Ok) << d;
      for (int c = 0; c < r.chain.cellsOf(d); ++c) {
        const int cell = d * mc.cells_per_device + c;
        const double expect_V = cellTruth_V(cell) * (1.0 + mc.cell_adc.gain_error + r.chain.channelGain(cell)) +
                                mc.cell_adc.offset + r.chain.channelOffset_V(cell);
        EXPECT_NEAR(r.out[d].cell[c] * kLsb_V, expect_V, kLsb_V / 2 + 1e-9) << cell;
      }
      // GPIO1/2: the NTC divider from the 3 V second reference, beta model.
      for (int k = 0; k < 2; ++k) {
        const double t_K = 273.15 + (k == 0 ? 20.0 : 35.0) + d;
        const double r_ntc = 10000.0 * std::exp(3435.0 * (1.0 / t_K - 1.0 / 298.15));
        EXPECT_NEAR(r.out[d].gpio[k] * kLsb_V, 3.0 * r_ntc / (10000.0 + r_ntc), kLsb_V / 2 + 1e-9) << k;
      }
      EXPECT_EQ(r.out[d].ref, 30000);
      // ITMP -> die temperature within one code (1/76 degC)
      EXPECT_NEAR(r.out[d].itmp * 1e-4 / 7.6e-3 - 276.0, 40.0, 0.02);
      EXPECT_EQ(r.out[d].ov, 0u);
      EXPECT_EQ(r.out[d].uv & ((1u << r.chain.cellsOf(d)) - 1u), 0u);
    }
    EXPECT_EQ(r.out[1].cell[mc.cells_per_device - 1], 0);  // the unused top input reads 0 V
    EXPECT_NE(r.out[1].uv >> (mc.cells_per_device - 1), 0u);  // ... and is under VUV
  }
}

TEST(LtcDriver, CoreReadingForTheTwelveCellPart) {
  Ltc681xConfig mc = modelConfig(Ltc681xPart::Ltc6811, 1);
  Rig r(mc, 12);
  ASSERT_TRUE(r.init());
  r.chain.analog(0).cell_V[3] = 4.3;  // over the 4.2 V VOV
  r.readAll();
  ASSERT_EQ(r.res[0], bms::FrameResult::Ok);
  bms::DeviceReading dr{};
  ASSERT_TRUE(bms::ltcToDeviceReading(r.cfg, 0, r.out[0], dr));
  for (int c = 0; c < 12; ++c)
    EXPECT_NEAR(dr.cell_mV[c], (c == 3 ? 4.3 : cellTruth_V(c)) * 1e3, 0.5 + 0.05 + 1e-6) << c;
  EXPECT_TRUE(dr.alert);
  EXPECT_EQ(r.out[0].ov, 1u << 3);
  EXPECT_NEAR(dr.die_dC, 400, 1);
}

// Every used GPIO is read, whichever auxiliary group holds it (AUXA GPIO1-3, AUXB
// GPIO4-5, AUXC GPIO6-8, AUXD GPIO9): for each count of thermistors on an LTC6813, each
// GPIO in use reads its NTC's divider (was: 6 thermistors left GPIO6 unread).
TEST(LtcDriver, EveryThermistorCountReadsEachOfItsGpios) {
  for (int n = 1; n <= 9; ++n) {
    Ltc681xConfig mc = modelConfig(Ltc681xPart::Ltc6813, 1);
    mc.thermistors_per_device = n;
    Rig r(mc, 18);
    DeviceAnalog& a = r.chain.analog(0);
    a.therm_C.assign(static_cast<size_t>(n), 0.0);
    a.therm_fault.assign(static_cast<size_t>(n), ThermistorFault::None);
    for (int k = 0; k < n; ++k) a.therm_C[static_cast<size_t>(k)] = 15.0 + 3.0 * k;
    ASSERT_TRUE(r.init()) << n;
    r.readAll();
    ASSERT_EQ(r.res[0], bms::FrameResult::Ok) << n;
    for (int k = 0; k < n; ++k) {
      const double t_K = 273.15 + 15.0 + 3.0 * k;
      const double r_ntc = 10000.0 * std::exp(3435.0 * (1.0 / t_K - 1.0 / 298.15));
      EXPECT_NEAR(r.out[0].gpio[k] * kLsb_V, 3.0 * r_ntc / (10000.0 + r_ntc), kLsb_V / 2 + 1e-9) << n << " GPIO" << k + 1;
    }
  }
}

TEST(LtcDriver, CoreReadingHoldsAllEighteenCellsOfTheLtc6813) {
  Rig s(modelConfig(Ltc681xPart::Ltc6813, 1), 18);
  ASSERT_TRUE(s.init());
  s.chain.analog(0).cell_V[17] = 3.123;
  s.readAll();
  ASSERT_EQ(s.res[0], bms::FrameResult::Ok);
  bms::DeviceReading dr{};
  ASSERT_TRUE(bms::ltcToDeviceReading(s.cfg, 0, s.out[0], dr));
  for (int c = 0; c < 18; ++c) EXPECT_NEAR(dr.cell_mV[c], (c == 17 ? 3.123 : cellTruth_V(c)) * 1e3, 0.5 + 0.05 + 1e-6) << c;
}

TEST(LtcDriver, WatchdogSleepResetsTheConfigurationAndTheDriverRestoresIt) {
  Rig r(modelConfig(Ltc681xPart::Ltc6813, 3), 54);
  ASSERT_TRUE(r.init());
  r.board.wait(2.5);  // silence beyond the watchdog
  for (int d = 0; d < 3; ++d) {
    EXPECT_TRUE(r.chain.asleep(d));
    EXPECT_EQ(r.chain.cfga(d, 0), LTC681X_CFGR0_DEFAULT);
    EXPECT_EQ(r.chain.cfga(d, 3), 0);
  }
  r.readAll();
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(r.res[d], bms::FrameResult::Ok) << d;
    EXPECT_EQ(r.chain.cfga(d, 3), 2625 >> 4);
  }
  EXPECT_EQ(r.st.sleepWakeups, 2u);
  // Reading every 0.5 s keeps the cores awake: only the ports idle in between.
  for (int k = 0; k < 6; ++k) {
    r.board.wait(0.5);
    r.readAll();
  }
  EXPECT_EQ(r.st.sleepWakeups, 2u);
  EXPECT_GE(r.st.idleWakeups, 6u);
}

TEST(LtcDriver, BrokenLinkSilencesTheDevicesBeyondAndCountsTheirPecErrors) {
  Rig r(modelConfig(Ltc681xPart::Ltc6813, 4), 72);
  ASSERT_TRUE(r.init());
  r.readAll();  // a good read-out first: the recovery after the repair reads within its period
  ASSERT_GT(r.st.readout_us, 0u);
  r.chain.setBrokenLinkAbove(1);
  r.readAll();
  EXPECT_EQ(r.res[0], bms::FrameResult::Ok);
  EXPECT_EQ(r.res[1], bms::FrameResult::Ok);
  EXPECT_EQ(r.res[2], bms::FrameResult::Timeout);
  EXPECT_EQ(r.res[3], bms::FrameResult::Timeout);
  EXPECT_EQ(r.st.pecErrors[0], 0u);
  EXPECT_EQ(r.st.pecErrors[1], 0u);
  EXPECT_GT(r.st.pecErrors[2], 0u);
  EXPECT_EQ(r.st.pecErrors[2], r.st.pecErrors[3]);
  // Repaired: everyone answers again.
  r.chain.setBrokenLinkAbove(-1);
  r.readAll();
  for (int d = 0; d < 4; ++d) EXPECT_EQ(r.res[d], bms::FrameResult::Ok) << d;
}

// The call after a failed read-out recovers the chain (wake, configuration, the
// references' power-up). Where that and the last good read-out's length fit the period
// it reads as well; where they do not (10 ms, with a 7.5 ms read-out), it reads nothing
// -- every device NotRead, in less than the period -- and the next call reads.
TEST(LtcDriver, ARecoveryReadsInTheSameCallOnlyWhereThePeriodHoldsBoth) {
  for (const uint32_t period_us : {100000u, 10000u}) {
    Rig r(modelConfig(Ltc681xPart::Ltc6811, 2), 24);
    r.cfg.period_us = period_us;
    ASSERT_TRUE(r.init());
    r.readAll();  // a good read-out: its length is known
    ASSERT_EQ(r.res[1], bms::FrameResult::Ok);
    ASSERT_GT(r.st.readout_us, 0u);
    r.chain.setBrokenLinkAbove(0);
    r.board.wait(0.1);
    r.readAll();
    ASSERT_EQ(r.res[1], bms::FrameResult::Timeout);
    r.chain.setBrokenLinkAbove(-1);
    r.board.wait(0.1);
    const double start_s = r.board.t_s;
    r.readAll();
    if (period_us == 100000u) {
      for (int d = 0; d < 2; ++d) EXPECT_EQ(r.res[d], bms::FrameResult::Ok) << d;
    } else {
      for (int d = 0; d < 2; ++d) EXPECT_EQ(r.res[d], bms::FrameResult::NotRead) << d;
      EXPECT_LT(r.board.t_s - start_s, 0.010) << "the recovery alone fits the period";
      r.board.wait(0.01);
      r.readAll();
      for (int d = 0; d < 2; ++d) EXPECT_EQ(r.res[d], bms::FrameResult::Ok) << d;
    }
  }
}

TEST(LtcDriver, PecErrorsAreCountedPerDeviceAndRetried) {
  Rig r(modelConfig(Ltc681xPart::Ltc6811, 3), 36);
  ASSERT_TRUE(r.init());
  r.chain.setCommFault(1, MonitorDeviceFault{false, 0.1, -1});
  int ok = 0;
  for (int k = 0; k < 20; ++k) {
    r.board.wait(0.1);
    r.readAll();
    ok += r.res[1] == bms::FrameResult::Ok;
    EXPECT_EQ(r.res[0], bms::FrameResult::Ok);
    EXPECT_EQ(r.res[2], bms::FrameResult::Ok);
  }
  EXPECT_EQ(ok, 20);
  EXPECT_GT(r.st.pecErrors[1], 0u);
  EXPECT_EQ(r.st.pecErrors[0], 0u);
  EXPECT_EQ(r.st.pecErrors[2], 0u);
  // Without retries some read-outs of device 1 fail their PEC.
  r.cfg.readRetries = 0;
  int bad = 0;
  for (int k = 0; k < 20; ++k) {
    r.board.wait(0.1);
    r.readAll();
    bad += r.res[1] == bms::FrameResult::BadCrc;
  }
  EXPECT_GT(bad, 0);
}

TEST(LtcDriver, OpenWireCheckFlagsTheOpenPin) {
  for (int pin : {-1, 0, 5, 11, 12}) {
    Rig r(modelConfig(Ltc681xPart::Ltc6811, 2), 24);
    ASSERT_TRUE(r.init());
    if (pin >= 0) r.chain.setOpenWire(1, pin, true);
    bms::LtcReading up[bms::kMaxDevices]{}, down[bms::kMaxDevices]{};
    uint32_t open[bms::kMaxDevices] = {};
    bms::ltcOpenWireCheck(r.cfg, r.st, r.board.board(), r.board.api(), up, down, open, r.res);
    ASSERT_EQ(r.res[0], bms::FrameResult::Ok);
    ASSERT_EQ(r.res[1], bms::FrameResult::Ok);
    EXPECT_EQ(open[0], 0u) << pin;
    EXPECT_EQ(open[1], pin < 0 ? 0u : 1u << pin) << pin;
  }
}

TEST(LtcDriver, BalancingReachesTheCellsAndTheDischargeTimerEndsIt) {
  Rig r(modelConfig(Ltc681xPart::Ltc6813, 2), 36);
  ASSERT_TRUE(r.init());
  uint32_t mask[bms::kBalanceWords] = {};
  mask[0] = (1u << 0) | (1u << 13) | (1u << 17) | (1u << (18 + 2) );  // dev 0: 1, 14, 18; dev 1: 3
  mask[1] = 1u << (35 - 32);                                          // dev 1: cell 18
  bms::ltcSetBalance(r.cfg, r.st, r.board.board(), r.board.api(), mask, 60);
  EXPECT_TRUE(r.chain.balancing(0, 0));
  EXPECT_TRUE(r.chain.balancing(0, 13));
  EXPECT_TRUE(r.chain.balancing(0, 17));
  EXPECT_TRUE(r.chain.balancing(1, 2));
  EXPECT_TRUE(r.chain.balancing(1, 17));
  EXPECT_FALSE(r.chain.balancing(0, 1));
  EXPECT_EQ(r.chain.cfga(0, 5) >> 4, 2);  // DCTO 2: 1 min, the smallest at least 60 s
  // MUTE pauses them all, UNMUTE brings them back.
  bms::ltcSetMute(r.cfg, r.st, r.board.board(), r.board.api(), true);
  EXPECT_FALSE(r.chain.balancing(0, 0));
  bms::ltcSetMute(r.cfg, r.st, r.board.board(), r.board.api(), false);
  EXPECT_TRUE(r.chain.balancing(0, 0));
  // The host goes silent: the cores sleep, the timer keeps balancing for its minute.
  r.board.wait(59.5);
  EXPECT_TRUE(r.chain.asleep(0));
  EXPECT_TRUE(r.chain.balancing(0, 13));
  r.board.wait(0.6);
  for (int d = 0; d < 2; ++d)
    for (int c = 0; c < 18; ++c) EXPECT_FALSE(r.chain.balancing(d, c)) << d << " " << c;
}

TEST(LtcDriver, ConversionWaitIsTheTablesTime) {
  Rig r(modelConfig(Ltc681xPart::Ltc6811, 1), 12);
  r.cfg.readStatus = false;
  r.cfg.thermistorsPerDevice = 0;
  ASSERT_TRUE(r.init());
  for (uint8_t md : {LTC681X_MD_FAST, LTC681X_MD_NORMAL, LTC681X_MD_FILTERED}) {
    r.cfg.adcMode = md;
    const double t0 = r.board.t_s;
    r.readAll();
    ASSERT_EQ(r.res[0], bms::FrameResult::Ok);
    const double waited = bms::ltcConversionTime_us(r.cfg, LTC681X_CONV_CELLS) * 1e-6;
    EXPECT_GE(r.board.t_s - t0, waited);
    EXPECT_LT(r.board.t_s - t0, waited + 1e-3);  // plus the frames (and a wake-up)
  }
}


TEST(LtcDriver, AMinuteOfReadOutsWithBalancingNeverLosesTheChain) {
  // A core's rhythm: read every 250 ms, rewrite the balancing every 10 s with a 1 min
  // timer. The chain never sleeps, the switches never drop, no PEC error appears.
  Rig r(modelConfig(Ltc681xPart::Ltc6813, 3), 54);
  ASSERT_TRUE(r.init());
  uint32_t mask[bms::kBalanceWords] = {};
  mask[0] = 1u << 5;
  mask[1] = 1u << (40 - 32);  // device 2, cell 5
  for (int k = 0; k < 240; ++k) {
    if (k % 40 == 0) bms::ltcSetBalance(r.cfg, r.st, r.board.board(), r.board.api(), mask, 60);
    r.readAll();
    for (int d = 0; d < 3; ++d) ASSERT_EQ(r.res[d], bms::FrameResult::Ok) << k << " " << d;
    ASSERT_TRUE(r.chain.balancing(0, 5)) << k;
    ASSERT_TRUE(r.chain.balancing(2, 4)) << k;
    r.board.wait(0.25);
  }
  EXPECT_EQ(r.st.sleepWakeups, 1u);  // the one at init
  EXPECT_GE(r.st.idleWakeups, 239u);
  for (int d = 0; d < 3; ++d) EXPECT_EQ(r.st.pecErrors[d], 0u);
  EXPECT_NEAR(r.out[2].cell[4] * kLsb_V, cellTruth_V(40), kLsb_V / 2 + 1e-9);
}


TEST(LtcDriver, TheLtc6813sUpperCellFlagsAreReadWithoutThermistorsToo) {
  Ltc681xConfig mc = modelConfig(Ltc681xPart::Ltc6813, 1);
  mc.thermistors_per_device = 0;
  Rig r(mc, 18);
  r.cfg.readStatus = false;
  ASSERT_TRUE(r.init());
  r.chain.analog(0).cell_V[16] = 4.35;  // cell 17 over the 4.2 V VOV
  r.chain.analog(0).cell_V[2] = 2.5;    // cell 3 under the 2.8 V VUV
  r.readAll();
  ASSERT_EQ(r.res[0], bms::FrameResult::Ok);
  EXPECT_EQ(r.out[0].ov, 1u << 16);
  EXPECT_EQ(r.out[0].uv, 1u << 2);
}

}  // namespace
}  // namespace packsim
