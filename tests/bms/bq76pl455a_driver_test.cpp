// packsim's BQ76PL455A driver against the chain model, through the firmware contract
// (ChainTestBoard): addressing and configuration, a full read-out against the truth,
// per-device outcomes under comm faults, CRC retries, fault clearing, balancing that
// expires on the device, and the read-out time the UART allows.
#include <gtest/gtest.h>

#include <bms/afe/bq76pl455a_driver.hpp>

#include <cmath>

#include "models/afe/bq76pl455a.hpp"
#include "tests/models/chain_test_board.hpp"

namespace packsim {
namespace {

MonitorConfig chainConfig(int devices, int cells) {
  MonitorConfig c;
  c.model = "bq76pl455a";
  c.devices = devices;
  c.cells_per_device = cells;
  c.thermistors_per_device = 2;
  c.cell_adc.lsb = 5.0 / 65535.0;
  c.cell_adc.code_max = 65535;
  c.baud = 250000.0;
  c.conversion_s_per_channel = 100e-6;
  c.secondary = SecondaryProtection{true, 4.30, 1.0, 2.80, 1.0, 65.0, 1.0};
  return c;
}

bms::Pl455Config driverConfig(const MonitorConfig& m, int cellCount) {
  bms::Pl455Config c{};
  c.bus = PSFW_BUS_MONITOR(0);
  c.deviceCount = static_cast<uint8_t>(m.devices);
  c.cellsPerDevice = static_cast<uint8_t>(m.cells_per_device);
  c.cellCount = static_cast<uint16_t>(cellCount);
  c.thermistorsPerDevice = 2;
  c.cellLsb_uV = 5.0e6f / 65535.0f;  // the datasheet's
  c.oversamplingLog2 = 0;
  c.comparators = true;
  c.compUv_mV = 2800;
  c.compOv_mV = 4300;
  c.cellUv_mV = 2800;
  c.cellOv_mV = 4300;
  // The NTC's code at 65 degC, as the firmware's thermistor table gives it.
  Rng none(1);
  c.auxHotCode = static_cast<uint16_t>(m.thermistor.code(65.0, none));
  c.crcRetries = 3;
  return c;
}

struct Rig {
  Rig(int devices, int cells, int cellCount, uint64_t seed = 3, double noise_V = 0.0)
      : mcfg(withNoise(chainConfig(devices, cells), noise_V)),
        chain(mcfg, cellCount, seed),
        board(chain),
        cfg(driverConfig(mcfg, cellCount)) {
    for (int d = 0; d < devices; ++d) {
      DeviceAnalog& a = chain.analog(d);
      for (size_t c = 0; c < a.cell_V.size(); ++c) a.cell_V[c] = truth(d, static_cast<int>(c));
      a.therm_C = {30.0 + d, 35.0 + d};
      a.die_C = 31.5;
    }
  }
  static MonitorConfig withNoise(MonitorConfig c, double n) {
    c.cell_adc.noise_rms = n;
    return c;
  }
  static double truth(int d, int c) { return 3.2 + 0.013 * c + 0.05 * d; }
  uint8_t init() { return bms::pl455Init(cfg, state, board.board(), board.api()); }
  void readAll() { bms::pl455ReadAll(cfg, state, board.board(), board.api(), reading, result); }

  MonitorConfig mcfg;
  Bq76pl455aChain chain;
  test::ChainTestBoard board;
  bms::Pl455Config cfg;
  bms::Pl455State state{};
  bms::DeviceReading reading[bms::kMaxDevices]{};
  bms::FrameResult result[bms::kMaxDevices]{};
};

TEST(Bq76pl455aDriver, FullReadOutReturnsTheTruthWithinQuantisation) {
  Rig r(3, 16, 40);  // the top device holds 8 cells
  EXPECT_EQ(r.init(), 3);
  r.readAll();
  const Thermistor th;
  Rng none(1);
  for (int d = 0; d < 3; ++d) {
    ASSERT_EQ(r.result[d], bms::FrameResult::Ok) << d;
    const int n = d < 2 ? 16 : 8;
    double module_V = 0.0;
    for (int c = 0; c < 16; ++c) {
      if (c >= n) {
        EXPECT_EQ(r.reading[d].cell_mV[c], 0);
        continue;
      }
      // 76 uV code + rounding to mV
      EXPECT_NEAR(r.reading[d].cell_mV[c], Rig::truth(d, c) * 1e3, 0.5 + 0.08) << d << " " << c;
      module_V += Rig::truth(d, c);
    }
    EXPECT_NEAR(r.reading[d].stack_mV, module_V * 1e3, 1.6);  // 1.5 mV code
    EXPECT_EQ(r.reading[d].thermCode[0], th.code(30.0 + d, none));
    EXPECT_EQ(r.reading[d].thermCode[1], th.code(35.0 + d, none));
    EXPECT_EQ(r.reading[d].die_dC, 315);
    EXPECT_FALSE(r.reading[d].fault);
    EXPECT_FALSE(r.reading[d].alert);
  }
}

// The read-out's request frames come from a table init builds for the part's 16
// addresses; a longer chain's devices beyond it get theirs built at each read-out, and
// every device reads the same either way (twice: the table is reused).
TEST(Bq76pl455aDriver, ChainLongerThanTheFrameTableReadsEveryDevice) {
  Rig r(18, 2, 36);
  ASSERT_EQ(r.init(), 18);
  for (int pass = 0; pass < 2; ++pass) {
    r.readAll();
    for (int d = 0; d < 18; ++d) {
      ASSERT_EQ(r.result[d], bms::FrameResult::Ok) << d;
      for (int c = 0; c < 2; ++c) EXPECT_NEAR(r.reading[d].cell_mV[c], Rig::truth(d, c) * 1e3, 0.5 + 0.08) << d << " " << c;
    }
  }
}

TEST(Bq76pl455aDriver, NoisyReadOutStaysWithinTheConfiguredError) {
  Rig r(2, 16, 32, 9, 0.5e-3);
  r.init();
  for (int k = 0; k < 20; ++k) {
    r.readAll();
    for (int d = 0; d < 2; ++d) {
      ASSERT_EQ(r.result[d], bms::FrameResult::Ok);
      for (int c = 0; c < 16; ++c)  // 5 sigma of 0.5 mV noise + quantisation
        EXPECT_NEAR(r.reading[d].cell_mV[c], Rig::truth(d, c) * 1e3, 2.5 + 0.6);
    }
  }
}

TEST(Bq76pl455aDriver, SilentDeviceTimesOutAloneAndStuckLinesNeverParse) {
  Rig r(3, 16, 48);
  ASSERT_EQ(r.init(), 3);
  r.chain.setCommFault(1, MonitorDeviceFault{true, 0.0, -1});
  r.readAll();
  EXPECT_EQ(r.result[0], bms::FrameResult::Ok);
  EXPECT_EQ(r.result[1], bms::FrameResult::Timeout);
  EXPECT_EQ(r.result[2], bms::FrameResult::Ok);
  for (int stuck : {0xFF, 0x00}) {
    r.chain.setCommFault(1, MonitorDeviceFault{false, 0.0, stuck});
    r.readAll();
    EXPECT_TRUE(r.result[1] == bms::FrameResult::BadHeader || r.result[1] == bms::FrameResult::BadCrc) << stuck;
    EXPECT_EQ(r.result[0], bms::FrameResult::Ok);
  }
  r.chain.setCommFault(1, MonitorDeviceFault{});
  r.chain.setBrokenLinkAbove(0);
  r.readAll();
  EXPECT_EQ(r.result[0], bms::FrameResult::Ok);
  EXPECT_EQ(r.result[1], bms::FrameResult::Timeout);
  EXPECT_EQ(r.result[2], bms::FrameResult::Timeout);
}

TEST(Bq76pl455aDriver, CrcErrorsAreRetriedABoundedNumberOfTimes) {
  Rig r(2, 16, 32);
  r.init();
  r.chain.setCommFault(0, MonitorDeviceFault{false, 0.3, -1});
  int ok = 0;
  for (int k = 0; k < 30; ++k) {
    r.readAll();
    ok += r.result[0] == bms::FrameResult::Ok;
    if (r.result[0] == bms::FrameResult::Ok)
      EXPECT_NEAR(r.reading[0].cell_mV[5], Rig::truth(0, 5) * 1e3, 0.6);  // retried, not a corrupted value
  }
  EXPECT_GT(r.state.crcRetriesUsed, 0u);
  EXPECT_GE(ok, 28);  // 4 attempts at 30 %: < 1 % of read-outs still fail
  r.chain.setCommFault(0, MonitorDeviceFault{false, 1.0, -1});
  const uint32_t before = r.state.crcRetriesUsed;
  r.readAll();
  EXPECT_EQ(r.result[0], bms::FrameResult::BadCrc);
  EXPECT_EQ(r.state.crcRetriesUsed - before, r.cfg.crcRetries);
}

TEST(Bq76pl455aDriver, ComparatorFaultIsReportedAndClearedByTheDriver) {
  Rig r(2, 16, 32);
  r.init();
  r.readAll();
  EXPECT_FALSE(r.reading[1].fault);
  r.chain.analog(1).cell_V[7] = 4.35;
  r.board.wait(0.0);
  r.board.wait(1.1);
  EXPECT_TRUE(r.chain.faultLine());
  r.readAll();
  EXPECT_TRUE(r.reading[1].fault);
  EXPECT_TRUE(r.reading[1].alert);  // the ADC sees it over CELL_OV too
  EXPECT_FALSE(r.reading[0].fault);
  ASSERT_TRUE(bms::pl455ClearFaults(r.cfg, r.board.board(), r.board.api()));
  r.readAll();
  EXPECT_TRUE(r.reading[1].fault);  // still over: the latch holds
  r.chain.analog(1).cell_V[7] = 4.1;
  r.board.wait(0.01);
  bms::pl455ClearFaults(r.cfg, r.board.board(), r.board.api());
  EXPECT_FALSE(r.chain.faultLine());
  r.readAll();
  EXPECT_FALSE(r.reading[1].fault);
  EXPECT_FALSE(r.reading[1].alert);
}

TEST(Bq76pl455aDriver, DriverThresholdsReachTheDevice) {
  Rig r(1, 16, 16);
  r.cfg.compOv_mV = 4100;  // the firmware's own, below the EEPROM's 4.30 V
  r.init();
  r.chain.analog(0).cell_V[2] = 4.15;
  r.board.wait(0.0);
  r.board.wait(1.01);
  EXPECT_TRUE(r.chain.faultLine());
  // An AUX threshold at 50 degC: an input at 55 degC trips it (the EEPROM's is 65).
  Rig t(1, 16, 16);
  Rng none(1);
  t.cfg.auxHotCode = static_cast<uint16_t>(t.mcfg.thermistor.code(50.0, none));
  t.init();
  t.chain.analog(0).therm_C[0] = 55.0;
  t.board.wait(0.0);
  t.board.wait(1.01);
  EXPECT_TRUE(t.chain.faultLine());
  // Zero thresholds keep the EEPROM's (65 degC): 55 degC does not trip.
  Rig k(1, 16, 16);
  k.cfg.auxHotCode = 0;
  k.cfg.compOv_mV = 0;
  k.init();
  k.chain.analog(0).therm_C[0] = 55.0;
  k.chain.analog(0).cell_V[2] = 4.15;
  k.board.wait(0.0);
  k.board.wait(1.01);
  EXPECT_FALSE(k.chain.faultLine());
}

TEST(Bq76pl455aDriver, BalancingReachesTheDeviceAndExpiresThere) {
  Rig r(2, 16, 32);
  r.init();
  uint32_t mask[bms::kBalanceWords] = {};
  mask[0] = (1u << 3) | (1u << 20);  // device 0 cell 3, device 1 cell 4
  EXPECT_EQ(bms::pl455BalanceTimeCode(90), 2);  // 60 s: never longer than asked
  ASSERT_TRUE(bms::pl455WriteBalance(r.cfg, r.board.board(), r.board.api(), mask, 90));
  EXPECT_TRUE(r.chain.balancing(0, 3));
  EXPECT_TRUE(r.chain.balancing(1, 4));
  EXPECT_FALSE(r.chain.balancing(1, 3));
  r.board.wait(59.0);
  EXPECT_TRUE(r.chain.balancing(0, 3));
  r.board.wait(1.1);
  EXPECT_FALSE(r.chain.balancing(0, 3));
  EXPECT_FALSE(r.chain.balancing(1, 4));
}

TEST(Bq76pl455aDriver, ReadOutTakesTheTimeTheLinkAllows) {
  Rig r(4, 16, 64);
  r.init();
  const double t0 = r.board.t_s;
  r.readAll();
  // Broadcast sample (5 bytes), the conversion wait (20 channels x 100 us), then per
  // device: STATUS+FAULT_SUM (6 out, 6 back), held results (6 out, 43 back), 40 us a byte.
  const double byte_s = 10.0 / 250000.0;
  const double expected = 5 * byte_s + 20 * 100e-6 + 4 * (12 + 49) * byte_s;
  EXPECT_NEAR(r.board.t_s - t0, expected, 1e-9);
  EXPECT_EQ(bms::pl455ConversionTime_us(r.cfg, 0), 2000u);
}

// The held-results request asks for exactly the channels the driver selected (cells of
// a full or partly populated device, 0..8 AUX inputs, die, module): the part answers
// that many and the reading parses, with every cell and input in its place.
TEST(Bq76pl455aDriver, EverySelectionOfCellsAndInputsReadsBackInFull) {
  for (const int therms : {0, 1, 3, 8}) {
    for (const int cells : {1, 5, 16}) {
      MonitorConfig m = chainConfig(2, 16);
      m.thermistors_per_device = therms;
      const int cellCount = 16 + cells;  // the top device holds `cells`
      Bq76pl455aChain chain(m, cellCount, 3);
      test::ChainTestBoard board(chain);
      bms::Pl455Config cfg = driverConfig(m, cellCount);
      cfg.thermistorsPerDevice = static_cast<uint8_t>(therms);
      for (int d = 0; d < 2; ++d) {
        DeviceAnalog& a = chain.analog(d);
        for (size_t c = 0; c < a.cell_V.size(); ++c) a.cell_V[c] = Rig::truth(d, static_cast<int>(c));
        for (size_t k = 0; k < a.therm_C.size(); ++k) a.therm_C[k] = 20.0 + static_cast<double>(k);
      }
      bms::Pl455State state{};
      bms::DeviceReading reading[bms::kMaxDevices]{};
      bms::FrameResult result[bms::kMaxDevices]{};
      ASSERT_EQ(bms::pl455Init(cfg, state, board.board(), board.api()), 2);
      bms::pl455ReadAll(cfg, state, board.board(), board.api(), reading, result);
      const Thermistor th;
      Rng none(1);
      for (int d = 0; d < 2; ++d) {
        ASSERT_EQ(result[d], bms::FrameResult::Ok) << therms << " inputs, " << cells << " cells, device " << d;
        const int n = d == 0 ? 16 : cells;
        for (int c = 0; c < n; ++c) EXPECT_NEAR(reading[d].cell_mV[c], Rig::truth(d, c) * 1e3, 0.58) << d << " " << c;
        for (int k = 0; k < therms; ++k) EXPECT_EQ(reading[d].thermCode[k], th.code(20.0 + k, none)) << d << " " << k;
        EXPECT_EQ(reading[d].die_dC, 250);  // the model's default die at 25 degC
      }
    }
  }
}

}  // namespace
}  // namespace packsim
