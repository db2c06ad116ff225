// The BQ76952 model's register map against the part's documented behaviour, driven
// byte by byte as an I2C host would. CRCs are checked with an independent bit-serial
// CRC-8 (polynomial 0x07, initial 0) written here, not the project's table code.
#include <gtest/gtest.h>

#include <bms/afe/bq76952_regs.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "models/afe/bq76952.hpp"

namespace packsim {
namespace {

uint8_t bitSerialCrc8(const std::vector<uint8_t>& bytes) {
  uint8_t crc = 0;
  for (uint8_t b : bytes) {
    for (int i = 7; i >= 0; --i) {
      const bool top = ((crc >> 7) ^ (b >> i)) & 1;
      crc = static_cast<uint8_t>(crc << 1);
      if (top) crc ^= 0x07;
    }
  }
  return crc;
}

constexpr uint8_t W = BQ952_I2C_ADDR << 1, R = (BQ952_I2C_ADDR << 1) | 1;

MonitorConfig config(bool crc) {
  MonitorConfig c;
  c.model = "bq76952";
  c.cells_per_device = 4;
  c.thermistors_per_device = 3;
  c.cell_adc.lsb = 1e-3;
  c.cell_adc.code_max = 32767;
  c.crc = crc;
  c.baud = 400000.0;
  c.measurement_period_s = 0.0;
  c.shunt_ohm = 0.001;
  return c;
}

// An I2C host written against the datasheet's frame description.
struct Host {
  Bq76952Chain& dev;
  bool crc;
  double t = 0.0;

  int write(uint8_t cmd, const std::vector<uint8_t>& data, bool corrupt = false) {
    std::vector<uint8_t> tx{W, cmd};
    for (size_t k = 0; k < data.size(); ++k) {
      tx.push_back(data[k]);
      if (crc) {
        uint8_t c = k == 0 ? bitSerialCrc8({W, cmd, data[0]}) : bitSerialCrc8({data[k]});
        if (corrupt) c ^= 0x01;
        tx.push_back(c);
      }
    }
    dev.advance(t);
    const BusTransfer r = dev.transfer(t, tx.data(), tx.size(), nullptr, 0);
    t += r.duration_s;
    return r.received;
  }
  // Reads n data bytes from cmd; checks every CRC; returns the data.
  std::vector<uint8_t> read(uint8_t cmd, size_t n, int* received = nullptr, bool* crcOk = nullptr) {
    const uint8_t tx[2] = {W, cmd};
    std::vector<uint8_t> rx(crc ? 2 * n : n, 0xA5);
    dev.advance(t);
    const BusTransfer r = dev.transfer(t, tx, 2, rx.data(), rx.size());
    t += r.duration_s;
    if (received) *received = r.received;
    std::vector<uint8_t> out;
    bool ok = true;
    for (size_t k = 0; k < n; ++k) {
      if (!crc) {
        out.push_back(rx[k]);
        continue;
      }
      out.push_back(rx[2 * k]);
      const uint8_t want = k == 0 ? bitSerialCrc8({W, cmd, R, rx[0]}) : bitSerialCrc8({rx[2 * k]});
      ok = ok && rx[2 * k + 1] == want;
    }
    if (crcOk) *crcOk = ok;
    return out;
  }
  int read16(uint8_t cmd) {
    const auto b = read(cmd, 2);
    return b[0] | (b[1] << 8);
  }
  void sub(uint16_t code) {
    write(BQ952_SUBCMD_LOW, {static_cast<uint8_t>(code & 0xFF), static_cast<uint8_t>(code >> 8)});
    t += BQ952_SUBCMD_US * 1e-6;
  }
  std::vector<uint8_t> subRead(uint16_t code, size_t n) {
    sub(code);
    const auto b = read(BQ952_SUBCMD_LOW, 2 + 32 + 2);
    EXPECT_EQ(b[0] | (b[1] << 8), code);
    return std::vector<uint8_t>(b.begin() + 2, b.begin() + 2 + static_cast<long>(n));
  }
  void subWrite(uint16_t code, const std::vector<uint8_t>& data, int checksumError = 0) {
    std::vector<uint8_t> w{static_cast<uint8_t>(code & 0xFF), static_cast<uint8_t>(code >> 8)};
    int sum = w[0] + w[1];
    for (uint8_t b : data) w.push_back(b), sum += b;
    write(BQ952_SUBCMD_LOW, w);
    write(BQ952_RESP_CHECKSUM, {static_cast<uint8_t>((~sum + checksumError) & 0xFF), static_cast<uint8_t>(data.size() + 4)});
    t += BQ952_SUBCMD_US * 1e-6;
  }
  void settle(double dt) {
    t += dt;
    dev.advance(t);
  }
};

void setCells(Bq76952Chain& d, double v) {
  for (double& x : d.analog(0).cell_V) x = v;
}

TEST(Bq76952, DeviceNumberEchoChecksumAndSubcommandTime) {
  Bq76952Chain dev(config(true), 4, 1);
  Host h{dev, true};
  h.write(BQ952_SUBCMD_LOW, {0x01, 0x00});
  // Read at once: the part is still busy and the echo reads 0xFF.
  auto busy = h.read(BQ952_SUBCMD_LOW, 2);
  EXPECT_EQ(busy[0], 0xFF);
  EXPECT_EQ(busy[1], 0xFF);
  h.t += BQ952_SUBCMD_US * 1e-6;
  const auto b = h.read(BQ952_SUBCMD_LOW, 36);
  EXPECT_EQ(b[0], 0x01);
  EXPECT_EQ(b[1], 0x00);
  EXPECT_EQ(b[2] | (b[3] << 8), 0x7695);                              // BQ76952
  EXPECT_EQ(b[35], 6);                                                 // length = 2 data + 4
  EXPECT_EQ(b[34], static_cast<uint8_t>(~(0x01 + 0x00 + 0x95 + 0x76)));  // checksum
}

TEST(Bq76952, DirectCommandsReadTheMeasurementsInTheirUnits) {
  MonitorConfig c = config(false);
  Bq76952Chain dev(c, 4, 1);
  DeviceAnalog& a = dev.analog(0);
  a.cell_V = {3.6004, 3.7, 3.2996, 4.1};
  a.therm_C = {25.0, 45.0, -10.0};
  a.die_C = 30.0;
  a.current_A = 2.5;  // discharge
  Host h{dev, false};
  EXPECT_EQ(h.read16(BQ952_CELL_VOLTAGE(1)), 3600);
  EXPECT_EQ(h.read16(BQ952_CELL_VOLTAGE(2)), 3700);
  EXPECT_EQ(h.read16(BQ952_CELL_VOLTAGE(3)), 3300);
  EXPECT_EQ(h.read16(BQ952_CELL_VOLTAGE(4)), 4100);
  EXPECT_EQ(h.read16(BQ952_STACK_VOLTAGE), 1470);  // 14.700 V in 10 mV
  // CC2 is positive in charge, 1 mA units by default.
  EXPECT_EQ(static_cast<int16_t>(h.read16(BQ952_CC2_CURRENT)), -2500);
  EXPECT_EQ(h.read16(BQ952_INT_TEMPERATURE), 3032);  // 303.15 K
  // Thermistors through the 12-bit divider: within one code of the truth (< 0.1 K here).
  EXPECT_NEAR(h.read16(BQ952_TS_TEMPERATURE(0)) * 0.1, 298.15, 0.15);
  EXPECT_NEAR(h.read16(BQ952_TS_TEMPERATURE(1)) * 0.1, 318.15, 0.15);
  EXPECT_NEAR(h.read16(BQ952_TS_TEMPERATURE(2)) * 0.1, 263.15, 0.15);
  // An open thermistor reads 0 K, a shorted one the top of the register.
  a.therm_fault = {ThermistorFault::Open, ThermistorFault::Short, ThermistorFault::None};
  EXPECT_EQ(h.read16(BQ952_TS_TEMPERATURE(0)), 0);
  EXPECT_EQ(h.read16(BQ952_TS_TEMPERATURE(1)), 0xFFFF);
}

TEST(Bq76952, RepliesCarryTheI2cCrcAndAWrongCrcDropsTheWrite) {
  Bq76952Chain dev(config(true), 4, 1);
  setCells(dev, 3.7);
  Host h{dev, true};
  bool ok = false;
  int got = 0;
  const auto cells = h.read(BQ952_CELL_VOLTAGE(1), 8, &got, &ok);
  EXPECT_EQ(got, 16);
  EXPECT_TRUE(ok);
  EXPECT_EQ(cells[0] | (cells[1] << 8), 3700);
  // SET_CFGUPDATE with a wrong CRC is not executed; with the right one it is.
  h.write(BQ952_SUBCMD_LOW, {0x90, 0x00}, /*corrupt=*/true);
  EXPECT_EQ(h.read16(BQ952_BATTERY_STATUS) & BQ952_BS_CFGUPDATE, 0);
  h.sub(BQ952_SUB_SET_CFGUPDATE);
  EXPECT_EQ(h.read16(BQ952_BATTERY_STATUS) & BQ952_BS_CFGUPDATE, BQ952_BS_CFGUPDATE);
}

TEST(Bq76952, DataMemoryTakesWritesOnlyInConfigUpdateMode) {
  Bq76952Chain dev(config(false), 4, 1);
  setCells(dev, 3.9);
  Host h{dev, false};
  const uint8_t before = dev.dataMemory(BQ952_DM_COV_THRESHOLD);
  EXPECT_EQ(before, 86);  // 4.35 V / 50.6 mV
  // Outside CONFIG_UPDATE: refused.
  h.subWrite(BQ952_DM_COV_THRESHOLD, {76});
  EXPECT_EQ(h.subRead(BQ952_DM_COV_THRESHOLD, 1)[0], before);
  // Inside, but with a wrong checksum: refused.
  h.sub(BQ952_SUB_SET_CFGUPDATE);
  h.subWrite(BQ952_DM_COV_THRESHOLD, {76}, /*checksumError=*/1);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_COV_THRESHOLD), before);
  h.subWrite(BQ952_DM_COV_THRESHOLD, {76});  // 3.8456 V
  EXPECT_EQ(h.subRead(BQ952_DM_COV_THRESHOLD, 1)[0], 76);
  h.sub(BQ952_SUB_EXIT_CFGUPDATE);
  EXPECT_EQ(h.read16(BQ952_BATTERY_STATUS) & (BQ952_BS_CFGUPDATE | BQ952_BS_POR), 0);
  // The new threshold acts: 3.9 V is now over-voltage (alert at once).
  h.settle(0.01);
  EXPECT_EQ(h.read(BQ952_SAFETY_ALERT_A, 1)[0] & BQ952_SA_COV, BQ952_SA_COV);
  // RESET brings back the programmed (power-up) values.
  h.sub(BQ952_SUB_RESET);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_COV_THRESHOLD), before);
  EXPECT_EQ(h.read16(BQ952_BATTERY_STATUS) & BQ952_BS_POR, BQ952_BS_POR);
}

TEST(Bq76952, CovAlertAtOnceStatusAfterDelayAlarmLatchedUntilCleared) {
  MonitorConfig c = config(false);
  Bq76952Chain dev(c, 4, 1);
  setCells(dev, 3.7);
  Host h{dev, false};
  h.sub(BQ952_SUB_FET_ENABLE);
  h.write(BQ952_ALARM_STATUS, {0xFF, 0xFF});
  h.settle(0.01);
  EXPECT_EQ(dev.analog(0).cell_V.size(), 4u);
  EXPECT_FALSE(dev.faultLine());
  EXPECT_TRUE(dev.chargeFetOn());
  dev.analog(0).cell_V[2] = 4.40;
  const double t0 = h.t + 0.01;
  h.settle(0.01);
  EXPECT_EQ(h.read(BQ952_SAFETY_ALERT_A, 1)[0], BQ952_SA_COV);
  EXPECT_EQ(h.read(BQ952_SAFETY_STATUS_A, 1)[0], 0);
  // The delay is 74 x 3.3 ms = 244.2 ms from the first loop that saw it.
  const double delay = 74 * 3.3e-3;
  h.t = t0 + delay - 0.005;
  h.settle(0.0);
  EXPECT_EQ(h.read(BQ952_SAFETY_STATUS_A, 1)[0], 0);
  h.t = t0 + delay + 0.001;
  h.settle(0.0);
  EXPECT_EQ(h.read(BQ952_SAFETY_STATUS_A, 1)[0], BQ952_SA_COV);
  EXPECT_TRUE(dev.faultLine());
  EXPECT_FALSE(dev.chargeFetOn());   // COV opens CHG
  EXPECT_TRUE(dev.dischargeFetOn());  // not DSG
  EXPECT_EQ(h.read(BQ952_FET_STATUS, 1)[0], BQ952_FET_DSG | BQ952_FET_ALRT_PIN);
  // Clearing while the fault is present does nothing.
  h.write(BQ952_ALARM_STATUS, {0x00, 0xFF});
  EXPECT_TRUE(h.read16(BQ952_ALARM_STATUS) & BQ952_AL_SSA);
  // Recovery by hysteresis: below 4.35 - 0.1 V the status clears by itself...
  dev.analog(0).cell_V[2] = 4.30;
  h.settle(0.1);
  EXPECT_EQ(h.read(BQ952_SAFETY_STATUS_A, 1)[0], BQ952_SA_COV);  // within the hysteresis
  dev.analog(0).cell_V[2] = 4.20;
  h.settle(0.1);
  EXPECT_EQ(h.read(BQ952_SAFETY_STATUS_A, 1)[0], 0);
  EXPECT_TRUE(dev.chargeFetOn());
  // ...but the alarm stays latched (and the ALERT line with it) until the host clears it.
  EXPECT_TRUE(h.read16(BQ952_ALARM_STATUS) & BQ952_AL_SSA);
  EXPECT_TRUE(dev.faultLine());
  h.write(BQ952_ALARM_STATUS, {0xFF, 0xFF});
  EXPECT_FALSE(h.read16(BQ952_ALARM_STATUS) & BQ952_AL_SSA);
  EXPECT_FALSE(dev.faultLine());
}

TEST(Bq76952, OverCurrentInDischargeOpensDsgAndRecoversAfterTheRecoveryTime) {
  MonitorConfig c = config(false);
  Bq76952Chain dev(c, 4, 1);
  setCells(dev, 3.7);
  Host h{dev, false};
  h.sub(BQ952_SUB_FET_ENABLE);
  // OCD1 8 mV across 1 mOhm = 8 A; delay 3 x 3.3 ms.
  dev.analog(0).current_A = 9.0;
  h.settle(0.001);
  EXPECT_EQ(h.read(BQ952_SAFETY_ALERT_A, 1)[0] & BQ952_SA_OCD1, BQ952_SA_OCD1);
  h.settle(0.0099 + 0.001);
  EXPECT_EQ(h.read(BQ952_SAFETY_STATUS_A, 1)[0] & BQ952_SA_OCD1, BQ952_SA_OCD1);
  EXPECT_FALSE(dev.dischargeFetOn());
  EXPECT_TRUE(dev.chargeFetOn());
  const double tripped = h.t;
  dev.analog(0).current_A = 0.0;
  h.settle(4.0);
  EXPECT_NE(h.read(BQ952_SAFETY_STATUS_A, 1)[0] & BQ952_SA_OCD1, 0);  // 5 s recovery time
  h.t = tripped + 5.05;
  h.settle(0.0);
  EXPECT_EQ(h.read(BQ952_SAFETY_STATUS_A, 1)[0] & BQ952_SA_OCD1, 0);
  EXPECT_TRUE(dev.dischargeFetOn());
}

TEST(Bq76952, FetsStayOffInTestModeAndFollowTheHostSubcommands) {
  Bq76952Chain dev(config(false), 4, 1);
  setCells(dev, 3.7);
  Host h{dev, false};
  h.settle(0.01);
  EXPECT_EQ(h.read(BQ952_FET_STATUS, 1)[0] & (BQ952_FET_CHG | BQ952_FET_DSG), 0);
  EXPECT_EQ(h.subRead(BQ952_SUB_MANUFACTURING_STATUS, 2)[0] & BQ952_MFG_FET_EN, 0);
  h.sub(BQ952_SUB_FET_ENABLE);
  EXPECT_EQ(h.subRead(BQ952_SUB_MANUFACTURING_STATUS, 2)[0] & BQ952_MFG_FET_EN, BQ952_MFG_FET_EN);
  EXPECT_EQ(h.read(BQ952_FET_STATUS, 1)[0] & (BQ952_FET_CHG | BQ952_FET_DSG), BQ952_FET_CHG | BQ952_FET_DSG);
  h.sub(BQ952_SUB_CHG_PCHG_OFF);
  EXPECT_FALSE(dev.chargeFetOn());
  EXPECT_TRUE(dev.dischargeFetOn());
  h.sub(BQ952_SUB_ALL_FETS_OFF);
  EXPECT_FALSE(dev.dischargeFetOn());
  h.settle(0.01);
  EXPECT_EQ(h.read16(BQ952_ALARM_RAW_STATUS) & (BQ952_AL_XCHG | BQ952_AL_XDSG), BQ952_AL_XCHG | BQ952_AL_XDSG);
  h.sub(BQ952_SUB_ALL_FETS_ON);
  EXPECT_TRUE(dev.chargeFetOn());
  EXPECT_TRUE(dev.dischargeFetOn());
  h.sub(BQ952_SUB_DSG_PDSG_OFF);
  EXPECT_FALSE(dev.dischargeFetOn());
}

TEST(Bq76952, HostBalancingRunsUntilStoppedOrExpiresOnTheDevice) {
  Bq76952Chain dev(config(false), 4, 1);
  setCells(dev, 3.7);
  Host h{dev, false};
  h.subWrite(BQ952_SUB_CB_ACTIVE_CELLS, {0x05, 0x00});
  EXPECT_TRUE(dev.balancing(0, 0));
  EXPECT_FALSE(dev.balancing(0, 1));
  EXPECT_TRUE(dev.balancing(0, 2));
  EXPECT_EQ(h.subRead(BQ952_SUB_CB_ACTIVE_CELLS, 2)[0], 0x05);
  h.settle(0.1);
  EXPECT_TRUE(h.read16(BQ952_ALARM_RAW_STATUS) & BQ952_AL_CB);
  // Not re-armed: the device ends it one Cell Balance Interval (20 s) after the write.
  h.settle(19.0);
  EXPECT_TRUE(dev.balancing(0, 0));
  EXPECT_EQ(h.subRead(BQ952_SUB_CBSTATUS1, 2)[0], 19);
  h.settle(1.0);
  EXPECT_FALSE(dev.balancing(0, 0));
  EXPECT_EQ(h.subRead(BQ952_SUB_CB_ACTIVE_CELLS, 2)[0], 0);
  // Written 0 by the host: stops at once.
  h.subWrite(BQ952_SUB_CB_ACTIVE_CELLS, {0x02, 0x00});
  EXPECT_TRUE(dev.balancing(0, 1));
  h.subWrite(BQ952_SUB_CB_ACTIVE_CELLS, {0x00, 0x00});
  EXPECT_FALSE(dev.balancing(0, 1));
}

// CB_ACTIVE_CELLS bits above the cells the part has (4 of its 16 inputs) switch
// nothing, and the write is noted like any other the part ignores, naming the bits.
TEST(Bq76952, BalancingBitsForCellsThePartDoesNotHaveAreNoted) {
  Bq76952Chain dev(config(false), 4, 1);
  setCells(dev, 3.7);
  Host h{dev, false};
  h.subWrite(BQ952_SUB_CB_ACTIVE_CELLS, {0x09, 0x00});  // cells 1 and 4: legal
  EXPECT_TRUE(dev.misuse().entries().empty());
  h.subWrite(BQ952_SUB_CB_ACTIVE_CELLS, {0x31, 0x80});  // cell 1, and cells 5, 6, 16
  EXPECT_TRUE(dev.balancing(0, 0));
  EXPECT_EQ(h.subRead(BQ952_SUB_CB_ACTIVE_CELLS, 2)[0], 0x01);
  const std::vector<RegisterMisuse>& m = dev.misuse().entries();
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].what, "CB_ACTIVE_CELLS");
  EXPECT_EQ(m[0].why, "balancing bits 0x8030 (cells 5-6, 16) for cells the device does not have (it has 4): ignored, "
                      "those switches stay off");
}

TEST(Bq76952, ReadingsRefreshOncePerMeasurementLoopWithFullscan) {
  MonitorConfig c = config(false);
  c.measurement_period_s = 0.06;
  Bq76952Chain dev(c, 4, 1);
  setCells(dev, 3.7);
  Host h{dev, false};
  EXPECT_EQ(h.read16(BQ952_CELL_VOLTAGE(1)), 3700);
  h.write(BQ952_ALARM_STATUS, {BQ952_AL_FULLSCAN, 0});
  EXPECT_EQ(h.read16(BQ952_ALARM_STATUS) & BQ952_AL_FULLSCAN, 0);
  setCells(dev, 3.5);
  h.settle(0.03);
  // Before the loop completes: the old result, data-ready clear.
  EXPECT_EQ(h.read16(BQ952_CELL_VOLTAGE(1)), 3700);
  EXPECT_EQ(h.read16(BQ952_ALARM_STATUS) & BQ952_AL_FULLSCAN, 0);
  h.settle(0.03);
  EXPECT_EQ(h.read16(BQ952_ALARM_STATUS) & BQ952_AL_FULLSCAN, BQ952_AL_FULLSCAN);
  EXPECT_EQ(h.read16(BQ952_CELL_VOLTAGE(1)), 3500);
}

TEST(Bq76952, CommFaultsActOnTheBytes) {
  Bq76952Chain dev(config(true), 4, 1);
  setCells(dev, 3.7);
  Host h{dev, true};
  int got = 0;
  bool ok = true;
  // Another address: nobody acknowledges.
  const uint8_t other[2] = {0x20, BQ952_CELL_VOLTAGE(1)};
  uint8_t rx[4];
  EXPECT_EQ(dev.transfer(0.0, other, 2, rx, 4).received, -1);
  // Silent: no answer, writes lost.
  dev.setCommFault(0, MonitorDeviceFault{true, 0.0, -1});
  h.read(BQ952_CELL_VOLTAGE(1), 2, &got);
  EXPECT_EQ(got, -1);
  h.sub(BQ952_SUB_SET_CFGUPDATE);
  EXPECT_FALSE(dev.configUpdateMode());
  // Stuck: every reply byte reads so (and fails the CRC); writes do not land.
  for (int stuck : {0x00, 0xFF}) {
    dev.setCommFault(0, MonitorDeviceFault{false, 0.0, stuck});
    const auto b = h.read(BQ952_CELL_VOLTAGE(1), 2, &got, &ok);
    EXPECT_EQ(got, 4);
    EXPECT_EQ(b[0], stuck);
    EXPECT_FALSE(ok);
    h.sub(BQ952_SUB_SET_CFGUPDATE);
    EXPECT_FALSE(dev.configUpdateMode());
  }
  // CRC error rate 1: every reply has exactly one bit flipped.
  dev.setCommFault(0, MonitorDeviceFault{false, 1.0, -1});
  dev.advance(h.t);
  const uint8_t tx[2] = {W, BQ952_CELL_VOLTAGE(1)};
  uint8_t clean[4], bad[4];
  dev.setCommFault(0, MonitorDeviceFault{});
  dev.transfer(h.t, tx, 2, clean, 4);
  for (int k = 0; k < 20; ++k) {
    dev.setCommFault(0, MonitorDeviceFault{false, 1.0, -1});
    dev.transfer(h.t, tx, 2, bad, 4);
    int flipped = 0;
    for (int i = 0; i < 4; ++i) flipped += __builtin_popcount(clean[i] ^ bad[i]);
    EXPECT_EQ(flipped, 1);
  }
}

TEST(Bq76952, TransactionTimeFollowsTheI2cClock) {
  MonitorConfig c = config(false);
  c.baud = 100000.0;
  Bq76952Chain dev(c, 4, 1);
  // Write [addr][cmd] (2 x 9 bits + start/stop), repeated start + [addr|R] + 4 bytes.
  EXPECT_NEAR(dev.transferTime_s(2, 4), (2 * 9 + 2 + 1 + 5 * 9) / 100000.0, 1e-12);
  const uint8_t tx[2] = {W, BQ952_CELL_VOLTAGE(1)};
  uint8_t rx[4];
  EXPECT_NEAR(dev.transfer(0.0, tx, 2, rx, 4).duration_s, 66e-5, 1e-12);
}

TEST(Bq76952, ChannelErrorsFromTheSeedAndBytesDeterministic) {
  MonitorConfig c = config(true);
  c.channel_gain_sd = 0.002;
  c.channel_offset_sd_V = 0.003;
  c.cell_adc.noise_rms = 0.002;
  Bq76952Chain a(c, 4, 77), b(c, 4, 77), other(c, 4, 78);
  for (int k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(a.channelGain(k), b.channelGain(k));
    EXPECT_DOUBLE_EQ(a.channelOffset_V(k), b.channelOffset_V(k));
    EXPECT_NE(a.channelGain(k), other.channelGain(k));
    EXPECT_NE(a.channelGain(k), 0.0);
  }
  std::vector<uint8_t> ra, rb, ro;
  for (Bq76952Chain* d : {&a, &b, &other}) {
    setCells(*d, 3.7);
    std::vector<uint8_t>& out = d == &a ? ra : d == &b ? rb : ro;
    const uint8_t tx[2] = {W, BQ952_CELL_VOLTAGE(1)};
    for (int k = 0; k < 10; ++k) {
      d->advance(0.1 * k);
      uint8_t rx[16];
      d->transfer(0.1 * k, tx, 2, rx, 16);
      out.insert(out.end(), rx, rx + 16);
    }
  }
  EXPECT_EQ(ra, rb);
  EXPECT_NE(ra, ro);
}

// Each protection opens the FETs the part's default FET Protections tables name, at the
// condition's start plus its data-memory delay (within one 60 ms measurement loop and one
// 10 ms step), and re-closes them on the part's recovery: voltage and temperature by
// hysteresis once the condition ends at 5 s, current after its recovery time (5 s after
// the trip) with the current gone.
TEST(Bq76952, ProtectionsOpenAndRecloseTheirFetsAfterTheirDelays) {
  struct Case {
    const char* name;
    double cell_V, current_A, ts1_C, ts3_C;
    bool chg, dsg;          // which FET the part's defaults open
    double open_s, close_s;  // expected
  };
  // Delays in the part's steps: COV/CUV 74 x 3.3 ms; OCC (4 + 2) x 3.3 ms; OCD1 (1 + 2)
  // x 3.3 ms; SCD at once; temperature 2 s.
  const double vDelay = 74 * 0.0033, occDelay = 6 * 0.0033, ocd1Delay = 3 * 0.0033;
  const Case cases[] = {
      {"COV", 4.40, 0.0, 25, 25, true, false, 1.0 + vDelay, 5.0},
      {"CUV", 2.40, 0.0, 25, 25, false, true, 1.0 + vDelay, 5.0},
      {"OCC", 3.7, -5.0, 25, 25, true, false, 1.0 + occDelay, 1.0 + occDelay + 5.0},
      {"OCD1", 3.7, 9.0, 25, 25, false, true, 1.0 + ocd1Delay, 1.0 + ocd1Delay + 5.0},
      {"SCD", 3.7, 120.0, 25, 25, true, true, 1.0, 6.0},
      {"OTC", 3.7, 0.0, 57, 25, true, false, 3.0, 5.0},
      {"OTD", 3.7, 0.0, 62, 25, true, true, 3.0, 5.0},  // 62 C is above OTC's 55 C too
      {"OTF", 3.7, 0.0, 25, 85, true, true, 3.0, 5.0},
      {"UT", 3.7, 0.0, -5, 25, true, true, 3.0, 5.0},   // UTC (CHG) and UTD (DSG)
      {"OTC (over-temperature in charge, judged at any current), OTD", 3.7, 0.0, 62, 25, true, true, 3.0, 5.0},
  };
  for (const Case& k : cases) {
    MonitorConfig c = config(false);
    c.measurement_period_s = 0.06;
    Bq76952Chain dev(c, 4, 1);
    Host h{dev, false};
    h.sub(BQ952_SUB_FET_ENABLE);
    double when[2][2];  // [chg/dsg][open/close]
    for (auto& w : when) w[0] = w[1] = -1.0;
    std::string cause;  // what holds the FAULT line at 4 s, the protections by name
    const double dt = 0.01;
    for (int i = 1; i <= 1400; ++i) {
      const double t = i * dt;
      const bool on = t >= 1.0 && t < 5.0;  // the condition holds from 1 s to 5 s
      DeviceAnalog& a = dev.analog(0);
      for (int n = 0; n < 4; ++n) a.cell_V[n] = n == 2 && on ? k.cell_V : 3.7;
      a.current_A = on ? k.current_A : 0.0;
      a.therm_C = {on ? k.ts1_C : 25.0, 25.0, on ? k.ts3_C : 25.0};
      dev.advance(t);
      const bool state[2] = {dev.chargeFetOn(), dev.dischargeFetOn()};
      if (!dev.faultLine()) EXPECT_EQ(dev.faultCause(), "") << k.name;
      if (t == 4.0) cause = dev.faultCause().substr(std::string("Safety Status ").size());
      for (int f = 0; f < 2; ++f) {
        if (!state[f] && when[f][0] < 0) when[f][0] = t;
        if (state[f] && when[f][0] >= 0 && when[f][1] < 0) when[f][1] = t;
      }
    }
    const bool expect[2] = {k.chg, k.dsg};
    EXPECT_NE(cause.find(k.name), std::string::npos) << k.name << ": the FAULT line holds for " << cause;
    const double slack = c.measurement_period_s + dt + 1e-9;
    for (int f = 0; f < 2; ++f) {
      const char* fet = f == 0 ? "CHG" : "DSG";
      EXPECT_EQ(when[f][0] >= 0, expect[f]) << k.name << " " << fet;
      if (!expect[f]) continue;
      EXPECT_GE(when[f][0], k.open_s - 1e-9) << k.name << " " << fet << " opens";
      EXPECT_LE(when[f][0], k.open_s + slack) << k.name << " " << fet << " opens";
      EXPECT_GE(when[f][1], k.close_s - 1e-9) << k.name << " " << fet << " recloses";
      EXPECT_LE(when[f][1], k.close_s + slack) << k.name << " " << fet << " recloses";
    }
  }
}

// At 62 °C both OTC and OTD latch: each FET's driver is off for the protections the part
// routes to it (OTC to CHG, OTD to DSG), and says which.
TEST(Bq76952, EachFetSaysWhichProtectionHoldsItOff) {
  MonitorConfig c = config(false);
  c.measurement_period_s = 0.06;
  Bq76952Chain dev(c, 4, 1);
  Host h{dev, false};
  h.sub(BQ952_SUB_FET_ENABLE);
  EXPECT_EQ(dev.fetOffCause(true), "");
  for (int i = 1; i <= 400; ++i) {
    DeviceAnalog& a = dev.analog(0);
    for (int n = 0; n < 4; ++n) a.cell_V[n] = 3.7;
    a.therm_C = {62.0, 25.0, 25.0};
    dev.advance(i * 0.01);
  }
  EXPECT_EQ(dev.fetOffCause(true), "a protection in Safety Status: OTD (over-temperature in discharge)");
  EXPECT_EQ(dev.fetOffCause(false),
            "a protection in Safety Status: OTC (over-temperature in charge, judged at any current)");
}

// OCD3, the slow discharge limit on the coulomb counter (Safety C): a current above its
// threshold in user amps for its whole seconds opens DSG; off unless configured.
TEST(Bq76952, Ocd3OpensTheDischargeFetAfterWholeSeconds) {
  MonitorConfig c = config(false);
  c.bq.user_amps_A = 0.01;
  c.bq.ocd3_A = 60.0;
  c.bq.ocd3_delay_s = 1.0;
  c.bq.ocd1_mV = 200.0;  // 200 A: out of the way
  c.bq.scd_mV = 500.0;
  Bq76952Chain dev(c, 4, 1);
  Host h{dev, false};
  h.sub(BQ952_SUB_FET_ENABLE);
  double opened = -1.0;
  for (int i = 1; i <= 400; ++i) {
    const double t = i * 0.01;
    DeviceAnalog& a = dev.analog(0);
    for (double& v : a.cell_V) v = 3.7;
    a.current_A = t >= 1.0 ? 65.0 : 59.0;  // 59 A never trips it
    dev.advance(t);
    if (!dev.dischargeFetOn() && opened < 0) opened = t;
  }
  EXPECT_NEAR(opened, 2.0, 0.011);
  EXPECT_TRUE(dev.chargeFetOn()) << "OCD3 opens only DSG";
  c.bq.ocd3_A = 0.0;  // off
  Bq76952Chain off(c, 4, 1);
  Host h2{off, false};
  h2.sub(BQ952_SUB_FET_ENABLE);
  for (int i = 1; i <= 400; ++i) {
    off.analog(0).current_A = 65.0;
    for (double& v : off.analog(0).cell_V) v = 3.7;
    off.advance(i * 0.01);
  }
  EXPECT_TRUE(off.dischargeFetOn());
  // A threshold the part cannot hold in its user amps is refused.
  c.bq.user_amps_A = 0.001;
  c.bq.ocd3_A = 60.0;  // 60,000 userA > 32,768
  EXPECT_THROW(Bq76952Chain(c, 4, 1), std::invalid_argument);
}

// Autonomous balancing (TRM: every Cell Balance Interval, highest cells above Min Cell V
// and Min Delta above the lowest, at most Max Cells, no two neighbours, stop at Stop Delta).
TEST(Bq76952, AutonomousBalancingPicksCellsByItsThresholdsEachInterval) {
  Bq76952Chain dev(config(false), 4, 1);
  DeviceAnalog& a = dev.analog(0);
  a.cell_V = {3.95, 4.00, 4.05, 4.06};
  a.therm_C = {25.0, 25.0, 25.0};
  Host h{dev, false};
  h.settle(0.01);
  EXPECT_FALSE(dev.balancing(0, 3));  // off by default
  h.sub(BQ952_SUB_SET_CFGUPDATE);
  h.subWrite(BQ952_DM_CB_CONFIG, {BQ952_CB_RLX});
  h.subWrite(BQ952_DM_CB_MAX_CELLS, {2});
  h.sub(BQ952_SUB_EXIT_CFGUPDATE);
  h.settle(0.01);
  // Deltas over the lowest (3950 mV): 50, 100, 110 mV, all >= 40. Highest first: cell 4,
  // then cell 3 is its neighbour, so cell 2.
  EXPECT_FALSE(dev.balancing(0, 0));
  EXPECT_TRUE(dev.balancing(0, 1));
  EXPECT_FALSE(dev.balancing(0, 2));
  EXPECT_TRUE(dev.balancing(0, 3));
  EXPECT_EQ(h.subRead(BQ952_SUB_CB_ACTIVE_CELLS, 2)[0], 0x0A);
  // Cell 4 falls to 20 mV over the lowest (= Stop Delta): it stops at the next
  // evaluation, 20 s on, not before; cell 3 (50 mV) is the highest, so cell 2 waits.
  a.cell_V = {3.95, 4.00, 4.05, 3.97};
  h.settle(19.0);
  EXPECT_TRUE(dev.balancing(0, 3));
  h.settle(1.0);
  EXPECT_FALSE(dev.balancing(0, 3));
  EXPECT_TRUE(dev.balancing(0, 2));
  EXPECT_FALSE(dev.balancing(0, 1));
  // Discharging (not relax): no autonomous balancing at the next evaluation.
  a.current_A = 5.0;
  h.settle(20.0);
  EXPECT_EQ(h.subRead(BQ952_SUB_CB_ACTIVE_CELLS, 2)[0], 0);
  // At rest again but a cell thermistor above Max Cell Temp (60 degC): none either.
  a.current_A = 0.0;
  a.therm_C = {65.0, 25.0, 25.0};
  h.settle(20.0);
  EXPECT_EQ(h.subRead(BQ952_SUB_CB_ACTIVE_CELLS, 2)[0], 0);
  a.therm_C = {25.0, 25.0, 25.0};
  h.settle(20.0);
  EXPECT_EQ(h.subRead(BQ952_SUB_CB_ACTIVE_CELLS, 2)[0], 0x04);
}

// MonitorConfig::bq's defaults land on the part's documented data-memory defaults
// (TRM: COV 86, COV delay 74, CUV 50, OCC 2 / delay 4, OCD1 4 / delay 1, SCD 100 mV);
// a value the part cannot hold is an error naming the setting, not a silent clamp.
TEST(Bq76952, ProgrammedSettingsAreThePartsDefaultsAndOutOfRangeIsAnError) {
  Bq76952Chain dev(config(false), 4, 1);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_COV_THRESHOLD), 86);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_COV_DELAY), 74);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_CUV_THRESHOLD), 50);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_OCC_THRESHOLD), 2);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_OCC_DELAY), 4);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_OCD1_THRESHOLD), 4);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_OCD1_DELAY), 1);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_SCD_THRESHOLD), 5);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_CHG_FET_PROT_A), 0x98);  // SCD, OCC, COV
  EXPECT_EQ(dev.dataMemory(BQ952_DM_DSG_FET_PROT_A), 0xE4);  // SCD, OCD2, OCD1, CUV
  MonitorConfig c = config(false);
  c.bq.ocd1_delay_s = 1.0;  // OCD1 Delay holds at most (127 + 2) x 3.3 ms
  try {
    Bq76952Chain bad(c, 4, 1);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("ocd1_delay_ms"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Bq76952Chain(config(false), 17, 1), std::invalid_argument);
}

// Writes the part ignores stay ignored, and each distinct (register, reason) is noted
// once with its count (the run turns these into register_misuse events).
TEST(Bq76952, IgnoredWritesAreNotedOncePerRegisterAndReasonWithACount) {
  Bq76952Chain dev(config(true), 4, 1);
  setCells(dev, 3.7);
  Host h{dev, true};
  // Legal traffic leaves nothing: reads, a subcommand, a data-memory read, an alarm clear.
  h.read(BQ952_CELL_VOLTAGE(1), 8);
  h.sub(BQ952_SUB_FET_ENABLE);
  h.subRead(BQ952_DM_COV_THRESHOLD, 1);
  h.write(BQ952_ALARM_STATUS, {0xFF, 0xFF});
  EXPECT_TRUE(dev.misuse().entries().empty());

  // A read-only direct command, written twice, and a cell voltage's high byte once.
  const int before = h.read16(BQ952_STACK_VOLTAGE);
  h.write(BQ952_STACK_VOLTAGE, {0x00, 0x00});
  h.write(BQ952_STACK_VOLTAGE, {0x12, 0x34});
  EXPECT_EQ(h.read16(BQ952_STACK_VOLTAGE), before);  // still ignored
  h.write(static_cast<uint8_t>(BQ952_CELL_VOLTAGE(2) + 1), {0x00});
  // A write with a wrong CRC: dropped.
  h.write(BQ952_SUBCMD_LOW, {0x90, 0x00}, /*corrupt=*/true);
  EXPECT_EQ(h.read16(BQ952_BATTERY_STATUS) & BQ952_BS_CFGUPDATE, 0);
  // A data-memory write outside CONFIG_UPDATE, then one with a wrong checksum inside it.
  const uint8_t cov = dev.dataMemory(BQ952_DM_COV_THRESHOLD);
  h.subWrite(BQ952_DM_COV_THRESHOLD, {76});
  h.sub(BQ952_SUB_SET_CFGUPDATE);
  h.subWrite(BQ952_DM_COV_THRESHOLD, {76}, /*checksumError=*/1);
  EXPECT_EQ(dev.dataMemory(BQ952_DM_COV_THRESHOLD), cov);
  // Balancing commanded in CONFIG_UPDATE mode.
  h.subWrite(BQ952_SUB_CB_ACTIVE_CELLS, {0x01, 0x00});
  EXPECT_FALSE(dev.balancing(0, 0));

  const std::vector<RegisterMisuse>& m = dev.misuse().entries();
  ASSERT_EQ(m.size(), 7u);
  auto expect = [&](size_t i, const std::string& what, const std::string& why, long count) {
    EXPECT_EQ(m[i].device, 0);
    EXPECT_EQ(m[i].what, what);
    EXPECT_NE(m[i].why.find(why), std::string::npos) << m[i].why;
    EXPECT_EQ(m[i].count, count) << what;
  };
  expect(0, "Stack Voltage", "read-only", 2);
  expect(1, "Stack Voltage (high byte)", "read-only", 2);
  expect(2, "Cell 2 Voltage", "read-only", 1);
  expect(3, "subcommand (low byte)", "CRC", 1);
  expect(4, "data memory 0x9278", "outside CONFIG_UPDATE", 1);
  expect(5, "data memory 0x9278", "checksum", 1);
  expect(6, "CB_ACTIVE_CELLS", "CONFIG_UPDATE", 1);
  EXPECT_LT(m[0].first_s, m[0].last_s);
}

// The loop opens a cell's balancing switch while it converts the cell or a neighbour
// (BQ76952 TRM, "Cell Balancing": balancing is disabled on the cell being measured and
// its neighbours, on the top cell during the stack measurement): a balanced cell reads
// 3.700 V unloaded, not the 3.698 V at its pins (80 mA through 25 mΩ), and its switch
// conducts the rest of the loop. 4 cells, 3 thermistors: 18 + 3 slots of 3 ms = 63 ms;
// an inner cell is open 3 slots (duty 6/7), the bottom 2 (19/21), the top 2 + 1/3 (8/9).
TEST(Bq76952, ABalancedCellReadsUnloadedAndItsSwitchConductsOutsideItsSlots) {
  Bq76952Chain dev(config(false), 4, 1);
  DeviceAnalog& a = dev.analog(0);
  a.cell_unloaded_V.assign(4, 3.7);
  a.cell_V = {3.7, 3.7 - 0.080 * 0.025, 3.7, 3.7};
  Host h{dev, false};
  h.subWrite(BQ952_SUB_CB_ACTIVE_CELLS, {0x02, 0x00});
  ASSERT_TRUE(dev.balancing(0, 1));
  h.settle(0.1);
  EXPECT_EQ(h.read16(BQ952_CELL_VOLTAGE(2)), 3700);
  EXPECT_NEAR(dev.balancingDuty(0, 1, 0.0, 1.0), 6.0 / 7.0, 1e-12);
  EXPECT_NEAR(dev.balancingDuty(0, 0, 0.0, 1.0), 19.0 / 21.0, 1e-12);
  EXPECT_NEAR(dev.balancingDuty(0, 3, 0.0, 1.0), 8.0 / 9.0, 1e-12);
  // A slower loop (idle slots up to measurement_period_s) opens it for less of the time.
  MonitorConfig slow = config(false);
  slow.measurement_period_s = 0.252;
  Bq76952Chain quarter(slow, 4, 1);
  EXPECT_NEAR(quarter.balancingDuty(0, 1, 0.0, 1.0), 1.0 - 9e-3 / 0.252, 1e-12);
}

}  // namespace
}  // namespace packsim
