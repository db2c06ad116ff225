// packsim's BQ76952 driver against the register-level model through the firmware
// contract (ChainTestBoard): configuration, read-out against the truth, comm faults,
// retries, fault clearing, balancing, FET control and the read-out's bus time.
#include <gtest/gtest.h>

#include <bms/afe/bq76952_driver.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "models/afe/bq76952.hpp"
#include "tests/models/chain_test_board.hpp"

namespace packsim {
namespace {

MonitorConfig modelConfig(bool crc) {
  MonitorConfig c;
  c.model = "bq76952";
  c.cells_per_device = 16;
  c.thermistors_per_device = 3;
  c.cell_adc.lsb = 1e-3;
  c.cell_adc.code_max = 32767;
  c.crc = crc;
  c.baud = 400000.0;
  c.measurement_period_s = 0.06;
  c.shunt_ohm = 0.001;
  return c;
}

bms::Bq952DriverConfig driverConfig(bool crc, uint8_t cells) {
  bms::Bq952DriverConfig c{};
  c.deviceCount = 1;
  c.firstBus = 0;
  c.cellsPerDevice = cells;
  c.cellCount = cells;
  c.thermistorsPerDevice = 3;
  c.crc = crc;
  c.crcRetries = 3;
  c.waitForScan = true;
  c.scanTimeout_us = 200000;
  c.userAmps = 2;  // 10 mA
  c.writeProtections = true;
  c.protection = bms::Bq952ProtectionConfig{4200, 500, 100, 2700, 500, 100, 20, 50, 60, 20, 200, 5,
                                            55, 60, 85, -10, -15, 2, 2, 5};
  c.balanceInterval_s = 20;
  return c;
}

struct Rig {
  Bq76952Chain dev;
  test::ChainTestBoard board;
  bms::Bq952Driver drv{};
  bms::Bq952DriverConfig cfg;
  Rig(const MonitorConfig& m, int cells, uint64_t seed = 5)
      : dev(m, cells, seed), board(dev), cfg(driverConfig(m.crc, static_cast<uint8_t>(cells))) {
    bms::bq952Init(drv, board.board(), board.api());
    DeviceAnalog& a = dev.analog(0);
    for (size_t k = 0; k < a.cell_V.size(); ++k) a.cell_V[k] = 3.60 + 0.01 * static_cast<double>(k);
    a.therm_C = {22.0, 31.0, 40.0};
    a.die_C = 35.0;
    a.current_A = 12.34;
  }
  bms::FrameResult read(bms::DeviceReading& r) { return bms::bq952Read(drv, cfg, 0, r); }
  // Time passes in 10 ms steps, as the simulation advances the chain every tick.
  void run(double dt_s) {
    const double end = board.t_s + dt_s;
    while (board.t_s < end - 1e-9) board.wait(std::min(0.01, end - board.t_s));
  }
};

TEST(Bq76952Driver, ConfigureWritesTheProtectionsAndLeavesFetTestMode) {
  Rig rig(modelConfig(true), 16);
  ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  EXPECT_EQ(rig.dev.dataMemory(BQ952_DM_COV_THRESHOLD), 83);  // 4200 / 50.6
  EXPECT_EQ(rig.dev.dataMemory(BQ952_DM_CUV_THRESHOLD), 53);  // 2700 / 50.6
  EXPECT_EQ(rig.dev.dataMemory(BQ952_DM_OCD1_THRESHOLD), 30);  // 60 mV / 2 mV
  EXPECT_EQ(rig.dev.dataMemory(BQ952_DM_SCD_THRESHOLD), 9);    // 200 mV
  EXPECT_EQ(static_cast<int8_t>(rig.dev.dataMemory(BQ952_DM_UTD_THRESHOLD)), -15);
  EXPECT_EQ(static_cast<int8_t>(rig.dev.dataMemory(BQ952_DM_OTC_RECOVERY)), 50);
  EXPECT_FALSE(rig.dev.configUpdateMode());
  EXPECT_TRUE(rig.dev.chargeFetOn());
  EXPECT_TRUE(rig.dev.dischargeFetOn());
  // The configured COV (83 x 50.6 mV = 4.1998 V) acts, not the part's 4.35 V.
  rig.dev.analog(0).cell_V[3] = 4.25;
  rig.run(1.0);
  EXPECT_FALSE(rig.dev.chargeFetOn());
}

TEST(Bq76952Driver, ReadOutReturnsTheTruthWithinQuantisationAndConfiguredError) {
  MonitorConfig m = modelConfig(true);
  m.channel_gain_sd = 0.0005;
  m.channel_offset_sd_V = 0.001;
  Rig rig(m, 16);
  ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  rig.board.wait(0.1);
  bms::DeviceReading r{};
  ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
  const DeviceAnalog& a = rig.dev.analog(0);
  double sum = 0;
  for (int k = 0; k < 16; ++k) {
    const double v = a.cell_V[static_cast<size_t>(k)];
    const double expect_mV = 1e3 * (v * (1.0 + rig.dev.channelGain(k)) + rig.dev.channelOffset_V(k));
    EXPECT_NEAR(r.cell_mV[k], expect_mV, 0.5 + 1e-9) << "cell " << k;
    sum += v;
  }
  EXPECT_NEAR(r.stack_mV, sum * 1e3, 5.0);
  EXPECT_NEAR(r.temp_dC[0], 220, 2);
  EXPECT_NEAR(r.temp_dC[1], 310, 2);
  EXPECT_NEAR(r.temp_dC[2], 400, 2);
  EXPECT_NEAR(r.die_dC, 350, 1);
  EXPECT_EQ(r.current_mA, 12340);  // 10 mA units, positive in discharge
  EXPECT_EQ(r.fetStatus & (BQ952_FET_CHG | BQ952_FET_DSG), BQ952_FET_CHG | BQ952_FET_DSG);
  EXPECT_FALSE(r.fault);
  // Charge: 12.34 A for the counter's whole conversions since the reset.
  rig.board.wait(10.0);
  ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
  const double t = rig.board.t_s;
  EXPECT_NEAR(r.charge_mAs, 12340.0 * t, 12340.0 * 0.26);
}

TEST(Bq76952Driver, WaitsForAFreshMeasurementLoop) {
  Rig rig(modelConfig(false), 8);
  ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  bms::DeviceReading r{};
  ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
  // A new value at the pins: the next read-out waits for the loop that converted it.
  rig.dev.analog(0).cell_V[0] = 3.3;
  ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
  EXPECT_EQ(r.cell_mV[0], 3300);
}

// Without waiting for a loop, a read-out between two loops is the previous loop again
// (FULLSCAN clear: sameLoop), and CC2 is the current of the loop the cells are from;
// a CC2 at its int16 rail (beyond 327.67 A at 10 mA units) is no such current.
TEST(Bq76952Driver, SaysWhetherTheLoopIsNewAndItsCurrentIsKnown) {
  Rig rig(modelConfig(false), 8);
  rig.cfg.waitForScan = false;
  ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  rig.run(0.1);
  bms::DeviceReading r{};
  ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
  EXPECT_FALSE(r.sameLoop);
  EXPECT_TRUE(r.loopCurrent);
  EXPECT_EQ(r.current_mA, 12340);
  rig.dev.analog(0).current_A = 2.0;  // after the loop: the registers still hold 12.34 A
  ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
  EXPECT_TRUE(r.sameLoop);
  EXPECT_EQ(r.current_mA, 12340);
  rig.run(0.07);  // a loop (60 ms) has run
  ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
  EXPECT_FALSE(r.sameLoop);
  EXPECT_EQ(r.current_mA, 2000);
  rig.dev.analog(0).current_A = 400.0;
  rig.run(0.07);
  ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
  EXPECT_FALSE(r.loopCurrent);
}

TEST(Bq76952Driver, SilentOrStuckDevicesNeverGiveAReading) {
  for (bool crc : {true, false}) {
    Rig rig(modelConfig(crc), 8);
    ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
    bms::DeviceReading r{};
    rig.dev.setCommFault(0, MonitorDeviceFault{true, 0.0, -1});
    EXPECT_EQ(rig.read(r), bms::FrameResult::Timeout);
    for (int stuck : {0x00, 0xFF}) {
      rig.dev.setCommFault(0, MonitorDeviceFault{false, 0.0, stuck});
      const bms::FrameResult res = rig.read(r);
      EXPECT_EQ(res, crc ? bms::FrameResult::BadCrc : bms::FrameResult::BadHeader) << "crc " << crc << " stuck " << stuck;
    }
    rig.dev.setCommFault(0, MonitorDeviceFault{});
    EXPECT_EQ(rig.read(r), bms::FrameResult::Ok);
  }
}

TEST(Bq76952Driver, CrcErrorsAreRetried) {
  Rig rig(modelConfig(true), 8);
  ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  rig.dev.setCommFault(0, MonitorDeviceFault{false, 0.3, -1});
  bms::DeviceReading r{};
  int ok = 0;
  for (int k = 0; k < 50; ++k) {
    rig.board.wait(0.1);
    if (rig.read(r) == bms::FrameResult::Ok) {
      ++ok;
      EXPECT_NEAR(r.cell_mV[0], 3600, 1);
    }
  }
  EXPECT_GT(rig.drv.crcRetriesUsed, 10u);
  EXPECT_GE(ok, 45);  // 3 retries at 30 %: a read fails with p < 1 %
  // Every reply corrupted: retries run out.
  rig.dev.setCommFault(0, MonitorDeviceFault{false, 1.0, -1});
  EXPECT_EQ(rig.read(r), bms::FrameResult::BadCrc);
}

TEST(Bq76952Driver, ClearFaultsDropsTheAlertOnceTheConditionIsGone) {
  Rig rig(modelConfig(true), 8);
  ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  EXPECT_FALSE(rig.dev.faultLine());
  rig.dev.analog(0).cell_V[1] = 4.3;
  rig.run(1.0);
  bms::DeviceReading r{};
  ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
  EXPECT_TRUE(r.fault);
  EXPECT_EQ(r.safetyA & BQ952_SA_COV, BQ952_SA_COV);
  EXPECT_EQ(r.fetStatus & BQ952_FET_CHG, 0);
  EXPECT_TRUE(rig.dev.faultLine());
  ASSERT_EQ(bms::bq952ClearFaults(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  EXPECT_TRUE(rig.dev.faultLine());  // still over-voltage
  rig.dev.analog(0).cell_V[1] = 3.9;
  rig.run(1.0);
  ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
  EXPECT_FALSE(r.fault);
  EXPECT_TRUE(rig.dev.faultLine());  // latched until cleared
  ASSERT_EQ(bms::bq952ClearFaults(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  EXPECT_FALSE(rig.dev.faultLine());
}

TEST(Bq76952Driver, BalancingReachesTheDeviceAndExpires) {
  Rig rig(modelConfig(true), 8);
  ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  ASSERT_EQ(bms::bq952SetBalance(rig.drv, rig.cfg, 0, 0x0081, 60), bms::FrameResult::Ok);
  const double start = rig.board.t_s;
  EXPECT_TRUE(rig.dev.balancing(0, 0));
  EXPECT_TRUE(rig.dev.balancing(0, 7));
  EXPECT_FALSE(rig.dev.balancing(0, 1));
  // Serviced once a second: on for the requested 60 s (past three device intervals), then off.
  while (rig.board.t_s < start + 59.0) {
    rig.board.wait(1.0);
    ASSERT_EQ(bms::bq952ServiceBalance(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
    EXPECT_TRUE(rig.dev.balancing(0, 0)) << rig.board.t_s - start;
  }
  rig.board.wait(2.0);
  ASSERT_EQ(bms::bq952ServiceBalance(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  EXPECT_FALSE(rig.dev.balancing(0, 0));
  // The MCU stops servicing (e.g. it hangs): the device ends balancing by itself.
  ASSERT_EQ(bms::bq952SetBalance(rig.drv, rig.cfg, 0, 0x0002, 600), bms::FrameResult::Ok);
  rig.board.wait(19.0);
  EXPECT_TRUE(rig.dev.balancing(0, 1));
  rig.board.wait(1.5);
  EXPECT_FALSE(rig.dev.balancing(0, 1));
}

TEST(Bq76952Driver, FetControlThroughSubcommands) {
  Rig rig(modelConfig(true), 8);
  ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  ASSERT_EQ(bms::bq952SetFets(rig.drv, rig.cfg, 0, false, true), bms::FrameResult::Ok);
  EXPECT_FALSE(rig.dev.chargeFetOn());
  EXPECT_TRUE(rig.dev.dischargeFetOn());
  ASSERT_EQ(bms::bq952SetFets(rig.drv, rig.cfg, 0, false, false), bms::FrameResult::Ok);
  EXPECT_FALSE(rig.dev.dischargeFetOn());
  ASSERT_EQ(bms::bq952SetFets(rig.drv, rig.cfg, 0, true, true), bms::FrameResult::Ok);
  EXPECT_TRUE(rig.dev.chargeFetOn());
  EXPECT_TRUE(rig.dev.dischargeFetOn());
}

// The bits a read-out puts on the bus, counted from the transactions the driver is
// documented to make (I2C: 9 bits a byte, start/stop, repeated start + read address).
double readoutBits(bool crc) {
  const int k = crc ? 2 : 1;
  auto write = [&](int dataBytes) { return (2 + k * dataBytes) * 9 + 2; };
  auto read = [&](int dataBytes) { return 2 * 9 + 2 + (1 + k * dataBytes) * 9 + 1; };
  return write(2) + read(36)  // DASTATUS6 and its buffer
         + read(2)            // Alarm Status (FULLSCAN already set)
         + read(40)           // cells, stack, PACK, LD, CC2
         + read(6)            // safety alerts / status
         + read(24)           // temperatures .. FET Status
         + write(2);          // clear FULLSCAN
}

TEST(Bq76952Driver, ReadOutTakesTheTimeTheLinkAllows) {
  for (double baud : {100000.0, 400000.0}) {
    for (bool crc : {true, false}) {
      MonitorConfig m = modelConfig(crc);
      m.baud = baud;
      Rig rig(m, 16);
      ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
      rig.board.wait(0.1);  // a loop has completed: no waiting for FULLSCAN
      const double t0 = rig.board.t_s;
      bms::DeviceReading r{};
      ASSERT_EQ(rig.read(r), bms::FrameResult::Ok);
      const double expect = readoutBits(crc) / baud + BQ952_SUBCMD_US * 1e-6;
      // The board clock counts whole microseconds in now_us only; t_s is exact.
      EXPECT_NEAR(rig.board.t_s - t0, expect, 1e-9) << "baud " << baud << " crc " << crc;
    }
  }
}

TEST(Bq76952Driver, SameSeedSameReadings) {
  MonitorConfig m = modelConfig(true);
  m.cell_adc.noise_rms = 0.002;
  m.channel_gain_sd = 0.001;
  auto run = [&](uint64_t seed) {
    Rig rig(m, 16, seed);
    EXPECT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
    std::vector<uint16_t> v;
    bms::DeviceReading r{};
    for (int k = 0; k < 5; ++k) {
      rig.board.wait(0.1);
      EXPECT_EQ(rig.read(r), bms::FrameResult::Ok);
      v.insert(v.end(), r.cell_mV, r.cell_mV + 16);
    }
    return v;
  };
  EXPECT_EQ(run(9), run(9));
  EXPECT_NE(run(9), run(10));
}

TEST(Bq76952Driver, ConfiguresAutonomousBalancing) {
  Rig rig(modelConfig(true), 8);
  rig.cfg.balancingConfig = BQ952_CB_CHG;
  rig.cfg.autoBalance = bms::Bq952AutoBalanceConfig{0, 45, 70, 1, 3500, 30, 10};
  ASSERT_EQ(bms::bq952Configure(rig.drv, rig.cfg, 0), bms::FrameResult::Ok);
  // Charging at 2 A; cells 3.60 .. 3.67 V: only cells 4..8 sit >= 30 mV over the lowest,
  // and one cell at a time: the highest, cell 8 (from the next 20 s evaluation on).
  rig.dev.analog(0).current_A = -2.0;
  rig.run(20.0);
  for (int c = 0; c < 8; ++c) EXPECT_EQ(rig.dev.balancing(0, c), c == 7) << c;
  // Not while discharging (CB_RLX off too).
  rig.dev.analog(0).current_A = 2.0;
  rig.run(20.0);
  for (int c = 0; c < 8; ++c) EXPECT_FALSE(rig.dev.balancing(0, c)) << c;
}

}  // namespace
}  // namespace packsim
