// The BQ76PL536A stack model against the part's datasheet behaviour, frame by frame:
// addressing, broadcast, reads and writes, protected writes, CRC, conversion time,
// the secondary comparators and their latches, the balancing timer, comm faults.
#include "models/afe/bq76pl536a.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace packsim {
namespace {

// Bit-serial CRC-8 (x^8 + x^2 + x + 1, initial 0), written from the polynomial alone.
uint8_t crc8BitSerial(const std::vector<uint8_t>& bytes) {
  uint8_t crc = 0;
  for (uint8_t byte : bytes)
    for (int bit = 7; bit >= 0; --bit) {
      const bool in = ((byte >> bit) & 1u) != 0;
      const bool top = (crc & 0x80u) != 0;
      crc = static_cast<uint8_t>(crc << 1);
      if (in != top) crc ^= 0x07u;
    }
  return crc;
}

constexpr double kLsb_V = 6.25 / 16383.0;

MonitorConfig config(int devices) {
  MonitorConfig c;
  c.devices = devices;
  c.cells_per_device = 6;
  c.thermistors_per_device = 2;
  c.cell_adc.lsb = kLsb_V;
  c.cell_adc.code_max = 16383;
  return c;
}

struct Bus {
  Bq76pl536aChain& chain;
  double t = 0.0;
  BusTransfer last;

  void write(uint8_t addr, uint8_t reg, uint8_t value, bool goodCrc = true) {
    std::vector<uint8_t> f = {static_cast<uint8_t>(addr * 2 + 1), reg, value};
    f.push_back(static_cast<uint8_t>(crc8BitSerial(f) ^ (goodCrc ? 0 : 0x01)));
    last = chain.transfer(t, f.data(), f.size(), nullptr, 0);
  }
  // Data bytes of a read (without the CRC); empty on timeout. Checks the reply CRC.
  std::vector<uint8_t> read(uint8_t addr, uint8_t reg, uint8_t count, bool* crcOk = nullptr) {
    const uint8_t tx[3] = {static_cast<uint8_t>(addr * 2), reg, count};
    std::vector<uint8_t> rx(count + 1u, 0);
    last = chain.transfer(t, tx, 3, rx.data(), rx.size());
    if (last.received < 0) return {};
    std::vector<uint8_t> all(tx, tx + 3);
    all.insert(all.end(), rx.begin(), rx.begin() + count);
    const bool ok = crc8BitSerial(all) == rx[count];
    if (crcOk) *crcOk = ok;
    else EXPECT_TRUE(ok) << "reply CRC";
    rx.resize(count);
    return rx;
  }
  uint8_t reg(uint8_t addr, uint8_t r) {
    const std::vector<uint8_t> v = read(addr, r, 1);
    return v.empty() ? 0xEE : v[0];
  }
  void addressAll(int n) {
    write(BQ536_ADDR_BROADCAST, BQ536_RESET, BQ536_RESET_KEY);
    for (int d = 0; d < n; ++d) write(0, BQ536_ADDRESS_CONTROL, static_cast<uint8_t>(d + 1));
  }
  void protectedWrite(uint8_t addr, uint8_t r, uint8_t v) {
    write(addr, BQ536_SHDW_CTRL, BQ536_SHDW_KEY);
    write(addr, r, v);
  }
};

uint16_t be16(const std::vector<uint8_t>& v, size_t i) { return static_cast<uint16_t>((v[i] << 8) | v[i + 1]); }

TEST(Bq76pl536a, PowerUpStateAndEepromFromTheSecondaryConfig) {
  Bq76pl536aChain chain(config(1), 6, 1);
  Bus bus{chain};
  // Unaddressed: answers address 0; POR and AR latched; no address assigned.
  EXPECT_EQ(bus.reg(0, BQ536_FAULT_STATUS), BQ536_FS_POR);
  EXPECT_EQ(bus.reg(0, BQ536_ALERT_STATUS), BQ536_AS_AR);
  EXPECT_EQ(bus.reg(0, BQ536_DEVICE_STATUS), BQ536_DS_FAULT | BQ536_DS_ALERT);
  // CONFIG from MonitorConfig::secondary in datasheet steps: COV 4.35 V = 2.0 + 47·50 mV,
  // 1 s = 10 × 100 ms; CUV 2.5 V = 0.7 + 18·0.1 V; OT 65 °C = 35 + 6·5 on both inputs;
  // OTT 1 s = 100 × 10 ms.
  const std::vector<uint8_t> cfg = bus.read(0, BQ536_CONFIG_COV, 6);
  const std::vector<uint8_t> want = {47, 0x80 | 10, 18, 0x80 | 10, 0x66, 100};
  EXPECT_EQ(cfg, want);
  // The housekeeping latches do not drive the FAULT line.
  EXPECT_FALSE(chain.faultLine());
}

TEST(Bq76pl536a, AutoAddressingBottomUpAndBroadcast) {
  Bq76pl536aChain chain(config(3), 18, 1);
  Bus bus{chain};
  bus.write(0, BQ536_ADDRESS_CONTROL, 1);
  EXPECT_EQ(bus.reg(1, BQ536_ADDRESS_CONTROL), 0x81);
  EXPECT_NE(bus.reg(1, BQ536_DEVICE_STATUS) & BQ536_DS_ADDR_RQST, 0);
  // The next device up now answers address 0; the third is behind it (no address yet).
  EXPECT_EQ(bus.reg(0, BQ536_ADDRESS_CONTROL), 0x00);
  bus.write(0, BQ536_ADDRESS_CONTROL, 2);
  bus.write(0, BQ536_ADDRESS_CONTROL, 3);
  EXPECT_EQ(bus.reg(2, BQ536_ADDRESS_CONTROL), 0x82);
  EXPECT_EQ(bus.reg(3, BQ536_ADDRESS_CONTROL), 0x83);
  EXPECT_TRUE(bus.read(0, BQ536_ADDRESS_CONTROL, 1).empty());  // nobody is unaddressed
  // Broadcast writes reach every device; a broadcast read gets no answer.
  bus.write(BQ536_ADDR_BROADCAST, BQ536_IO_CONTROL, BQ536_IO_TS1 | BQ536_IO_TS2);
  for (int d = 0; d < 3; ++d) EXPECT_EQ(chain.peek(d, BQ536_IO_CONTROL), 3);
  EXPECT_TRUE(bus.read(BQ536_ADDR_BROADCAST, BQ536_IO_CONTROL, 1).empty());
  EXPECT_EQ(bus.last.received, -1);
  // A write to one address reaches only that device.
  bus.write(2, BQ536_IO_CONTROL, 0);
  EXPECT_EQ(chain.peek(0, BQ536_IO_CONTROL), 3);
  EXPECT_EQ(chain.peek(1, BQ536_IO_CONTROL), 0);
  // A broadcast RESET puts every device back to address 0 with POR set.
  bus.write(BQ536_ADDR_BROADCAST, BQ536_RESET, BQ536_RESET_KEY);
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(chain.peek(d, BQ536_ADDRESS_CONTROL), 0);
    EXPECT_EQ(chain.peek(d, BQ536_FAULT_STATUS), BQ536_FS_POR);
    EXPECT_EQ(chain.peek(d, BQ536_IO_CONTROL), 0);
  }
  // A wrong key is not a reset.
  bus.addressAll(3);
  bus.write(BQ536_ADDR_BROADCAST, BQ536_RESET, 0x5A);
  EXPECT_EQ(chain.peek(2, BQ536_ADDRESS_CONTROL), 0x83);
}

TEST(Bq76pl536a, ReplyCrcCoversTheWholeExchangeAndBadWriteCrcIsRejected) {
  Bq76pl536aChain chain(config(2), 12, 1);
  Bus bus{chain};
  bus.addressAll(2);
  bool ok = false;
  for (uint8_t reg : {BQ536_DEVICE_STATUS, BQ536_ALERT_STATUS, BQ536_CONFIG_COV}) {
    bus.read(2, reg, 4, &ok);
    EXPECT_TRUE(ok);
    EXPECT_EQ(bus.last.received, 5);
  }
  // A write with a wrong CRC changes nothing and flags CRC in FAULT_STATUS.
  bus.write(1, BQ536_IO_CONTROL, 3, /*goodCrc=*/false);
  EXPECT_EQ(chain.peek(0, BQ536_IO_CONTROL), 0);
  EXPECT_NE(chain.peek(0, BQ536_FAULT_STATUS) & BQ536_FS_CRC, 0);
  EXPECT_EQ(chain.peek(1, BQ536_FAULT_STATUS) & BQ536_FS_CRC, 0);
  // ... cleared by writing 1 then 0.
  bus.write(1, BQ536_FAULT_STATUS, BQ536_FS_CRC | BQ536_FS_POR);
  bus.write(1, BQ536_FAULT_STATUS, 0);
  EXPECT_EQ(chain.peek(0, BQ536_FAULT_STATUS), 0);
  EXPECT_EQ(chain.peek(0, BQ536_DEVICE_STATUS) & BQ536_DS_FAULT, 0);
}

TEST(Bq76pl536a, ProtectedRegistersTakeOneWriteAfterTheShadowKey) {
  Bq76pl536aChain chain(config(1), 6, 1);
  Bus bus{chain};
  bus.addressAll(1);
  bus.write(1, BQ536_CONFIG_COV, 40);  // no key: refused
  EXPECT_EQ(bus.reg(1, BQ536_CONFIG_COV), 47);
  bus.protectedWrite(1, BQ536_CONFIG_COV, 40);
  EXPECT_EQ(bus.reg(1, BQ536_CONFIG_COV), 40);
  bus.write(1, BQ536_CONFIG_COV, 41);  // the key was used up
  EXPECT_EQ(bus.reg(1, BQ536_CONFIG_COV), 40);
  bus.write(1, BQ536_SHDW_CTRL, BQ536_SHDW_KEY);
  bus.write(1, BQ536_IO_CONTROL, 0);  // any other write closes it
  bus.write(1, BQ536_CONFIG_OTT, 5);
  EXPECT_EQ(bus.reg(1, BQ536_CONFIG_OTT), 100);
  bus.write(1, BQ536_SHDW_CTRL, 0x34);  // wrong key
  bus.write(1, BQ536_CONFIG_OTT, 5);
  EXPECT_EQ(bus.reg(1, BQ536_CONFIG_OTT), 100);
  // Read-only results ignore writes.
  bus.write(1, BQ536_VCELL1, 0x12);
  EXPECT_EQ(bus.reg(1, BQ536_VCELL1), 0);
}

TEST(Bq76pl536a, IgnoredWritesAreNotedOncePerDeviceRegisterAndReason) {
  Bq76pl536aChain chain(config(2), 12, 1);
  Bus bus{chain};
  bus.addressAll(2);
  bus.protectedWrite(1, BQ536_CONFIG_COV, 0x30);  // legal: key, then the write
  bus.write(BQ536_ADDR_BROADCAST, BQ536_CB_CTRL, 0x00);
  EXPECT_TRUE(chain.misuse().entries().empty());
  // Device 2: a read-only register twice, a protected one without the key, a reset
  // without its key; device 1: a write with a bad CRC; both: a reserved register.
  const uint8_t cov = bus.reg(2, BQ536_CONFIG_COV);
  bus.write(2, BQ536_VCELL1 + 2, 0x00);
  bus.write(2, BQ536_VCELL1 + 2, 0x01);
  bus.write(2, BQ536_CONFIG_COV, 0x10);
  EXPECT_EQ(bus.reg(2, BQ536_CONFIG_COV), cov);  // still refused
  bus.write(2, BQ536_RESET, 0x00);
  bus.write(1, BQ536_CB_CTRL, 0x01, /*goodCrc=*/false);
  EXPECT_EQ(bus.reg(1, BQ536_CB_CTRL), 0);
  bus.write(BQ536_ADDR_BROADCAST, 0x2A, 0x55);
  const std::vector<RegisterMisuse>& m = chain.misuse().entries();
  ASSERT_EQ(m.size(), 6u);
  EXPECT_EQ(m[0].device, 1);
  EXPECT_EQ(m[0].what, "VCELL2");
  EXPECT_EQ(m[0].count, 2);
  EXPECT_EQ(m[1].what, "CONFIG_COV");
  EXPECT_NE(m[1].why.find("SHDW_CTRL"), std::string::npos);
  EXPECT_EQ(m[2].what, "RESET");
  EXPECT_EQ(m[3].device, 0);
  EXPECT_EQ(m[3].what, "CB_CTRL");
  EXPECT_NE(m[3].why.find("bad CRC"), std::string::npos);
  EXPECT_EQ(m[4].device, 0);
  EXPECT_EQ(m[4].what, "register 0x2A");
  EXPECT_EQ(m[5].device, 1);
  EXPECT_EQ(m[5].what, "register 0x2A");
}

TEST(Bq76pl536a, ConversionTakesItsTimeAndDataReadyFollows) {
  MonitorConfig cfg = config(1);
  Bq76pl536aChain chain(cfg, 5, 1);  // 5 cells on a 6-cell part
  const double cells_V[5] = {3.1, 3.25, 3.4, 3.55, 4.1};
  for (int c = 0; c < 5; ++c) chain.analog(0).cell_V[static_cast<size_t>(c)] = cells_V[c];
  chain.analog(0).therm_C = {30.0, 45.0};
  Bus bus{chain};
  bus.addressAll(1);
  bus.write(1, BQ536_IO_CONTROL, BQ536_IO_TS1 | BQ536_IO_TS2);
  bus.write(1, BQ536_ADC_CONTROL, BQ536_AC_ADC_ON | BQ536_AC_GPAI | BQ536_AC_TS1 | BQ536_AC_TS2 | 5);
  bus.t = 1.0;
  chain.advance(bus.t);
  bus.write(1, BQ536_ADC_CONVERT, BQ536_CONV_START);
  const double start = 1.0 + bus.last.duration_s;  // the command acts at the end of its frame
  // 9 channels (GPAI, 6 cells, 2 TS) × 6 µs: before that, DRDY clear and old results (0).
  bus.t = start + 53e-6;
  std::vector<uint8_t> v = bus.read(1, BQ536_RESULTS_FIRST, BQ536_RESULTS_LEN);
  EXPECT_EQ(v[0] & BQ536_DS_DRDY, 0);
  EXPECT_EQ(be16(v, BQ536_VCELL1), 0);
  bus.t = start + 54e-6;
  v = bus.read(1, BQ536_RESULTS_FIRST, BQ536_RESULTS_LEN);
  EXPECT_NE(v[0] & BQ536_DS_DRDY, 0);
  double sum = 0.0;
  for (int c = 0; c < 5; ++c) {
    EXPECT_EQ(be16(v, BQ536_VCELL(c)), std::lround(cells_V[c] / kLsb_V)) << c;
    sum += cells_V[c];
  }
  EXPECT_EQ(be16(v, BQ536_VCELL(5)), 0);  // unpopulated input
  EXPECT_EQ(be16(v, BQ536_GPAI), std::lround(sum / (6 * kLsb_V)));
  Rng unused(0);
  EXPECT_EQ(be16(v, BQ536_TEMPERATURE1), cfg.thermistor.code(30.0, unused));
  EXPECT_EQ(be16(v, BQ536_TEMPERATURE2), cfg.thermistor.code(45.0, unused));
  // Without the divider bias a thermistor input reads 0; a shorter CELL_SEL converts
  // fewer cells and leaves the others' results as they were.
  chain.analog(0).cell_V[0] = 3.0;
  chain.analog(0).cell_V[4] = 3.0;
  bus.write(1, BQ536_IO_CONTROL, BQ536_IO_TS1);
  bus.write(1, BQ536_ADC_CONTROL, BQ536_AC_TS1 | BQ536_AC_TS2 | 1);  // cells 1-2, TS1, TS2: 4 channels
  bus.t = 2.0;
  bus.write(1, BQ536_ADC_CONVERT, BQ536_CONV_START);
  bus.t = 2.0 + bus.last.duration_s + 24e-6;
  v = bus.read(1, BQ536_RESULTS_FIRST, BQ536_RESULTS_LEN);
  EXPECT_NE(v[0] & BQ536_DS_DRDY, 0);
  EXPECT_EQ(be16(v, BQ536_VCELL1), std::lround(3.0 / kLsb_V));
  EXPECT_EQ(be16(v, BQ536_VCELL(4)), std::lround(4.1 / kLsb_V));
  EXPECT_EQ(be16(v, BQ536_TEMPERATURE1), cfg.thermistor.code(30.0, unused));
  EXPECT_EQ(be16(v, BQ536_TEMPERATURE2), 0);
}

TEST(Bq76pl536a, CovLatchesAfterItsDelayAndClearsOnlyWhenGone) {
  Bq76pl536aChain chain(config(1), 6, 1);
  Bus bus{chain};
  bus.addressAll(1);
  bus.write(1, BQ536_FAULT_STATUS, BQ536_FS_POR);
  bus.write(1, BQ536_FAULT_STATUS, 0);
  for (double& v : chain.analog(0).cell_V) v = 3.7;
  chain.advance(0.0);
  chain.analog(0).cell_V[2] = 4.36;  // above 4.35 V
  chain.advance(10.0);
  chain.advance(10.99);
  EXPECT_FALSE(chain.faultLine());
  EXPECT_EQ(chain.faultCause(), "");
  chain.advance(11.0);  // held for the programmed 1 s
  EXPECT_TRUE(chain.faultLine());
  EXPECT_EQ(chain.faultCause(), "device 1: COV (cell over-voltage)");
  bus.t = 11.0;
  EXPECT_EQ(bus.reg(1, BQ536_FAULT_STATUS), BQ536_FS_COV);
  EXPECT_EQ(bus.reg(1, BQ536_COV_FAULT), 0x04);
  EXPECT_NE(bus.reg(1, BQ536_DEVICE_STATUS) & BQ536_DS_FAULT, 0);
  // Still over: 1 then 0 does not clear it.
  bus.write(1, BQ536_FAULT_STATUS, BQ536_FS_COV);
  bus.write(1, BQ536_FAULT_STATUS, 0);
  EXPECT_EQ(bus.reg(1, BQ536_FAULT_STATUS), BQ536_FS_COV);
  // Gone: a write of 0 alone does not clear it; 1 then 0 does.
  chain.analog(0).cell_V[2] = 4.2;
  chain.advance(12.0);
  EXPECT_TRUE(chain.faultLine());
  bus.write(1, BQ536_FAULT_STATUS, 0);
  EXPECT_EQ(bus.reg(1, BQ536_FAULT_STATUS), BQ536_FS_COV);
  bus.write(1, BQ536_FAULT_STATUS, BQ536_FS_COV);
  bus.write(1, BQ536_FAULT_STATUS, 0);
  EXPECT_EQ(bus.reg(1, BQ536_FAULT_STATUS), 0);
  EXPECT_EQ(bus.reg(1, BQ536_COV_FAULT), 0);
  EXPECT_FALSE(chain.faultLine());
}

TEST(Bq76pl536a, CuvDelayInMicrosecondStepsAfterReprogramming) {
  Bq76pl536aChain chain(config(1), 6, 1);
  Bus bus{chain};
  bus.addressAll(1);
  bus.protectedWrite(1, BQ536_CONFIG_CUV, 23);  // 0.7 + 2.3 = 3.0 V
  bus.protectedWrite(1, BQ536_CONFIG_CUVT, 5);  // 5 × 100 µs
  for (double& v : chain.analog(0).cell_V) v = 3.05;
  chain.advance(0.0);
  chain.analog(0).cell_V[5] = 2.95;
  chain.advance(1.0);
  chain.advance(1.0 + 400e-6);
  EXPECT_FALSE(chain.faultLine());
  chain.advance(1.0 + 500e-6);
  EXPECT_TRUE(chain.faultLine());
  EXPECT_EQ(chain.peek(0, BQ536_CUV_FAULT), 0x20);
  // Disabled comparator: never trips.
  Bq76pl536aChain off(config(1), 6, 1);
  Bus b2{off};
  b2.addressAll(1);
  b2.protectedWrite(1, BQ536_CONFIG_CUV, BQ536_CONFIG_DISABLE | 23);
  for (double& v : off.analog(0).cell_V) v = 1.0;
  off.advance(0.0);
  off.advance(10.0);
  EXPECT_FALSE(off.faultLine());
}

TEST(Bq76pl536a, OverTemperatureAlertFromEitherInput) {
  MonitorConfig cfg = config(1);
  Bq76pl536aChain chain(cfg, 6, 1);
  for (double& v : chain.analog(0).cell_V) v = 3.7;
  chain.analog(0).therm_C = {25.0, 66.0};  // OT2 over 65 °C
  chain.advance(0.0);
  chain.advance(0.99);
  EXPECT_FALSE(chain.faultLine());
  chain.advance(1.0);
  EXPECT_TRUE(chain.faultLine());
  EXPECT_EQ(chain.peek(0, BQ536_ALERT_STATUS), BQ536_AS_AR | BQ536_AS_OT2);
  // A shorted NTC looks hot, an open one cold.
  Bq76pl536aChain shorted(cfg, 6, 1), open(cfg, 6, 1);
  shorted.analog(0).therm_fault[0] = ThermistorFault::Short;
  open.analog(0).therm_fault[0] = ThermistorFault::Open;
  open.analog(0).therm_C[0] = 100.0;
  for (auto* c : {&shorted, &open}) {
    for (double& v : c->analog(0).cell_V) v = 3.7;
    c->advance(0.0);
    c->advance(2.0);
  }
  EXPECT_TRUE(shorted.faultLine());
  EXPECT_FALSE(open.faultLine());
  // secondary.enabled = false: the EEPROM holds the comparators off.
  cfg.secondary.enabled = false;
  Bq76pl536aChain disabled(cfg, 6, 1);
  disabled.analog(0).therm_C = {99.0, 99.0};
  for (double& v : disabled.analog(0).cell_V) v = 4.9;
  disabled.advance(0.0);
  disabled.advance(5.0);
  EXPECT_FALSE(disabled.faultLine());
}

// With every comparator off the chain skips them while its pins change tick by tick
// (they see nothing whatever the inputs); one switched on by a protected write sees the
// pins as they are from then on, as a chain that looked at every tick does.
TEST(Bq76pl536a, AComparatorSwitchedOnAfterAStretchWithAllOffSeesThePinsAtOnce) {
  MonitorConfig cfg = config(1);
  cfg.secondary.enabled = false;
  Bq76pl536aChain chain(cfg, 6, 1);
  Bus bus{chain};
  bus.addressAll(1);
  auto tick = [&](double t, double v) {  // the pins filled, as the sensors do each tick
    for (double& c : chain.analog(0).cell_V) c = v;
    chain.analog(0).therm_C = {99.0, 99.0};
    chain.advance(t);
  };
  for (int k = 0; k <= 100; ++k) tick(k * 0.01, 3.0 + 0.02 * k);  // up to 5.0 V, 99 °C: nothing
  EXPECT_FALSE(chain.faultLine());
  bus.t = 1.0;
  bus.protectedWrite(1, BQ536_CONFIG_COVT, 5);  // 500 µs
  bus.protectedWrite(1, BQ536_CONFIG_COV, bq536_cov_code(4350));  // on, at 4.35 V
  chain.advance(1.0);  // the pins unchanged since the last tick (5.0 V): over from here
  chain.advance(1.0 + 400e-6);
  EXPECT_FALSE(chain.faultLine());
  chain.advance(1.0 + 500e-6);
  EXPECT_TRUE(chain.faultLine());
  EXPECT_EQ(chain.peek(0, BQ536_COV_FAULT), 0x3F);
  EXPECT_EQ(chain.peek(0, BQ536_ALERT_STATUS) & (BQ536_AS_OT1 | BQ536_AS_OT2), 0);  // OT still off
  // From now on each tick's pins count: gone, cleared, over again.
  tick(2.0, 4.2);
  bus.t = 2.0;
  bus.write(1, BQ536_FAULT_STATUS, BQ536_FS_COV);
  bus.write(1, BQ536_FAULT_STATUS, 0);
  EXPECT_FALSE(chain.faultLine());
  tick(3.0, 4.4);
  chain.advance(3.0 + 400e-6);
  EXPECT_FALSE(chain.faultLine());
  chain.advance(3.0 + 500e-6);
  EXPECT_TRUE(chain.faultLine());
  // An over-temperature threshold written later (input 2 only, 65 °C, 100 ms) takes
  // effect as written: the 99 °C input trips, the other stays off.
  bus.t = 4.0;
  bus.protectedWrite(1, BQ536_CONFIG_OTT, 10);
  bus.protectedWrite(1, BQ536_CONFIG_OT, static_cast<uint8_t>(bq536_ot_code(65) << 4));
  tick(4.0, 4.2);
  tick(4.09, 4.2);
  EXPECT_EQ(chain.peek(0, BQ536_ALERT_STATUS) & (BQ536_AS_OT1 | BQ536_AS_OT2), 0);
  tick(4.1, 4.2);
  EXPECT_EQ(chain.peek(0, BQ536_ALERT_STATUS) & (BQ536_AS_OT1 | BQ536_AS_OT2), BQ536_AS_OT2);
}

// A device with fewer cells than its six inputs (the top one of an 11s stack: 5 cells)
// ignores the balancing bits of the cells it does not have, and the run says so like any
// other ignored write: one entry per device and bits, naming them and its cell count.
TEST(Bq76pl536a, BalancingBitsForCellsADeviceDoesNotHaveAreNoted) {
  Bq76pl536aChain chain(config(2), 11, 1);
  Bus bus{chain};
  bus.addressAll(2);
  bus.write(1, BQ536_CB_TIME, 2);
  bus.write(2, BQ536_CB_TIME, 2);
  bus.write(2, BQ536_CB_CTRL, 0x1F);  // its five cells: legal
  EXPECT_TRUE(chain.misuse().entries().empty());
  bus.write(2, BQ536_CB_CTRL, 0x3F);
  bus.write(2, BQ536_CB_CTRL, 0x3F);
  EXPECT_EQ(bus.reg(2, BQ536_CB_CTRL), 0x1F);  // still ignored
  EXPECT_FALSE(chain.balancing(1, 5));
  bus.write(BQ536_ADDR_BROADCAST, BQ536_CB_CTRL, 0xFF);
  EXPECT_EQ(bus.reg(1, BQ536_CB_CTRL), 0x3F);
  const std::vector<RegisterMisuse>& m = chain.misuse().entries();
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0].device, 1);
  EXPECT_EQ(m[0].what, "CB_CTRL");
  EXPECT_EQ(m[0].why, "balancing bits 0x20 (cell 6) for cells the device does not have (it has 5): ignored, those "
                      "switches stay off");
  EXPECT_EQ(m[0].count, 2);
  EXPECT_EQ(m[1].device, 0);  // the broadcast: each device its own bits
  EXPECT_EQ(m[1].why.rfind("balancing bits 0xC0 (cells 7-8) for cells the device does not have (it has 6)", 0), 0u)
      << m[1].why;
  EXPECT_EQ(m[2].device, 1);
  EXPECT_EQ(m[2].why.rfind("balancing bits 0xE0 (cells 6-8) for cells the device does not have (it has 5)", 0), 0u)
      << m[2].why;
}

TEST(Bq76pl536a, BalancingTimerExpiresOnTheDevice) {
  Bq76pl536aChain chain(config(1), 6, 1);
  Bus bus{chain};
  bus.addressAll(1);
  bus.t = 10.0;
  bus.write(1, BQ536_CB_TIME, 2);  // 2 s
  bus.write(1, BQ536_CB_CTRL, 0x05);
  const double on = 10.0 + bus.last.duration_s;  // switched on at the end of the frame
  EXPECT_TRUE(chain.balancing(0, 0));
  EXPECT_FALSE(chain.balancing(0, 1));
  EXPECT_TRUE(chain.balancing(0, 2));
  EXPECT_NE(bus.reg(1, BQ536_DEVICE_STATUS) & BQ536_DS_CBT, 0);
  chain.advance(on + 1.9);
  EXPECT_TRUE(chain.balancing(0, 0));
  chain.advance(on + 2.0);
  EXPECT_FALSE(chain.balancing(0, 0));
  bus.t = on + 2.0;
  EXPECT_EQ(bus.reg(1, BQ536_CB_CTRL), 0);
  EXPECT_EQ(bus.reg(1, BQ536_DEVICE_STATUS) & BQ536_DS_CBT, 0);
  // Minute units: 0x80 | 1 = 60 s.
  bus.write(1, BQ536_CB_TIME, BQ536_CBT_MINUTES | 1);
  bus.write(1, BQ536_CB_CTRL, 0x20);
  const double on2 = bus.t + bus.last.duration_s;
  chain.advance(on2 + 59.9);
  EXPECT_TRUE(chain.balancing(0, 5));
  chain.advance(on2 + 60.0);
  EXPECT_FALSE(chain.balancing(0, 5));
}

// The per-tick shortcuts answer as the register file does, byte for byte: a read of any
// span (past 0x4F it reads 0) gives what peek() gives register by register,
// DEVICE_STATUS (composed when read) included, through conversions, balancing, a latched
// fault and a reset; the switch mask is the per-cell switches.
TEST(Bq76pl536a, ReadsOfAnySpanMatchTheRegisterFileAndTheSwitchMaskTheSwitches) {
  Bq76pl536aChain chain(config(2), 11, 3);  // the top device has 5 cells
  for (double& v : chain.analog(0).cell_V) v = 3.7;
  for (double& v : chain.analog(1).cell_V) v = 3.6;
  Bus bus{chain};
  bus.addressAll(2);
  auto expectReadsMatch = [&](const char* when) {
    for (uint8_t addr = 1; addr <= 2; ++addr)
      for (int first : {0, 1, 2, 0x10, 0x3F, 0x4E, 0x4F, 0x50, 0xF0})
        for (int count : {1, 2, 19, 0x50, 0xFF}) {
          const std::vector<uint8_t> v = bus.read(addr, static_cast<uint8_t>(first), static_cast<uint8_t>(count));
          ASSERT_EQ(v.size(), static_cast<size_t>(count)) << when;
          for (int i = 0; i < count; ++i) {
            const int r = first + i;
            const uint8_t expected = r < static_cast<int>(BQ536_REGISTER_COUNT) ? chain.peek(addr - 1, static_cast<uint8_t>(r)) : 0;
            ASSERT_EQ(v[static_cast<size_t>(i)], expected) << when << ": device " << int(addr) << " register " << r;
          }
        }
    for (int d = 0; d < 2; ++d) {
      uint32_t perCell = 0;
      for (int c = 0; c < chain.cellsOf(d); ++c) perCell |= chain.balancing(d, c) ? 1u << c : 0u;
      EXPECT_EQ(chain.balancingMask(d), perCell) << when << ": device " << d;
    }
  };
  auto statusOf = [&](int d) {  // the datasheet's bits from what they report
    uint8_t s = 0;
    if (chain.peek(d, BQ536_CB_CTRL) != 0) s |= BQ536_DS_CBT;
    if (chain.peek(d, BQ536_ALERT_STATUS) != 0) s |= BQ536_DS_ALERT;
    if (chain.peek(d, BQ536_FAULT_STATUS) != 0) s |= BQ536_DS_FAULT;
    if (chain.peek(d, BQ536_ADDRESS_CONTROL) & BQ536_ADDR_ASSIGNED) s |= BQ536_DS_ADDR_RQST;
    return s;
  };
  expectReadsMatch("addressed");
  EXPECT_EQ(chain.peek(0, BQ536_DEVICE_STATUS), statusOf(0));  // no conversion yet: no DRDY
  bus.write(BQ536_ADDR_BROADCAST, BQ536_ADC_CONTROL, BQ536_AC_ADC_ON | BQ536_AC_GPAI | 5);
  bus.t = 1.0;
  bus.write(BQ536_ADDR_BROADCAST, BQ536_ADC_CONVERT, BQ536_CONV_START);
  expectReadsMatch("converting");
  EXPECT_EQ(chain.peek(1, BQ536_DEVICE_STATUS), statusOf(1));
  bus.t = 1.1;
  chain.advance(bus.t);
  expectReadsMatch("converted");
  EXPECT_EQ(chain.peek(1, BQ536_DEVICE_STATUS), statusOf(1) | BQ536_DS_DRDY);
  bus.write(2, BQ536_CB_TIME, 2);
  bus.write(2, BQ536_CB_CTRL, 0xFF);  // masked to the device's 5 cells
  bus.write(1, BQ536_CB_CTRL, 0x09);
  expectReadsMatch("balancing");
  EXPECT_EQ(chain.balancingMask(1), 0x1Fu);
  EXPECT_EQ(chain.peek(1, BQ536_DEVICE_STATUS), statusOf(1) | BQ536_DS_DRDY);
  chain.analog(0).cell_V[3] = 4.5;  // over: COV latches after its 1 s
  bus.t = 2.0;
  chain.advance(bus.t);
  bus.t = 3.5;
  chain.advance(bus.t);
  ASSERT_TRUE(chain.faultLine());
  expectReadsMatch("latched");
  EXPECT_NE(chain.peek(0, BQ536_DEVICE_STATUS) & BQ536_DS_FAULT, 0);
  bus.write(BQ536_ADDR_BROADCAST, BQ536_RESET, BQ536_RESET_KEY);
  EXPECT_EQ(chain.peek(0, BQ536_DEVICE_STATUS), BQ536_DS_FAULT | BQ536_DS_ALERT);  // POR, AR; no address
  bus.addressAll(2);
  expectReadsMatch("reset and addressed again");
  EXPECT_EQ(chain.peek(0, BQ536_DEVICE_STATUS), statusOf(0));
}

// The comparators skip their pass while nothing is over, under or hot; a condition that
// appears after any stretch of that still latches exactly one delay after it appeared,
// and one that goes away and comes back starts its delay again.
TEST(Bq76pl536a, AConditionAfterALongQuietStretchLatchesOneDelayAfterItAppears) {
  Bq76pl536aChain chain(config(1), 6, 1);
  for (double& v : chain.analog(0).cell_V) v = 3.7;
  for (int k = 0; k <= 1000; ++k) chain.advance(k * 0.01);  // 10 s with nothing present
  EXPECT_FALSE(chain.faultLine());
  chain.analog(0).cell_V[1] = 4.4;  // over COV (4.35 V, 1 s)
  chain.advance(10.5);
  chain.advance(11.49);
  EXPECT_FALSE(chain.faultLine());
  chain.analog(0).cell_V[1] = 3.7;  // gone before its delay: the timer rests
  for (int k = 0; k < 100; ++k) chain.advance(11.5 + k * 0.01);
  chain.analog(0).cell_V[1] = 4.4;  // back: a new second from here
  chain.advance(13.0);
  chain.advance(13.99);
  EXPECT_FALSE(chain.faultLine());
  chain.advance(14.0);
  EXPECT_TRUE(chain.faultLine());
  EXPECT_EQ(chain.peek(0, BQ536_COV_FAULT), 0x02);
}

TEST(Bq76pl536a, CommFaultsActOnTheBytes) {
  Bq76pl536aChain chain(config(3), 18, 1);
  Bus bus{chain};
  bus.addressAll(3);
  const std::vector<uint8_t> clean = bus.read(2, BQ536_CONFIG_COV, 6);
  // Silent: no reply, and writes do not reach it.
  chain.setCommFault(1, MonitorDeviceFault{true, 0.0, -1});
  EXPECT_TRUE(bus.read(2, BQ536_CONFIG_COV, 6).empty());
  EXPECT_EQ(bus.last.received, -1);
  bus.write(2, BQ536_IO_CONTROL, 3);
  EXPECT_EQ(chain.peek(1, BQ536_IO_CONTROL), 0);
  EXPECT_EQ(bus.read(3, BQ536_CONFIG_COV, 6), clean);  // the others still answer
  // Stuck: every reply byte reads the stuck value.
  for (int stuck : {0x00, 0xFF}) {
    chain.setCommFault(1, MonitorDeviceFault{false, 0.0, stuck});
    const uint8_t tx[3] = {BQ536_FRAME_READ(2), BQ536_CONFIG_COV, 6};
    uint8_t rx[7];
    EXPECT_EQ(chain.transfer(0.0, tx, 3, rx, 7).received, 7);
    for (uint8_t b : rx) EXPECT_EQ(b, stuck);
  }
  // CRC errors: exactly one bit of the reply flipped, at that rate.
  chain.setCommFault(1, MonitorDeviceFault{false, 1.0, -1});
  bool ok = true;
  const std::vector<uint8_t> hit = bus.read(2, BQ536_CONFIG_COV, 6, &ok);
  int flipped = 0;
  for (size_t i = 0; i < clean.size(); ++i) flipped += __builtin_popcount(clean[i] ^ hit[i]);
  EXPECT_LE(flipped, 1);  // the bit may be in the CRC byte instead
  EXPECT_FALSE(ok);
  // Broken link above device 0: devices 1 and 2 neither answer nor take writes.
  chain.setCommFault(1, MonitorDeviceFault{});
  chain.setBrokenLinkAbove(0);
  EXPECT_FALSE(bus.read(1, BQ536_CONFIG_COV, 6).empty());
  EXPECT_TRUE(bus.read(2, BQ536_CONFIG_COV, 6).empty());
  EXPECT_TRUE(bus.read(3, BQ536_CONFIG_COV, 6).empty());
  bus.write(BQ536_ADDR_BROADCAST, BQ536_IO_CONTROL, 1);
  EXPECT_EQ(chain.peek(0, BQ536_IO_CONTROL), 1);
  EXPECT_EQ(chain.peek(2, BQ536_IO_CONTROL), 0);
}

TEST(Bq76pl536a, TransactionTimeFollowsTheSpiClock) {
  MonitorConfig cfg = config(1);
  cfg.baud = 1e6;
  Bq76pl536aChain chain(cfg, 6, 1);
  Bus bus{chain};
  bus.read(0, BQ536_RESULTS_FIRST, BQ536_RESULTS_LEN);
  EXPECT_DOUBLE_EQ(bus.last.duration_s, (3 + BQ536_RESULTS_LEN + 1) * 8 / 1e6);
  bus.write(0, BQ536_IO_CONTROL, 0);
  EXPECT_DOUBLE_EQ(bus.last.duration_s, 4 * 8 / 1e6);
}

// A two-device stack addressed and set to convert every cell and both thermistors (once,
// at its first call), its cells set to cellV(device, cell), one conversion, and both
// devices' result registers appended to `all`.
template <class CellV>
void convertAndRead(Bus& bus, Bq76pl536aChain& chain, CellV cellV, std::vector<uint8_t>& all) {
  if (bus.t == 0.0) {
    bus.addressAll(2);
    bus.write(BQ536_ADDR_BROADCAST, BQ536_IO_CONTROL, 3);
    bus.write(BQ536_ADDR_BROADCAST, BQ536_ADC_CONTROL, 0x3D);
  }
  for (int d = 0; d < 2; ++d) {
    std::vector<double>& v = chain.analog(d).cell_V;
    for (size_t i = 0; i < v.size(); ++i) v[i] = cellV(d, i);
  }
  bus.t += 0.1;
  bus.write(BQ536_ADDR_BROADCAST, BQ536_ADC_CONVERT, 1);
  bus.t += 1e-3;
  for (uint8_t a = 1; a <= 2; ++a) {
    const std::vector<uint8_t> v = bus.read(a, BQ536_RESULTS_FIRST, BQ536_RESULTS_LEN);
    all.insert(all.end(), v.begin(), v.end());
  }
}

TEST(Bq76pl536a, NoiseAndChannelErrorsAreDrawnFromTheSeed) {
  MonitorConfig cfg = config(2);
  cfg.cell_adc.noise_rms = 2e-3;
  cfg.channel_gain_sd = 1e-3;
  cfg.channel_offset_sd_V = 2e-3;
  cfg.module_noise_V = 5e-3;
  cfg.thermistor.noise_codes_rms = 2.0;
  auto readout = [&](uint64_t seed) {
    Bq76pl536aChain chain(cfg, 12, seed);
    Bus bus{chain};
    std::vector<uint8_t> all;
    for (int k = 0; k < 3; ++k)
      convertAndRead(bus, chain, [](int, size_t) { return 3.6; }, all);
    return all;
  };
  EXPECT_EQ(readout(7), readout(7));
  EXPECT_NE(readout(7), readout(8));
}

// The conversion's SSE4.1 build (its rounding roundsd, where the CPU has it) and the plain
// one give the same result registers, bit for bit: noisy cells across many codes (ties
// included: exact half-code inputs without noise), the module channel, the rails.
TEST(Bq76pl536a, TheConversionsSse41BuildReadsAsThePlainOne) {
  auto readout = [](bool native, double noise_V) {
    const bool was = useNativeRounding(native);
    MonitorConfig cfg = config(2);
    cfg.cell_adc.noise_rms = noise_V;
    cfg.channel_gain_sd = noise_V > 0.0 ? 1e-3 : 0.0;
    cfg.channel_offset_sd_V = noise_V > 0.0 ? 2e-3 : 0.0;
    cfg.module_noise_V = noise_V > 0.0 ? 5e-3 : 0.0;
    Bq76pl536aChain chain(cfg, 12, 11);
    Bus bus{chain};
    std::vector<uint8_t> all;
    for (int k = 0; k < 400; ++k)  // half codes (ties), codes between, past both rails
      convertAndRead(bus, chain, [k](int d, size_t i) {
        return ((k * 7 + static_cast<int>(i) * 13 + d * 29) % 16500 + (k % 2 ? 0.5 : 0.37)) * kLsb_V - (k % 9 == 0 ? 0.1 : 0.0);
      }, all);
    useNativeRounding(was);
    return all;
  };
  for (double noise_V : {0.0, 2e-3}) {
    const std::vector<uint8_t> plain = readout(false, noise_V);
    EXPECT_EQ(readout(true, noise_V), plain) << "noise " << noise_V;
    EXPECT_EQ(plain.size(), 400u * 2u * BQ536_RESULTS_LEN);
  }
}

// The power-up EEPROM's secondary protection (COV 4.35 V, CUV 2.5 V, OT 65 degC, each
// 1 s): each ramp crosses its threshold at 1.0 s, so the FAULT line rises one comparator
// delay later, at 2.0 s (within one 10 ms step); per-channel errors are drawn from the seed.
TEST(Bq76pl536a, SecondaryProtectionTripsOneDelayAfterItsThreshold) {
  MonitorConfig cfg = config(2);
  cfg.channel_gain_sd = 1e-3;
  cfg.channel_offset_sd_V = 1e-3;
  const int cells = 12;
  struct Case { int cell; double from_V, to_V; int therm; double from_C, to_C; };
  const Case cases[] = {{4, 4.30, 4.40, -1, 25, 25},   // COV
                        {9, 2.60, 2.40, -1, 25, 25},   // CUV
                        {0, 3.70, 3.70, 3, 60, 70}};   // OT on device 1, TS2
  for (const Case& k : cases) {
    Bq76pl536aChain chain(cfg, cells, 11);
    double trip = -1;
    for (int step = 0; step <= 500; ++step) {
      const double t = 0.01 * step, f = std::min(1.0, t / 2.0);
      for (int d = 0; d < 2; ++d) {
        for (int c = 0; c < 6; ++c) {
          const int pos = d * 6 + c;
          chain.analog(d).cell_V[static_cast<size_t>(c)] = pos == k.cell ? k.from_V + f * (k.to_V - k.from_V) : 3.7;
        }
        for (int j = 0; j < 2; ++j)
          chain.analog(d).therm_C[static_cast<size_t>(j)] = d * 2 + j == k.therm ? k.from_C + f * (k.to_C - k.from_C) : 25.0;
      }
      chain.advance(t);
      if (trip < 0 && chain.faultLine()) trip = t;
    }
    EXPECT_NEAR(trip, 2.0, 0.015) << k.cell << " " << k.therm;
  }
  Bq76pl536aChain chain(cfg, cells, 11), same(cfg, cells, 11), other(cfg, cells, 12);
  for (int c = 0; c < cells; ++c) {
    EXPECT_EQ(chain.channelGain(c), same.channelGain(c));
    EXPECT_EQ(chain.channelOffset_V(c), same.channelOffset_V(c));
    EXPECT_NE(chain.channelGain(c), other.channelGain(c));
  }
}

// The part converts with its balancing switches as they are (the data sheet has the
// host clear CB_CTRL to measure without them): a balanced cell reads the I_bal·R drop at
// its pins -- 3.7 V unloaded, 80 mA through 25 mΩ: 3.698 V -- unless the host opens the
// switches around its conversion (measure_paused), when it reads 3.7 V and the switch is
// open for the conversion's 7 channels × 6 µs.
TEST(Bq76pl536a, ABalancedCellReadsItsDropUnlessTheHostOpensTheSwitchForTheConversion) {
  Bq76pl536aChain chain(config(1), 6, 1);
  DeviceAnalog& a = chain.analog(0);
  a.cell_unloaded_V.assign(6, 3.7);
  a.cell_V.assign(6, 3.7);
  a.cell_V[2] = 3.7 - 0.080 * 0.025;
  Bus bus{chain};
  bus.addressAll(1);
  bus.write(1, BQ536_CB_TIME, 60);
  bus.write(1, BQ536_CB_CTRL, 0x04);
  ASSERT_TRUE(chain.balancing(0, 2));
  bus.write(1, BQ536_ADC_CONTROL, BQ536_AC_ADC_ON | BQ536_AC_GPAI | 5);  // GPAI + 6 cells
  for (bool hostPauses : {false, true}) {
    a.host_opens_balancing = hostPauses;
    bus.t += 1.0;
    chain.advance(bus.t);
    bus.write(1, BQ536_ADC_CONVERT, BQ536_CONV_START);
    const double start = bus.t + bus.last.duration_s;
    bus.t = start + 1e-3;
    const std::vector<uint8_t> v = bus.read(1, BQ536_RESULTS_FIRST, BQ536_RESULTS_LEN);
    const double read_V = be16(v, BQ536_VCELL(2)) * kLsb_V;
    EXPECT_NEAR(read_V, hostPauses ? 3.7 : 3.698, 0.5 * kLsb_V) << hostPauses;
    EXPECT_NEAR(be16(v, BQ536_VCELL(1)) * kLsb_V, 3.7, 0.5 * kLsb_V);
    // Over the second after the command: open for 42 µs while the host pauses, else never.
    const double duty = chain.balancingDuty(0, 2, start, start + 1.0);
    EXPECT_NEAR(duty, hostPauses ? 1.0 - 7 * 6e-6 : 1.0, 1e-12) << hostPauses;
  }
}

}  // namespace
}  // namespace packsim
