// The BQ76PL455A chain model against the part's documented behaviour, byte for byte:
// frame format and CRC-16 (checked with an independent bit-serial CRC), auto-addressing,
// register reads and writes, the EEPROM burn refused without its keys, sampling and its
// conversion time, latched comparator faults and their clearing, the balance timer
// expiring on the device, and comm faults acting on the bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <bms/afe/bq76pl455a_regs.h>

#include "models/afe/bq76pl455a.hpp"

namespace packsim {
namespace {

// CRC-16/ARC computed bit by bit from the polynomial x^16 + x^15 + x^2 + 1, the
// register shifted LSB first (independent of the table in bms_crc.cpp).
uint16_t bitSerialCrc16(const std::vector<uint8_t>& bytes) {
  uint16_t crc = 0;
  for (uint8_t b : bytes)
    for (int i = 0; i < 8; ++i) {
      const bool in = ((b >> i) & 1u) != ((crc & 1u) != 0);
      crc = static_cast<uint16_t>(crc >> 1);
      // reflected 0x8005: bits 15, 13 and 0 of the reversed polynomial
      if (in) crc ^= 0xA001;
    }
  return crc;
}

std::vector<uint8_t> frame(uint8_t req, int address, uint8_t reg, std::vector<uint8_t> data) {
  std::vector<uint8_t> f{static_cast<uint8_t>(PL455_INIT_COMMAND | req | PL455_SIZE_FIELD(data.size()))};
  if (address >= 0) f.push_back(static_cast<uint8_t>(address));
  f.push_back(reg);
  f.insert(f.end(), data.begin(), data.end());
  const uint16_t crc = bitSerialCrc16(f);
  f.push_back(static_cast<uint8_t>(crc & 0xFF));
  f.push_back(static_cast<uint8_t>(crc >> 8));
  return f;
}

MonitorConfig pl455Config(int devices, int cells) {
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

struct Rig {
  explicit Rig(int devices = 2, int cells = 16, uint64_t seed = 7, double noise_V = 0.0)
      : chain(withNoise(pl455Config(devices, cells), noise_V), devices * cells, seed) {
    for (int d = 0; d < devices; ++d)
      for (int c = 0; c < cells; ++c) chain.analog(d).cell_V[static_cast<size_t>(c)] = 3.5003 + 0.01 * c + 0.2 * d;
  }
  // One transaction at t; returns the reply bytes (empty on a timeout).
  std::vector<uint8_t> send(const std::vector<uint8_t>& tx, size_t rxLen = 0) {
    chain.advance(t);
    std::vector<uint8_t> rx(rxLen);
    last = chain.transfer(t, tx.data(), tx.size(), rx.data(), rxLen);
    t += last.duration_s;
    rx.resize(static_cast<size_t>(std::max(0, last.received)));
    return rx;
  }
  static MonitorConfig withNoise(MonitorConfig c, double noise_V) {
    c.cell_adc.noise_rms = noise_V;
    return c;
  }
  void writeAll(uint8_t reg, std::vector<uint8_t> data) { send(frame(PL455_REQ_BROADCAST_NR, -1, reg, data)); }
  void write(int d, uint8_t reg, std::vector<uint8_t> data) { send(frame(PL455_REQ_SINGLE_NR, d, reg, data)); }
  std::vector<uint8_t> read(int d, uint8_t reg, int count) {
    return send(frame(PL455_REQ_SINGLE_R, d, reg, {static_cast<uint8_t>(count - 1)}), static_cast<size_t>(count) + 3);
  }
  uint16_t read16(int d, uint8_t reg) {
    const auto r = read(d, reg, 2);
    return r.size() == 5 ? static_cast<uint16_t>((r[1] << 8) | r[2]) : 0xDEAD;
  }
  void autoAddress() {
    writeAll(PL455_REG_DEVCONFIG, {PL455_DEVCONFIG_ADDR_SEL | PL455_DEVCONFIG_COMP_ENA});
    writeAll(PL455_REG_DEV_CTRL, {PL455_DEV_CTRL_AUTO_ADDRESS});
    for (int d = 0; d < chain.deviceCount(); ++d) writeAll(PL455_REG_ADDR, {static_cast<uint8_t>(d)});
  }
  void wait(double dt) {
    t += dt;
    chain.advance(t);
  }

  Bq76pl455aChain chain;
  double t = 0.0;
  BusTransfer last;
};

bool replyValid(const std::vector<uint8_t>& r) {
  if (r.size() < 4 || (r[0] & 0x80) != 0 || r[0] + 4u != r.size()) return false;
  const uint16_t crc = bitSerialCrc16(std::vector<uint8_t>(r.begin(), r.end() - 2));
  return r[r.size() - 2] == (crc & 0xFF) && r[r.size() - 1] == (crc >> 8);
}

TEST(Bq76pl455a, BitSerialCrcHasTheCrc16ArcCheckValue) {
  const std::vector<uint8_t> check{'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(bitSerialCrc16(check), 0xBB3D);  // the catalogued check value of CRC-16/ARC
}

TEST(Bq76pl455a, DevicesAnswerSingleRequestsOnlyAfterAutoAddressing) {
  Rig r(3, 16);
  EXPECT_TRUE(r.read(0, PL455_REG_ADDR, 2).empty());
  EXPECT_EQ(r.last.received, -1);
  r.autoAddress();
  for (int d = 0; d < 3; ++d) {
    const auto rep = r.read(d, PL455_REG_ADDR, 2);
    ASSERT_TRUE(replyValid(rep)) << d;
    EXPECT_EQ(rep[0], 1);  // two data bytes
    EXPECT_EQ(rep[1], d);  // the bottom device took the first address
  }
  // A broadcast read with response: every device answers, the top one first.
  const auto all = r.send(frame(PL455_REQ_BROADCAST_R, -1, PL455_REG_ADDR, {0}), 12);
  ASSERT_EQ(all.size(), 12u);
  for (int k = 0; k < 3; ++k) {
    const std::vector<uint8_t> one(all.begin() + 4 * k, all.begin() + 4 * k + 4);
    EXPECT_TRUE(replyValid(one));
    EXPECT_EQ(one[1], 2 - k);
  }
}

TEST(Bq76pl455a, AcceptsFramesAsPublishedForThePart) {
  // Command frames as published in TI's support forum for this part (auto-addressing
  // one device, clearing its faults, reading STATUS): an independent check of the
  // frame layout and the CRC byte order.
  Rig r(1, 16);
  r.send({0xF1, 0x0E, 0x10, 0x54, 0x5F});              // DEVCONFIG = 0x10, broadcast
  r.send({0xF1, 0x0C, 0x08, 0x55, 0x35});              // DEV_CTRL: auto-address
  r.send({0xF1, 0x0A, 0x00, 0x57, 0x53});              // ADDR = 0
  r.send({0x92, 0x00, 0x52, 0xFF, 0xC0, 0x59, 0xAC});  // FAULT_SUM: clear all, device 0
  const auto status = r.send({0x81, 0x00, 0x51, 0x00, 0x15, 0xAC}, 4);  // read STATUS
  ASSERT_EQ(status.size(), 4u);
  EXPECT_TRUE(replyValid(status));
  EXPECT_EQ(r.read16(0, PL455_REG_FAULT_COM), 0);  // no frame was dropped for its CRC
  EXPECT_EQ(r.read(0, PL455_REG_ADDR, 2)[1], 0);
}

TEST(Bq76pl455a, RegistersReadBackWritesAndIgnoreReadOnlyOnes) {
  Rig r;
  r.autoAddress();
  r.write(1, PL455_REG_COMP_UV, {0x40, 0x80});  // COMP_UV and COMP_OV in one frame
  EXPECT_EQ(r.read16(1, PL455_REG_COMP_UV), 0x4080);
  EXPECT_NE(r.read16(0, PL455_REG_COMP_UV), 0x4080);  // only device 1 was addressed
  const auto srev = r.read(0, PL455_REG_SREV, 2);
  r.write(0, PL455_REG_SREV, {0x55});
  EXPECT_EQ(r.read(0, PL455_REG_SREV, 2), srev);
  // The EEPROM image carries the scenario's thresholds: COV 4.30 V, CUV 2.80 V.
  EXPECT_EQ(r.read(0, PL455_REG_COMP_OV, 2)[1], ((4300 - PL455_COMP_OV_BASE_MV) / 25) << 1);
  EXPECT_EQ(r.read(0, PL455_REG_COMP_UV, 2)[1], ((2800 - PL455_COMP_UV_BASE_MV) / 25) << 1);
}

TEST(Bq76pl455a, AFrameWithAWrongCrcIsDroppedAndFlagged) {
  Rig r;
  r.autoAddress();
  const uint16_t before = r.read16(0, PL455_REG_CELL_OV);
  auto bad = frame(PL455_REQ_SINGLE_NR, 0, PL455_REG_CELL_OV, {0x12, 0x34});
  bad.back() ^= 0x01;
  r.send(bad);
  EXPECT_EQ(r.read16(0, PL455_REG_CELL_OV), before);
  EXPECT_NE(r.read16(0, PL455_REG_FAULT_SUM) & PL455_FAULT_SUM_COMM, 0);
  EXPECT_NE(r.read16(0, PL455_REG_FAULT_COM) & PL455_FAULT_COM_UART_CRC, 0);
  auto badRead = frame(PL455_REQ_SINGLE_R, 0, PL455_REG_ADDR, {1});
  badRead[2] ^= 0x10;
  EXPECT_TRUE(r.send(badRead, 5).empty());
  EXPECT_EQ(r.last.received, -1);
}

TEST(Bq76pl455a, IgnoredWritesAreNotedOncePerDeviceRegisterAndReason) {
  Rig r;  // two devices
  r.autoAddress();
  r.write(1, PL455_REG_COMP_UV, {0x40, 0x80});
  r.writeAll(PL455_REG_FAULT_SUM, {0xFF, 0xC0});  // clear-on-one: legal
  EXPECT_TRUE(r.chain.misuse().entries().empty());
  r.write(0, PL455_REG_SREV, {0x55});
  r.write(0, PL455_REG_SREV, {0x56});
  r.write(1, PL455_REG_EE_BURN, {PL455_EE_BURN_GO});  // no keys
  auto bad = frame(PL455_REQ_SINGLE_NR, 0, PL455_REG_CELL_OV, {0x12, 0x34});
  bad.back() ^= 0x01;
  r.send(bad);  // every device that heard it drops it
  const std::vector<RegisterMisuse>& m = r.chain.misuse().entries();
  ASSERT_EQ(m.size(), 4u);
  EXPECT_EQ(m[0].device, 0);
  EXPECT_EQ(m[0].what, "SREV");
  EXPECT_EQ(m[0].count, 2);
  EXPECT_EQ(m[1].device, 1);
  EXPECT_EQ(m[1].what, "EE_BURN");
  EXPECT_NE(m[1].why.find("MAGIC"), std::string::npos);
  EXPECT_EQ(m[2].device, 0);
  EXPECT_EQ(m[2].what, "CELL_OV");
  EXPECT_NE(m[2].why.find("bad CRC"), std::string::npos);
  EXPECT_EQ(m[3].device, 1);
  EXPECT_EQ(m[3].what, "CELL_OV");
}

TEST(Bq76pl455a, EepromBurnIsRefusedWithoutTheKeysAndKeptWithThem) {
  Rig r(1, 16);
  r.autoAddress();
  const uint16_t factory = r.read16(0, PL455_REG_CELL_OV);
  auto resetAndRead = [&] {
    r.writeAll(PL455_REG_DEV_CTRL, {PL455_DEV_CTRL_RESET});
    r.autoAddress();
    return r.read16(0, PL455_REG_CELL_OV);
  };
  r.write(0, PL455_REG_CELL_OV, {0xD0, 0x00});
  r.write(0, PL455_REG_EE_BURN, {PL455_EE_BURN_GO});
  EXPECT_EQ(resetAndRead(), factory);  // refused: the reset reloads the old image
  r.write(0, PL455_REG_CELL_OV, {0xD0, 0x00});
  r.write(0, PL455_REG_MAGIC1, {0x8C, 0x2D, 0xB4, 0x94});
  r.write(0, PL455_REG_MAGIC2, {0xA5, 0x4B, 0x2C, 0x53});
  r.write(0, PL455_REG_EE_BURN, {PL455_EE_BURN_GO});
  EXPECT_EQ(resetAndRead(), 0xD000);
}

TEST(Bq76pl455a, SixteenCellSampleIs35BytesAndTakesItsConversionTime) {
  Rig r(1, 16);
  r.autoAddress();
  r.write(0, PL455_REG_CHANNELS, {0xFF, 0xFF, 0x00, 0x00});
  const double t0 = r.t;
  const auto rep = r.send(frame(PL455_REQ_SINGLE_R, 0, PL455_REG_CMD, {PL455_CMD_SAMPLE}), 35);
  ASSERT_EQ(rep.size(), 35u);
  EXPECT_TRUE(replyValid(rep));
  EXPECT_EQ(rep[0], 31);
  for (int c = 0; c < 16; ++c) {  // cell 16 first; noiseless: code = round(V / LSB)
    const uint16_t code = static_cast<uint16_t>((rep[1 + 2 * (15 - c)] << 8) | rep[2 + 2 * (15 - c)]);
    EXPECT_EQ(code, std::lround((3.5003 + 0.01 * c) / (5.0 / 65535.0))) << c;
  }
  // 6 command bytes, 16 channels x 100 us, 35 reply bytes at 10 bits / 250 kbaud.
  EXPECT_NEAR(r.t - t0, 6 * 40e-6 + 16 * 100e-6 + 35 * 40e-6, 1e-12);
  // Oversampling 4: four conversions per channel.
  r.write(0, PL455_REG_OVERSMPL, {2});
  const double t1 = r.t;
  r.send(frame(PL455_REQ_SINGLE_R, 0, PL455_REG_CMD, {PL455_CMD_SAMPLE}), 35);
  EXPECT_NEAR(r.t - t1, 6 * 40e-6 + 4 * 16 * 100e-6 + 35 * 40e-6, 1e-12);
}

TEST(Bq76pl455a, ReadingBeforeTheConversionEndsGivesTheOldResultAndNoDataReady) {
  Rig r(1, 16);
  r.autoAddress();
  r.write(0, PL455_REG_CHANNELS, {0xFF, 0xFF, 0x00, 0x00});  // 16 cells: 1.6 ms
  r.writeAll(PL455_REG_CMD, {PL455_CMD_SAMPLE});
  auto sendHeld = [&] {  // cell 1 comes last
    const auto rep = r.send(frame(PL455_REQ_SINGLE_R, 0, PL455_REG_CMD, {PL455_CMD_SEND_HELD}), 35);
    return rep.size() == 35 ? (rep[31] << 8) | rep[32] : -1;
  };
  EXPECT_EQ(r.read(0, PL455_REG_STATUS, 2)[1] & PL455_STATUS_DRDY, 0);
  // Nothing was ever converted: the held result is empty.
  EXPECT_TRUE(r.send(frame(PL455_REQ_SINGLE_R, 0, PL455_REG_CMD, {PL455_CMD_SEND_HELD}), 35).empty());
  r.wait(1.6e-3);
  EXPECT_NE(r.read(0, PL455_REG_STATUS, 2)[1] & PL455_STATUS_DRDY, 0);
  const int first = sendHeld();
  EXPECT_EQ(first, std::lround(3.5003 / (5.0 / 65535.0)));
  // The cell moves; a new sample is read too early: old code, data-ready clear.
  r.chain.analog(0).cell_V[0] = 3.7003;
  r.writeAll(PL455_REG_CMD, {PL455_CMD_SAMPLE});
  EXPECT_EQ(r.read(0, PL455_REG_STATUS, 2)[1] & PL455_STATUS_DRDY, 0);
  EXPECT_EQ(sendHeld(), first);
  r.wait(1.6e-3);
  EXPECT_EQ(sendHeld(), std::lround(3.7003 / (5.0 / 65535.0)));
}

TEST(Bq76pl455a, AdcThresholdsLatchUvOvOnASample) {
  Rig r(1, 16);
  r.autoAddress();
  r.write(0, PL455_REG_CHANNELS, {0xFF, 0xFF, 0x00, 0x00});
  r.chain.analog(0).cell_V[4] = 4.31;  // over COV 4.30 V at the ADC, cell 5
  r.send(frame(PL455_REQ_SINGLE_R, 0, PL455_REG_CMD, {PL455_CMD_SAMPLE}), 35);
  EXPECT_EQ(r.read16(0, PL455_REG_FAULT_OV), 1u << 4);
  EXPECT_NE(r.read16(0, PL455_REG_FAULT_SUM) & PL455_FAULT_SUM_OV, 0);
  EXPECT_FALSE(r.chain.faultLine());  // FO_CTRL: only the comparators and AUX drive FAULT
  r.writeAll(PL455_REG_FAULT_SUM, {0x40, 0x00});
  EXPECT_EQ(r.read16(0, PL455_REG_FAULT_OV), 0);
}

TEST(Bq76pl455a, ComparatorFaultLatchesAfterItsDelayAndClearsOnlyOnceGone) {
  Rig r(2, 16);
  r.autoAddress();
  r.chain.analog(1).cell_V[3] = 4.32;  // over COMP_OV 4.30 V
  r.wait(0.0);                          // the comparator sees it from now
  r.wait(0.99);
  EXPECT_FALSE(r.chain.faultLine());
  r.wait(0.02);  // held 1.01 s > 1.0 s delay
  EXPECT_TRUE(r.chain.faultLine());
  EXPECT_EQ(r.read16(1, PL455_REG_FAULT_2OV), 1u << 3);
  EXPECT_NE(r.read16(1, PL455_REG_FAULT_SUM) & PL455_FAULT_SUM_CMPOV, 0);
  EXPECT_EQ(r.read16(0, PL455_REG_FAULT_SUM), 0);
  r.writeAll(PL455_REG_FAULT_SUM, {0xFF, 0xC0});  // condition still present: stays
  EXPECT_TRUE(r.chain.faultLine());
  r.chain.analog(1).cell_V[3] = 4.2;
  r.wait(0.01);
  EXPECT_TRUE(r.chain.faultLine());  // latched after the condition went
  r.writeAll(PL455_REG_FAULT_SUM, {0xFF, 0xC0});
  EXPECT_FALSE(r.chain.faultLine());
  EXPECT_EQ(r.read16(1, PL455_REG_FAULT_2OV), 0);
}

TEST(Bq76pl455a, HotOrShortedThermistorLatchesAuxFault) {
  Rig r(1, 16);
  r.autoAddress();
  r.chain.analog(0).therm_C[1] = 64.5;
  r.wait(2.0);
  EXPECT_FALSE(r.chain.faultLine());
  r.chain.analog(0).therm_C[1] = 65.5;
  r.wait(0.0);
  r.wait(0.98);
  EXPECT_FALSE(r.chain.faultLine());
  r.wait(0.03);
  EXPECT_TRUE(r.chain.faultLine());
  EXPECT_EQ(r.read16(0, PL455_REG_FAULT_AUX), PL455_FAULT_AUX_UV(1));
  EXPECT_NE(r.read16(0, PL455_REG_FAULT_SUM) & PL455_FAULT_SUM_AUXUV, 0);
  r.chain.analog(0).therm_C[1] = 25.0;
  r.wait(0.01);
  r.writeAll(PL455_REG_FAULT_SUM, {0x20, 0x00});
  EXPECT_FALSE(r.chain.faultLine());
  r.chain.analog(0).therm_fault[0] = ThermistorFault::Short;
  r.wait(0.0);
  r.wait(1.01);
  EXPECT_EQ(r.read16(0, PL455_REG_FAULT_AUX), PL455_FAULT_AUX_UV(0));
}

// The chain's own protection against its settings: driven on a 10 ms step, the FAULT
// line rises one comparator delay (1 s) after the first step on which the condition
// holds - a cell past COMP_OV / COMP_UV, an NTC hotter than the AUX threshold (its
// exact code), a shorted NTC (code 0 reads hot).
struct Drive {
  int cell = -1;       // series position ramped, or -1
  double v0 = 0, dv_per_s = 0;
  int therm = -1;      // thermistor channel ramped, or -1
  double T0 = 25, dT_per_s = 0;
  bool shortTherm = false;
  double expected_s = 0;  // first step of the condition + 1 s
};

double tripTime(Bq76pl455aChain& chain, const Drive& drv) {
  const int devices = 2, cells = 16;
  for (int k = 0; k < 2000; ++k) {
    const double t = 0.01 * k;
    for (int d = 0; d < devices; ++d)
      for (int c = 0; c < cells; ++c) {
        const int pos = d * cells + c;
        chain.analog(d).cell_V[static_cast<size_t>(c)] = pos == drv.cell ? drv.v0 + drv.dv_per_s * t : 3.7;
      }
    for (int ch = 0; ch < devices * 2; ++ch) {
      const double T = ch == drv.therm ? drv.T0 + drv.dT_per_s * t : 25.0;
      const bool shorted = drv.shortTherm && ch == drv.therm && t >= 2.0;
      chain.analog(ch / 2).therm_C[static_cast<size_t>(ch % 2)] = T;
      chain.analog(ch / 2).therm_fault[static_cast<size_t>(ch % 2)] = shorted ? ThermistorFault::Short : ThermistorFault::None;
    }
    chain.advance(t);
    if (chain.faultLine()) return t;
  }
  return -1.0;
}

TEST(Bq76pl455a, OwnProtectionTripsOneComparatorDelayAfterTheCondition) {
  const std::vector<Drive> drives = {
      {20, 4.28, 0.013, -1, 25, 0, false, 1.54 + 1.0},    // COV 4.30 V: 4.28 + 0.013 t > 4.30 from 1.54 s
      {3, 2.83, -0.021, -1, 25, 0, false, 1.43 + 1.0},    // CUV 2.80 V: from 1.43 s
      {-1, 0, 0, 3, 63.0, 0.17, false, 11.77 + 1.0},      // OT 65 degC on device 1, input 1: from 11.77 s
      {-1, 0, 0, 0, 25.0, 0.0, true, 2.0 + 1.0},          // a shorted NTC looks hot: from 2.0 s
  };
  for (size_t i = 0; i < drives.size(); ++i) {
    Bq76pl455aChain chain(pl455Config(2, 16), 32, 5);
    EXPECT_NEAR(tripTime(chain, drives[i]), drives[i].expected_s, 0.005) << i;
  }
}

TEST(Bq76pl455a, GroupRequestsReachTheDevicesOfThatGroup) {
  Rig r(3, 16);
  r.autoAddress();
  r.write(1, PL455_REG_GROUP_ID, {5});
  r.write(2, PL455_REG_GROUP_ID, {5});
  r.send(frame(PL455_REQ_GROUP_NR, 5, PL455_REG_COMP_UV, {0x22}));
  EXPECT_NE(r.read(0, PL455_REG_COMP_UV, 2)[1], 0x22);
  EXPECT_EQ(r.read(1, PL455_REG_COMP_UV, 2)[1], 0x22);
  EXPECT_EQ(r.read(2, PL455_REG_COMP_UV, 2)[1], 0x22);
  const auto both = r.send(frame(PL455_REQ_GROUP_R, 5, PL455_REG_ADDR, {1}), 10);
  ASSERT_EQ(both.size(), 10u);
  EXPECT_EQ(both[1], 2);  // the top one first
  EXPECT_EQ(both[6], 1);
}

TEST(Bq76pl455a, ChannelErrorsAreDrawnFromTheSeed) {
  MonitorConfig c = pl455Config(2, 16);
  c.channel_gain_sd = 2e-3;
  c.channel_offset_sd_V = 1e-3;
  const Bq76pl455aChain chain(c, 32, 21), same(c, 32, 21), other(c, 32, 22);
  double sumSq = 0.0;
  for (int k = 0; k < 32; ++k) {
    EXPECT_EQ(chain.channelGain(k), same.channelGain(k));
    EXPECT_EQ(chain.channelOffset_V(k), same.channelOffset_V(k));
    EXPECT_NE(chain.channelGain(k), other.channelGain(k));
    sumSq += chain.channelGain(k) * chain.channelGain(k);
  }
  EXPECT_NE(chain.channelGain(0), chain.channelGain(1));
  // 32 draws of sd 2e-3: the sample sd within a factor 1.6 (chi-square 32 dof, p < 0.01 each side).
  const double sd = std::sqrt(sumSq / 32.0);
  EXPECT_GT(sd, 2e-3 / 1.6);
  EXPECT_LT(sd, 2e-3 * 1.6);
}

TEST(Bq76pl455a, OversamplingAveragesTheConversionNoise) {
  // cell_adc.noise_rms is the noise at MonitorConfig::oversampling (1 here); OVERSMPL = 2
  // averages 4 samples: the spread of the codes halves.
  auto spread = [](uint8_t log2) {
    Rig r(1, 16, 99, 2e-3);
    for (int k = 0; k < 16; ++k) r.chain.analog(0).cell_V[static_cast<size_t>(k)] = 3.6;
    r.autoAddress();
    r.write(0, PL455_REG_CHANNELS, {0xFF, 0xFF, 0x00, 0x00});
    r.write(0, PL455_REG_OVERSMPL, {log2});
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int k = 0; k < 40; ++k) {
      const auto rep = r.send(frame(PL455_REQ_SINGLE_R, 0, PL455_REG_CMD, {PL455_CMD_SAMPLE}), 35);
      for (int i = 0; i < 16; ++i) {
        const double v = ((rep[1 + 2 * i] << 8) | rep[2 + 2 * i]) * (5.0 / 65535.0) - 3.6;
        sum += v, sum2 += v * v, ++n;
      }
    }
    return std::sqrt(sum2 / n - (sum / n) * (sum / n));
  };
  const double one = spread(0), four = spread(2);
  EXPECT_NEAR(one, 2e-3, 0.2e-3);  // 640 samples: the estimate is within 10 %
  EXPECT_NEAR(four, 1e-3, 0.1e-3);
}

TEST(Bq76pl455a, BalancingStopsOnTheDeviceWhenItsTimeRunsOut) {
  Rig r(1, 16);
  r.autoAddress();
  r.write(0, PL455_REG_CBCONFIG, {2u << PL455_CBCONFIG_TIME_SHIFT});  // 1 min
  r.write(0, PL455_REG_CBENBL, {0x80, 0x05});                          // cells 1, 3, 16
  EXPECT_TRUE(r.chain.balancing(0, 0));
  EXPECT_TRUE(r.chain.balancing(0, 15));
  EXPECT_FALSE(r.chain.balancing(0, 1));
  EXPECT_EQ(r.chain.balancingMask(0), 0x8005u);  // the same switches at once
  r.wait(59.9);
  EXPECT_TRUE(r.chain.balancing(0, 2));
  r.wait(0.2);
  EXPECT_FALSE(r.chain.balancing(0, 2));
  EXPECT_EQ(r.chain.balancingMask(0), 0u);
  EXPECT_EQ(r.read16(0, PL455_REG_CBENBL), 0);
}

// The link supervision (CTO) trips once no valid frame was heard for its time: at the
// first advance where t - heard >= timeout, as the plain comparison says, however many
// advances came between (the chain skips its devices until something may be due).
TEST(Bq76pl455a, LinkSupervisionTripsWhenNoValidFrameWasHeardForItsTime) {
  const double byte_s = PL455_UART_BITS_PER_BYTE / 250000.0;
  const std::vector<uint8_t> cto = frame(PL455_REQ_BROADCAST_NR, -1, PL455_REG_CTO, {1});  // 100 ms
  const std::vector<uint8_t> read = frame(PL455_REQ_SINGLE_R, 0, PL455_REG_FAULT_SYS, {0});
  int trips = 0;
  for (const double after_s : {0.1 - 1e-9, 0.1 - 1e-12, 0.1, 0.1 + 1e-9, 0.25}) {
    Rig r(1, 16);
    r.autoAddress();
    const double heard_s = r.t + static_cast<double>(cto.size()) * byte_s;  // once its last byte is in
    r.send(cto);
    for (int k = 1; k <= 9; ++k) r.wait(heard_s + 0.01 * k - r.t);  // a tick's advances, no frame
    // The read acts (and the chain advances) once its own last byte is in.
    r.wait(heard_s + after_s - static_cast<double>(read.size()) * byte_s - r.t);
    const double readAt_s = r.t + static_cast<double>(read.size()) * byte_s;
    const bool tripped = readAt_s - heard_s >= 100 * 1e-3 - 1e-12;
    const std::vector<uint8_t> got = r.send(read, 4);
    ASSERT_EQ(got.size(), 4u);
    EXPECT_EQ(got[1] & PL455_FAULT_SYS_CTO, tripped ? PL455_FAULT_SYS_CTO : 0u) << "after " << after_s << " s";
    trips += tripped ? 1 : 0;
  }
  EXPECT_GT(trips, 0);  // both sides of the edge were asked
  EXPECT_LT(trips, 5);
}

// The switch mask is each cell's switch, on a device with fewer cells than CBENBL bits
// (a write above its cells does not switch anything).
TEST(Bq76pl455a, TheSwitchMaskIsEachCellsSwitch) {
  Rig r(2, 10);
  r.autoAddress();
  r.write(0, PL455_REG_CBCONFIG, {2u << PL455_CBCONFIG_TIME_SHIFT});
  r.write(1, PL455_REG_CBCONFIG, {2u << PL455_CBCONFIG_TIME_SHIFT});
  r.write(0, PL455_REG_CBENBL, {0xFF, 0x21});  // cells 1 and 6, and bits above its 10 cells
  r.write(1, PL455_REG_CBENBL, {0x02, 0x00});  // cell 10
  for (int d = 0; d < 2; ++d) {
    uint32_t perCell = 0;
    for (int c = 0; c < r.chain.cellsOf(d); ++c) perCell |= r.chain.balancing(d, c) ? 1u << c : 0u;
    EXPECT_EQ(r.chain.balancingMask(d), perCell) << d;
  }
  EXPECT_EQ(r.chain.balancingMask(0), 0x321u);
  EXPECT_EQ(r.chain.balancingMask(1), 0x200u);
}

// CBENBL bits above a device's cells (a 10-cell device: bits 11-16) switch nothing, and
// the write is noted as any other the part ignores: once per device and bits, naming
// them and its cell count.
TEST(Bq76pl455a, BalancingBitsForCellsADeviceDoesNotHaveAreNoted) {
  Rig r(2, 10);
  r.autoAddress();
  r.writeAll(PL455_REG_CBCONFIG, {2u << PL455_CBCONFIG_TIME_SHIFT});
  r.write(1, PL455_REG_CBENBL, {0x02, 0x01});  // cells 1 and 10: legal
  EXPECT_TRUE(r.chain.misuse().entries().empty());
  r.write(0, PL455_REG_CBENBL, {0xFF, 0x21});
  r.write(0, PL455_REG_CBENBL, {0xFF, 0x21});
  EXPECT_EQ(r.chain.balancingMask(0), 0x321u);
  const std::vector<RegisterMisuse>& m = r.chain.misuse().entries();
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].device, 0);
  EXPECT_EQ(m[0].what, "CBENBL");
  EXPECT_EQ(m[0].why, "balancing bits 0xFC00 (cells 11-16) for cells the device does not have (it has 10): ignored, "
                      "those switches stay off");
  EXPECT_EQ(m[0].count, 2);
}

// A sample reply carries the selected slots, the highest first, whatever the selection;
// an MCU that takes fewer bytes than the chain sends gets the first of them, across the
// replies of several devices (the top one's first).
TEST(Bq76pl455a, SparseSelectionsAndShortReceiveBuffersGetTheBytesInChainOrder) {
  auto sample = [](size_t rxLen) {
    Rig r(2, 16);
    r.autoAddress();
    r.chain.analog(0).therm_C = {30.0, 40.0};
    r.chain.analog(1).therm_C = {35.0, 45.0};
    // cells 1, 3 and 16, the module, AUX0 and AUX1, the die
    const uint32_t ch = PL455_CH_CELL(1) | PL455_CH_CELL(3) | PL455_CH_CELL(16) | PL455_CH_MODULE | PL455_CH_AUX(0) |
                        PL455_CH_AUX(1) | PL455_CH_DIE_TEMP;
    r.writeAll(PL455_REG_CHANNELS, {static_cast<uint8_t>(ch >> 24), static_cast<uint8_t>(ch >> 16),
                                    static_cast<uint8_t>(ch >> 8), static_cast<uint8_t>(ch)});
    return r.send(frame(PL455_REQ_BROADCAST_R, -1, PL455_REG_CMD, {PL455_CMD_SAMPLE}), rxLen);
  };
  const std::vector<uint8_t> all = sample(2 * 17);
  ASSERT_EQ(all.size(), 2u * 17u);  // per device: header, 7 channels x 2, CRC
  for (int dev = 0; dev < 2; ++dev) {
    const std::vector<uint8_t> one(all.begin() + 17 * dev, all.begin() + 17 * (dev + 1));
    EXPECT_TRUE(replyValid(one)) << dev;
    const int d = 1 - dev;  // the top device answers first
    auto code = [&](int i) { return (one[1 + 2 * i] << 8) | one[2 + 2 * i]; };
    const double lsb = 5.0 / 65535.0;
    EXPECT_EQ(code(0), std::lround((3.5003 + 0.01 * 15 + 0.2 * d) / lsb));  // cell 16 (slot 31)
    EXPECT_EQ(code(1), std::lround((3.5003 + 0.01 * 2 + 0.2 * d) / lsb));   // cell 3
    EXPECT_EQ(code(2), std::lround((3.5003 + 0.2 * d) / lsb));              // cell 1 (slot 16)
    Rng unused(0);
    EXPECT_EQ(code(3), Thermistor{}.code(d == 0 ? 40.0 : 45.0, unused));    // AUX1 (slot 9)
    EXPECT_EQ(code(4), Thermistor{}.code(d == 0 ? 30.0 : 35.0, unused));    // AUX0 (slot 8)
    EXPECT_EQ(code(5), 250);                                                // die 25.0 °C (slot 7)
    double module_V = 0.0;
    for (int c = 0; c < 16; ++c) module_V += 3.5003 + 0.01 * c + 0.2 * d;
    EXPECT_NEAR(code(6), module_V / (100.0 / 65535.0), 0.5);                // the module (slot 6)
  }
  for (size_t n : {size_t{1}, size_t{7}, size_t{17}, size_t{18}, size_t{33}}) {
    const std::vector<uint8_t> part = sample(n);
    EXPECT_EQ(part, std::vector<uint8_t>(all.begin(), all.begin() + static_cast<long>(n))) << n;
  }
}

// The comparators skip their pass while nothing is over, under or hot; a condition that
// appears after any stretch of that still latches exactly one delay after it appeared,
// and one that goes and comes back starts its delay again.
TEST(Bq76pl455a, AConditionAfterALongQuietStretchLatchesOneDelayAfterItAppears) {
  Rig r(1, 16);
  r.autoAddress();
  for (int k = 0; k < 1000; ++k) r.wait(0.01);  // 10 s with nothing present
  EXPECT_FALSE(r.chain.faultLine());
  r.chain.analog(0).cell_V[5] = 2.7;  // under COMP_UV 2.80 V (1 s)
  r.wait(0.5);
  const double appeared = r.t;
  r.wait(0.8);
  EXPECT_FALSE(r.chain.faultLine());
  r.chain.analog(0).cell_V[5] = 3.5;  // gone before its delay: the timer rests
  for (int k = 0; k < 100; ++k) r.wait(0.01);
  r.chain.analog(0).cell_V[5] = 2.7;  // back: a new second from here
  r.wait(0.0);
  EXPECT_GT(r.t - appeared, 1.0);
  r.wait(0.99);
  EXPECT_FALSE(r.chain.faultLine());
  r.wait(0.02);
  EXPECT_TRUE(r.chain.faultLine());
  EXPECT_EQ(r.read16(0, PL455_REG_FAULT_2UV), 1u << 5);
}

TEST(Bq76pl455a, CommFaultsActOnTheBytes) {
  Rig r(3, 16);
  r.autoAddress();
  r.chain.setCommFault(1, MonitorDeviceFault{true, 0.0, -1});
  EXPECT_TRUE(r.read(1, PL455_REG_ADDR, 2).empty());
  EXPECT_FALSE(r.read(2, PL455_REG_ADDR, 2).empty());
  r.write(1, PL455_REG_COMP_UV, {0x10});  // a silent device does not take writes
  r.chain.setCommFault(1, MonitorDeviceFault{});
  EXPECT_NE(r.read(1, PL455_REG_COMP_UV, 2)[1], 0x10);
  r.chain.setBrokenLinkAbove(0);
  EXPECT_FALSE(r.read(0, PL455_REG_ADDR, 2).empty());
  EXPECT_TRUE(r.read(1, PL455_REG_ADDR, 2).empty());
  EXPECT_TRUE(r.read(2, PL455_REG_ADDR, 2).empty());
  r.chain.setBrokenLinkAbove(-1);
  for (int stuck : {0x00, 0xFF}) {
    r.chain.setCommFault(2, MonitorDeviceFault{false, 0.0, stuck});
    const auto rep = r.read(2, PL455_REG_ADDR, 2);
    ASSERT_EQ(rep.size(), 5u);
    for (uint8_t b : rep) EXPECT_EQ(b, stuck);
    EXPECT_FALSE(replyValid(rep));
  }
  r.chain.setCommFault(2, MonitorDeviceFault{false, 1.0, -1});
  const auto flipped = r.read(2, PL455_REG_ADDR, 2);
  ASSERT_EQ(flipped.size(), 5u);
  EXPECT_FALSE(replyValid(flipped));  // one bit flipped: the CRC no longer matches
}

TEST(Bq76pl455a, TransactionTimeFollowsTheBaudRateAndTheTimeout) {
  Rig r(2, 16);
  r.autoAddress();
  r.read(0, PL455_REG_FAULT_SUM, 2);  // 6 bytes out, 5 bytes back at 40 us each
  EXPECT_NEAR(r.last.duration_s, 11 * 40e-6, 1e-12);
  r.chain.setCommFault(1, MonitorDeviceFault{true, 0.0, -1});
  r.read(1, PL455_REG_FAULT_SUM, 2);  // nothing back: the MCU waits out its timeout
  EXPECT_NEAR(r.last.duration_s, 6 * 40e-6 + Bq76pl455aChain::kResponseTimeout_s, 1e-12);
}

// The sample's SSE4.1 build (its rounding roundsd, where the CPU has it) and the plain one
// answer the same bytes: noisy and noiseless cells across many codes (ties included),
// the module, the die temperature, every channel selected.
TEST(Bq76pl455a, TheSamplesSse41BuildAnswersAsThePlainOne) {
  auto run = [](bool native, double noise_V) {
    const bool was = useNativeRounding(native);
    Rig r(2, 16, 5, noise_V);
    r.autoAddress();
    r.writeAll(PL455_REG_CHANNELS, {0xFF, 0xFF, 0xFF, 0xFF});
    std::vector<uint8_t> all;
    const double lsb = 5.0 / 65535.0;
    for (int k = 0; k < 200; ++k) {
      for (int d = 0; d < 2; ++d) {
        DeviceAnalog& a = r.chain.analog(d);
        for (size_t c = 0; c < a.cell_V.size(); ++c)  // half codes (ties) and codes between
          a.cell_V[c] = ((k * 11 + static_cast<int>(c) * 97 + d * 31) % 60000 + (k % 2 ? 0.5 : 0.29)) * lsb;
        a.die_C = 20.0 + 0.05 * k + (k % 3 ? 0.005 : 0.0);  // tenths of a degree: ties too
      }
      for (int d = 0; d < 2; ++d) {
        const std::vector<uint8_t> rep = r.send(frame(PL455_REQ_SINGLE_R, d, PL455_REG_CMD, {PL455_CMD_SAMPLE}), 80);
        all.insert(all.end(), rep.begin(), rep.end());
      }
      r.wait(0.01);
    }
    useNativeRounding(was);
    return all;
  };
  for (double noise_V : {0.0, 0.5e-3}) {
    const std::vector<uint8_t> plain = run(false, noise_V);
    EXPECT_EQ(run(true, noise_V), plain) << "noise " << noise_V;
    EXPECT_GT(plain.size(), 200u * 2u * 35u);
  }
}

TEST(Bq76pl455a, SameSeedGivesTheSameBytes) {
  auto run = [](uint64_t seed) {
    MonitorConfig c = pl455Config(2, 16);
    c.cell_adc.noise_rms = 0.5e-3;
    c.channel_gain_sd = 1e-3;
    Bq76pl455aChain chain(c, 32, seed);
    for (int d = 0; d < 2; ++d)
      for (int k = 0; k < 16; ++k) chain.analog(d).cell_V[static_cast<size_t>(k)] = 3.6;
    chain.setCommFault(1, MonitorDeviceFault{false, 0.5, -1});
    std::vector<uint8_t> all;
    double t = 0.0;
    auto send = [&](const std::vector<uint8_t>& tx, size_t n) {
      std::vector<uint8_t> rx(n);
      const BusTransfer b = chain.transfer(t, tx.data(), tx.size(), rx.data(), n);
      t += b.duration_s;
      all.insert(all.end(), rx.begin(), rx.end());
    };
    send(frame(PL455_REQ_BROADCAST_NR, -1, PL455_REG_DEV_CTRL, {PL455_DEV_CTRL_AUTO_ADDRESS}), 0);
    send(frame(PL455_REQ_BROADCAST_NR, -1, PL455_REG_ADDR, {0}), 0);
    send(frame(PL455_REQ_BROADCAST_NR, -1, PL455_REG_ADDR, {1}), 0);
    send(frame(PL455_REQ_BROADCAST_NR, -1, PL455_REG_CHANNELS, {0xFF, 0xFF, 0, 0}), 0);
    for (int k = 0; k < 5; ++k)
      for (int d = 0; d < 2; ++d) send(frame(PL455_REQ_SINGLE_R, d, PL455_REG_CMD, {0}), 35);
    return all;
  };
  EXPECT_EQ(run(11), run(11));
  EXPECT_NE(run(11), run(12));
}

}  // namespace
}  // namespace packsim
