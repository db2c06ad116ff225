// The LTC6811-1 / LTC6813-1 daisy-chain model against the data sheets, frame by frame:
// PEC15 (worked example, bit-serial reference), command codes, conversion times per
// mode, daisy-chain data order, wake-up and the watchdog, the discharge timer, MUTE,
// comm faults. Frames are built here from the data sheet's rules, not by the driver.
#include "models/afe/ltc681x.hpp"

#include <bms/afe/ltc681x_pec.hpp>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace packsim {
namespace {

// The data sheet's PEC procedure, bit by bit (IN0 = DIN xor PEC[14]; IN3, IN4, IN7, IN8,
// IN10, IN14 = IN0 xor the bit below; the rest shifts), seed 0b000000000010000; the
// 16-bit word is the 15-bit PEC with a 0 appended.
uint16_t pecBitSerial(const std::vector<uint8_t>& bytes) {
  uint16_t pec = 16;
  for (uint8_t byte : bytes)
    for (int bit = 7; bit >= 0; --bit) {
      const unsigned din = (byte >> bit) & 1u;
      const unsigned in0 = din ^ ((pec >> 14) & 1u);
      auto b = [&](int i) { return (pec >> i) & 1u; };
      const unsigned in3 = in0 ^ b(2), in4 = in0 ^ b(3), in7 = in0 ^ b(6), in8 = in0 ^ b(7), in10 = in0 ^ b(9),
                     in14 = in0 ^ b(13);
      uint16_t n = 0;
      n |= static_cast<uint16_t>(in14 << 14);
      n |= static_cast<uint16_t>(b(12) << 13);
      n |= static_cast<uint16_t>(b(11) << 12);
      n |= static_cast<uint16_t>(b(10) << 11);
      n |= static_cast<uint16_t>(in10 << 10);
      n |= static_cast<uint16_t>(b(8) << 9);
      n |= static_cast<uint16_t>(in8 << 8);
      n |= static_cast<uint16_t>(in7 << 7);
      n |= static_cast<uint16_t>(b(5) << 6);
      n |= static_cast<uint16_t>(b(4) << 5);
      n |= static_cast<uint16_t>(in4 << 4);
      n |= static_cast<uint16_t>(in3 << 3);
      n |= static_cast<uint16_t>(b(1) << 2);
      n |= static_cast<uint16_t>(b(0) << 1);
      n |= static_cast<uint16_t>(in0);
      pec = n;
    }
  return static_cast<uint16_t>(pec << 1);
}

std::vector<uint8_t> withPec(std::vector<uint8_t> v) {
  const uint16_t p = pecBitSerial(v);
  v.push_back(static_cast<uint8_t>(p >> 8));
  v.push_back(static_cast<uint8_t>(p & 0xFF));
  return v;
}

std::vector<uint8_t> cmd(uint16_t cc) { return withPec({static_cast<uint8_t>(cc >> 8), static_cast<uint8_t>(cc & 0xFF)}); }

// A host on the chain: its own clock, frames from the data sheet's rules.
struct Host {
  Ltc681xChain& chain;
  double t = 0.0;

  void send(const std::vector<uint8_t>& tx) {
    chain.advance(t);
    t += chain.transfer(t, tx.data(), tx.size(), nullptr, 0).duration_s;
  }
  void wait(double dt) {
    t += dt;
    chain.advance(t);
  }
  // One wake-up pulse per device, each after the previous device's wake-up time.
  void wake(double gap_s = 400e-6) {
    for (int d = 0; d < chain.deviceCount(); ++d) {
      send({0xFF});
      wait(gap_s);
    }
  }
  // A read of one group from every device: the raw reply (8 bytes per device).
  std::vector<uint8_t> read(uint16_t cc, int devices) {
    std::vector<uint8_t> tx = cmd(cc), rx(static_cast<size_t>(devices) * 8, 0);
    chain.advance(t);
    t += chain.transfer(t, tx.data(), tx.size(), rx.data(), rx.size()).duration_s;
    return rx;
  }
  // A write of one group: blocks[d] for device d, sent farthest first.
  void write(uint16_t cc, const std::vector<std::vector<uint8_t>>& blocks, int corruptDevice = -1) {
    std::vector<uint8_t> tx = cmd(cc);
    for (size_t k = blocks.size(); k-- > 0;) {
      std::vector<uint8_t> b = withPec(blocks[k]);
      if (static_cast<int>(k) == corruptDevice) b[7] ^= 0x02;
      tx.insert(tx.end(), b.begin(), b.end());
    }
    send(tx);
  }
};

bool slotPecOk(const std::vector<uint8_t>& rx, int d) {
  const std::vector<uint8_t> data(rx.begin() + 8 * d, rx.begin() + 8 * d + 6);
  const uint16_t p = pecBitSerial(data);
  return rx[static_cast<size_t>(8 * d + 6)] == (p >> 8) && rx[static_cast<size_t>(8 * d + 7)] == (p & 0xFF);
}
uint16_t word(const std::vector<uint8_t>& rx, int d, int i) {
  return static_cast<uint16_t>(rx[static_cast<size_t>(8 * d + 2 * i)] | (rx[static_cast<size_t>(8 * d + 2 * i + 1)] << 8));
}

Ltc681xConfig config(Ltc681xPart part, int devices) {
  Ltc681xConfig c;
  c.part = part;
  c.devices = devices;
  c.cells_per_device = part == Ltc681xPart::Ltc6813 ? 18 : 12;
  c.thermistors_per_device = 2;
  return c;
}

void fillCells(Ltc681xChain& chain, double base_V) {
  for (int d = 0; d < chain.deviceCount(); ++d)
    for (int c = 0; c < chain.cellsOf(d); ++c) chain.analog(d).cell_V[static_cast<size_t>(c)] = base_V + 0.01 * c + 0.1 * d;
}

TEST(Ltc681xPec, MatchesTheDataSheetExampleAndTheBitSerialProcedure) {
  // The data sheet's worked example: PEC of 0x0001 is 0x3D6E.
  EXPECT_EQ(pecBitSerial({0x00, 0x01}), 0x3D6E);
  const uint8_t ex[2] = {0x00, 0x01};
  EXPECT_EQ(bms::ltcPec15(ex, 2), 0x3D6E);
  // The table-driven PEC agrees with the procedure on arbitrary frames.
  std::vector<uint8_t> frame;
  for (int n = 0; n < 40; ++n) {
    frame.push_back(static_cast<uint8_t>(n * 37 + 11));
    EXPECT_EQ(bms::ltcPec15(frame.data(), frame.size()), pecBitSerial(frame)) << n;
  }
}

TEST(Ltc681xCommands, CodesAreTheDataSheets) {
  // Command table: CC[10:0] as printed (binary) in the data sheets.
  EXPECT_EQ(LTC681X_WRCFGA, 0b00000000001u);
  EXPECT_EQ(LTC681X_RDCFGA, 0b00000000010u);
  EXPECT_EQ(LTC681X_WRCFGB, 0b00000100100u);
  EXPECT_EQ(LTC681X_RDCFGB, 0b00000100110u);
  EXPECT_EQ(LTC681X_RDCVA, 0b00000000100u);
  EXPECT_EQ(LTC681X_RDCVB, 0b00000000110u);
  EXPECT_EQ(LTC681X_RDCVC, 0b00000001000u);
  EXPECT_EQ(LTC681X_RDCVD, 0b00000001010u);
  EXPECT_EQ(LTC681X_RDCVE, 0b00000001001u);
  EXPECT_EQ(LTC681X_RDCVF, 0b00000001011u);
  EXPECT_EQ(LTC681X_RDAUXA, 0b00000001100u);
  EXPECT_EQ(LTC681X_RDAUXB, 0b00000001110u);
  EXPECT_EQ(LTC681X_RDSTATA, 0b00000010000u);
  EXPECT_EQ(LTC681X_RDSTATB, 0b00000010010u);
  EXPECT_EQ(LTC681X_MUTE, 0b00000101000u);
  EXPECT_EQ(LTC681X_UNMUTE, 0b00000101001u);
  EXPECT_EQ(LTC681X_CLRCELL, 0b11100010001u);
  // ADCV = 01 MD[1] | MD[0] 11 DCP 0 CH[2:0]: 7 kHz (MD=10), DCP=0, all cells = 0x360,
  // whose PEC is the widely quoted 0xF46C.
  EXPECT_EQ(ltc681x_adcv(LTC681X_MD_NORMAL, 0, 0), 0x360u);
  EXPECT_EQ(pecBitSerial({0x03, 0x60}), 0xF46C);
  EXPECT_EQ(ltc681x_adcv(LTC681X_MD_FAST, 1, 3), 0b01011110011u);
  // ADOW = 01 MD[1] | MD[0] PUP 1 DCP 1 CH; ADAX = 10 MD[1] | MD[0] 1100 CHG; ADSTAT = 10 MD[1] | MD[0] 1101 CHST.
  EXPECT_EQ(ltc681x_adow(LTC681X_MD_NORMAL, 1, 0, 0), 0b01101101000u);
  EXPECT_EQ(ltc681x_adow(LTC681X_MD_NORMAL, 0, 0, 0), 0b01100101000u);
  EXPECT_EQ(ltc681x_adax(LTC681X_MD_NORMAL, 0), 0b10101100000u);
  EXPECT_EQ(ltc681x_adstat(LTC681X_MD_FILTERED, 2), 0b10111101010u);
}

TEST(Ltc681xTiming, ConversionTimesPerModeAreTheDataSheetTables) {
  // (MD, ADCOPT) -> mode, and ADCV all cells t6C / one pair t1C / ADSTAT t4C, us.
  struct Row { uint8_t md, adcopt; uint32_t all, one, stat; };
  const Row rows[] = {{1, 0, 1113, 201, 748},   {1, 1, 1288, 230, 865},     {2, 0, 2335, 405, 1563},
                      {2, 1, 3033, 521, 2028},  {3, 1, 4430, 754, 2959},    {3, 0, 201317, 33568, 134218}};
  for (const Row& r : rows) {
    EXPECT_EQ(ltc681x_conversion_us(r.md, r.adcopt, LTC681X_CONV_CELLS, 1), r.all) << int(r.md) << int(r.adcopt);
    EXPECT_EQ(ltc681x_conversion_us(r.md, r.adcopt, LTC681X_CONV_GPIOS, 1), r.all);
    EXPECT_EQ(ltc681x_conversion_us(r.md, r.adcopt, LTC681X_CONV_CELLS, 0), r.one);
    EXPECT_EQ(ltc681x_conversion_us(r.md, r.adcopt, LTC681X_CONV_STATUS, 1), r.stat);
  }
  EXPECT_EQ(ltc681x_conversion_us(0, 0, LTC681X_CONV_CELLS, 1), 0u);  // MD = 00: not modelled

  // The model's results land exactly after that time (REFON already up).
  for (const Row& r : rows) {
    Ltc681xChain chain(config(Ltc681xPart::Ltc6811, 1), 12, 1);
    fillCells(chain, 3.7);
    Host h{chain};
    h.wake();
    h.write(LTC681X_WRCFGA, {{static_cast<uint8_t>(0xF8 | 0x04 | r.adcopt), 0, 0, 0, 0, 0}});
    h.wait(5e-3);   // tREFUP
    h.wake(10e-6);  // the ports idled meanwhile
    h.send(cmd(ltc681x_adcv(r.md, 0, 0)));
    const double start = h.t;
    h.wait(r.all * 1e-6 - 20e-6);
    if (r.all > 4000) h.wake(10e-6);  // the port idles during long conversions
    std::vector<uint8_t> before = h.read(LTC681X_RDCVA, 1);
    EXPECT_EQ(word(before, 0, 0), 0xFFFF) << r.all;  // not converted yet
    h.t = start + r.all * 1e-6;
    h.wake(10e-6);
    std::vector<uint8_t> after = h.read(LTC681X_RDCVA, 1);
    EXPECT_EQ(word(after, 0, 0), 37000) << r.all;  // 3.7 V / 100 uV
  }
}

TEST(Ltc681xChainOrder, ReadsComeDeviceZeroFirstAndWritesFarthestFirst) {
  Ltc681xChain chain(config(Ltc681xPart::Ltc6811, 3), 36, 1);
  Host h{chain};
  h.wake();
  // Write: the data sheet sends the farthest device's block first; Host::write puts
  // blocks[d] in that order, so device d must hold blocks[d].
  h.write(LTC681X_WRCFGA, {{0xF8, 0x11, 0, 0, 0, 0}, {0xF8, 0x22, 0, 0, 0, 0}, {0xF8, 0x33, 0, 0, 0, 0}});
  EXPECT_EQ(chain.cfga(0, 1), 0x11);
  EXPECT_EQ(chain.cfga(1, 1), 0x22);
  EXPECT_EQ(chain.cfga(2, 1), 0x33);
  // Read: device 0 (nearest the host) answers in the first slot.
  const std::vector<uint8_t> rx = h.read(LTC681X_RDCFGA, 3);
  for (int d = 0; d < 3; ++d) {
    EXPECT_TRUE(slotPecOk(rx, d)) << d;
    EXPECT_EQ(rx[static_cast<size_t>(8 * d + 1)], 0x11 * (d + 1)) << d;
    EXPECT_EQ(rx[static_cast<size_t>(8 * d)], 0xF8 | LTC681X_CFGR0_DTEN);  // DTEN pin reads high
  }
}

TEST(Ltc681xWakeup, EachDeviceNeedsItsOwnPulseAndTheWatchdogResetsTheConfiguration) {
  Ltc681xChain chain(config(Ltc681xPart::Ltc6813, 3), 54, 1);
  Host h{chain};
  EXPECT_TRUE(chain.asleep(0));
  h.send({0xFF});  // one pulse wakes device 0 only
  h.wait(400e-6);
  EXPECT_FALSE(chain.asleep(0));
  EXPECT_TRUE(chain.asleep(1));
  // A frame now reaches device 0 and wakes device 1; device 2 hears nothing.
  const std::vector<uint8_t> rx = h.read(LTC681X_RDCFGA, 3);
  EXPECT_TRUE(slotPecOk(rx, 0));
  for (int i = 8; i < 24; ++i) EXPECT_EQ(rx[static_cast<size_t>(i)], 0xFF) << i;
  EXPECT_FALSE(chain.asleep(1));
  EXPECT_TRUE(chain.asleep(2));
  h.wake();
  for (int d = 0; d < 3; ++d) EXPECT_FALSE(chain.asleep(d));

  // Configure: VUV/VOV and a discharge bit, no timer (DCTO = 0).
  h.write(LTC681X_WRCFGA, {{0xFC, 0x12, 0x34, 0x56, 0x01, 0x00}, {0xFC, 0x12, 0x34, 0x56, 0, 0}, {0xFC, 0x12, 0x34, 0x56, 0, 0}});
  EXPECT_EQ(chain.cfga(0, 3), 0x56);
  EXPECT_TRUE(chain.balancing(0, 0));
  // Traffic every second keeps them awake.
  for (int k = 0; k < 3; ++k) {
    h.wait(1.0);
    h.wake(10e-6);
  }
  EXPECT_EQ(chain.cfga(0, 3), 0x56);
  // Silence for the watchdog's 1.8 s (the data sheet's minimum): SLEEP, CFGRA back to
  // its defaults, the discharge switch off.
  h.wait(1.79);
  EXPECT_FALSE(chain.asleep(0));
  h.wait(0.02);
  for (int d = 0; d < 3; ++d) {
    EXPECT_TRUE(chain.asleep(d));
    EXPECT_EQ(chain.cfga(d, 0), LTC681X_CFGR0_DEFAULT);
    for (int i = 1; i < 6; ++i) EXPECT_EQ(chain.cfga(d, i), 0) << i;
  }
  EXPECT_FALSE(chain.balancing(0, 0));
  // A frame to a sleeping chain is lost (it only wakes device 0).
  h.write(LTC681X_WRCFGA, {{0xFC, 0x12, 0x34, 0x56, 0, 0}, {0xFC, 0, 0, 0, 0, 0}, {0xFC, 0, 0, 0, 0, 0}});
  EXPECT_EQ(chain.cfga(0, 3), 0);
}

TEST(Ltc681xDischarge, DctoKeepsBalancingThroughSleepAndExpires) {
  Ltc681xChain chain(config(Ltc681xPart::Ltc6813, 1), 18, 1);
  Host h{chain};
  h.wake();
  // DCC1, DCC12 (CFGR5 bit 3), DCC13 (CFGRB0 bit 4), DCC18 (CFGRB1 bit 1); DCTO = 1: 0.5 min.
  h.write(LTC681X_WRCFGB, {{0x1F, 0x02, 0, 0, 0, 0}});
  h.write(LTC681X_WRCFGA, {{0xF8, 0, 0, 0, 0x01, 0x18}});
  EXPECT_TRUE(chain.balancing(0, 0));
  EXPECT_TRUE(chain.balancing(0, 11));
  EXPECT_TRUE(chain.balancing(0, 12));
  EXPECT_TRUE(chain.balancing(0, 17));
  EXPECT_FALSE(chain.balancing(0, 1));
  // DCTO reads back the bucket of the time left: 0..0.5 min -> 1.
  std::vector<uint8_t> rx = h.read(LTC681X_RDCFGA, 1);
  EXPECT_EQ(rx[5] >> 4, 1);
  // MUTE switches every discharge off, keeping the bits; UNMUTE back on.
  h.send(cmd(LTC681X_MUTE));
  EXPECT_FALSE(chain.balancing(0, 0));
  rx = h.read(LTC681X_RDCFGB, 1);
  EXPECT_NE(rx[1] & LTC6813_CFGRB1_MUTE, 0);
  h.send(cmd(LTC681X_UNMUTE));
  EXPECT_TRUE(chain.balancing(0, 0));
  // The watchdog sleeps the core at ~1.8 s but the timer keeps the switches on ...
  h.wait(10.0);
  EXPECT_TRUE(chain.asleep(0));
  EXPECT_TRUE(chain.balancing(0, 0));
  EXPECT_TRUE(chain.balancing(0, 17));
  // ... until 30 s after the write.
  h.wait(19.9);
  EXPECT_TRUE(chain.balancing(0, 0));
  h.wait(0.2);
  for (int c = 0; c < 18; ++c) EXPECT_FALSE(chain.balancing(0, c)) << c;
  EXPECT_EQ(chain.cfga(0, 5), 0);  // DCTO: disabled or timed out
}

TEST(Ltc681xComm, BadCommandPecIsIgnoredAndBadDataPecOnlyByItsDevice) {
  Ltc681xChain chain(config(Ltc681xPart::Ltc6811, 2), 24, 1);
  Host h{chain};
  h.wake();
  std::vector<uint8_t> bad = cmd(LTC681X_RDCFGA);
  bad[3] ^= 0x01;
  std::vector<uint8_t> rx(16, 0);
  chain.transfer(h.t, bad.data(), bad.size(), rx.data(), rx.size());
  for (uint8_t v : rx) EXPECT_EQ(v, 0xFF);
  h.write(LTC681X_WRCFGA, {{0xF8, 0x11, 0, 0, 0, 0}, {0xF8, 0x22, 0, 0, 0, 0}}, /*corruptDevice=*/1);
  EXPECT_EQ(chain.cfga(0, 1), 0x11);
  EXPECT_EQ(chain.cfga(1, 1), 0x00);
}

TEST(Ltc681xComm, IgnoredFramesAreNotedOncePerDeviceCommandAndReason) {
  Ltc681xChain chain(config(Ltc681xPart::Ltc6811, 2), 24, 1);
  Host h{chain};
  h.wake();
  h.write(LTC681X_WRCFGA, {{0xF8, 0, 0, 0, 0, 0}, {0xF8, 0, 0, 0, 0, 0}});
  h.send(cmd(ltc681x_adcv(2, 0, 0)));
  h.read(LTC681X_RDCVA, 2);
  EXPECT_TRUE(chain.misuse().entries().empty());
  // A bad command PEC, twice; a write with device 1's block corrupted; a write one
  // block short; an LTC6813 command on the LTC6811.
  std::vector<uint8_t> bad = cmd(LTC681X_WRCFGA);
  bad[3] ^= 0x01;
  h.send(bad);
  h.send(bad);
  h.write(LTC681X_WRCFGA, {{0xF8, 0x11, 0, 0, 0, 0}, {0xF8, 0x22, 0, 0, 0, 0}}, /*corruptDevice=*/1);
  EXPECT_EQ(chain.cfga(1, 1), 0x00);  // still ignored
  h.write(LTC681X_WRCFGA, {{0xF8, 0x33, 0, 0, 0, 0}});
  h.send(cmd(LTC681X_MUTE));
  const std::vector<RegisterMisuse>& m = chain.misuse().entries();
  ASSERT_EQ(m.size(), 4u);
  EXPECT_EQ(m[0].device, -1);
  EXPECT_EQ(m[0].what, "WRCFGA");
  EXPECT_NE(m[0].why.find("command PEC"), std::string::npos);
  EXPECT_EQ(m[0].count, 2);
  EXPECT_EQ(m[1].device, 1);
  EXPECT_NE(m[1].why.find("bad PEC"), std::string::npos);
  EXPECT_EQ(m[2].device, 1);
  EXPECT_NE(m[2].why.find("no data block"), std::string::npos);
  EXPECT_EQ(m[3].what, "MUTE");
  EXPECT_NE(m[3].why.find("LTC6811"), std::string::npos);
}

TEST(Ltc681xComm, BrokenLinkAndSilentDeviceSilenceEverythingBeyond) {
  Ltc681xChain chain(config(Ltc681xPart::Ltc6813, 4), 72, 1);
  Host h{chain};
  h.wake();
  chain.setBrokenLinkAbove(1);
  std::vector<uint8_t> rx = h.read(LTC681X_RDCFGA, 4);
  EXPECT_TRUE(slotPecOk(rx, 0));
  EXPECT_TRUE(slotPecOk(rx, 1));
  for (int i = 16; i < 32; ++i) EXPECT_EQ(rx[static_cast<size_t>(i)], 0xFF);
  chain.setBrokenLinkAbove(-1);
  h.wake(10e-6);
  chain.setCommFault(2, MonitorDeviceFault{true, 0.0, -1});
  rx = h.read(LTC681X_RDCFGA, 4);
  EXPECT_TRUE(slotPecOk(rx, 1));
  for (int i = 16; i < 32; ++i) EXPECT_EQ(rx[static_cast<size_t>(i)], 0xFF);
  // A stuck device drives its slot and what it relays.
  chain.setCommFault(2, MonitorDeviceFault{});
  chain.setCommFault(1, MonitorDeviceFault{false, 0.0, 0x00});
  h.wake(10e-6);
  rx = h.read(LTC681X_RDCFGA, 4);
  EXPECT_TRUE(slotPecOk(rx, 0));
  for (int i = 8; i < 32; ++i) EXPECT_EQ(rx[static_cast<size_t>(i)], 0x00);
}

TEST(Ltc681xAnalog, OpenWireFollowsTheAdowCurrents) {
  Ltc681xChain chain(config(Ltc681xPart::Ltc6811, 1), 12, 1);
  fillCells(chain, 3.0);
  chain.setOpenWire(0, 5, true);  // C5: between cell 5 and cell 6
  Host h{chain};
  h.wake();
  h.write(LTC681X_WRCFGA, {{0xFC, 0, 0, 0, 0, 0}});
  h.wait(5e-3);
  h.wake(10e-6);
  // Plain ADCV: the open pin holds its voltage, the readings look healthy.
  h.send(cmd(ltc681x_adcv(LTC681X_MD_NORMAL, 0, 0)));
  h.wait(3e-3);
  EXPECT_EQ(word(h.read(LTC681X_RDCVB, 1), 0, 2), 30500);  // cell 6 = 3.05 V
  // Two ADOW with the pull-up: C5 rises to C6, cell 6 reads 0, cell 5 both cells.
  for (int k = 0; k < 2; ++k) {
    h.send(cmd(ltc681x_adow(LTC681X_MD_NORMAL, 1, 0, 0)));
    h.wait(3e-3);
  }
  std::vector<uint8_t> rx = h.read(LTC681X_RDCVB, 1);
  EXPECT_EQ(word(rx, 0, 2), 0);
  EXPECT_EQ(word(rx, 0, 1), 30400 + 30500);
}


TEST(Ltc681xAnalog, PairConversionGpioFaultsAndDeterminism) {
  Ltc681xConfig c = config(Ltc681xPart::Ltc6813, 1);
  c.cell_adc.noise_rms = 0.5e-3;
  auto run = [&](uint64_t seed) {
    Ltc681xChain chain(c, 18, seed);
    fillCells(chain, 3.5);
    chain.analog(0).therm_fault[1] = ThermistorFault::Open;
    Host h{chain};
    h.wake();
    h.write(LTC681X_WRCFGA, {{0xFC, 0, 0, 0, 0, 0}});
    h.wait(5e-3);
    h.wake(10e-6);
    // CH = 1: cells 1, 7 and 13 only, in the one-pair time (405 us at 7 kHz).
    h.send(cmd(ltc681x_adcv(LTC681X_MD_NORMAL, 0, 1)));
    h.wait(405e-6);
    std::vector<uint8_t> a = h.read(LTC681X_RDCVA, 1), cc = h.read(LTC681X_RDCVC, 1), e = h.read(LTC681X_RDCVE, 1);
    EXPECT_NE(word(a, 0, 0), 0xFFFF);
    EXPECT_EQ(word(a, 0, 1), 0xFFFF);  // cell 2 not converted
    EXPECT_NE(word(cc, 0, 0), 0xFFFF);  // cell 7
    EXPECT_NE(word(e, 0, 0), 0xFFFF);   // cell 13
    EXPECT_EQ(word(e, 0, 1), 0xFFFF);
    h.send(cmd(ltc681x_adax(LTC681X_MD_NORMAL, 0)));
    h.wait(2335e-6);
    std::vector<uint8_t> ax = h.read(LTC681X_RDAUXA, 1);
    EXPECT_EQ(word(ax, 0, 1), 30000);  // open NTC on GPIO2: pulled up to VREF2
    EXPECT_EQ(word(ax, 0, 2), 0);      // no thermistor on GPIO3
    a.insert(a.end(), cc.begin(), cc.end());
    return a;
  };
  EXPECT_EQ(run(7), run(7));  // same seed, same bytes
  EXPECT_NE(run(7), run(8));  // the noise is drawn
}

TEST(Ltc681xDischarge, DctoReadsTheBucketOfTheTimeLeft) {
  Ltc681xChain chain(config(Ltc681xPart::Ltc6811, 1), 12, 1);
  Host h{chain};
  h.wake();
  h.write(LTC681X_WRCFGA, {{0xF8, 0, 0, 0, 0x80, 0x30}});  // DCC8, DCTO 3 = 2 min
  EXPECT_TRUE(chain.balancing(0, 7));
  h.wait(45.0);  // 75 s left: "1 to 2 min" reads 3
  h.wake();
  std::vector<uint8_t> rx = h.read(LTC681X_RDCFGA, 1);
  EXPECT_EQ(rx[5] >> 4, 3);
  EXPECT_EQ(rx[4], 0x80);
  h.wait(50.0);  // 25 s left: "0 to 0.5 min" reads 1
  h.wake();
  rx = h.read(LTC681X_RDCFGA, 1);
  EXPECT_EQ(rx[5] >> 4, 1);
  h.wait(30.0);
  h.wake();
  rx = h.read(LTC681X_RDCFGA, 1);
  EXPECT_EQ(rx[5] >> 4, 0);  // timed out
  EXPECT_EQ(rx[4], 0x00);
  EXPECT_FALSE(chain.balancing(0, 7));
}

TEST(Ltc681xCommands, TheLtc6811IgnoresTheLtc6813sOwnCommands) {
  Ltc681xChain chain(config(Ltc681xPart::Ltc6811, 1), 12, 1);
  Host h{chain};
  h.wake();
  h.write(LTC681X_WRCFGA, {{0xF8, 0, 0, 0, 0x01, 0}});
  h.send(cmd(LTC681X_MUTE));
  EXPECT_TRUE(chain.balancing(0, 0));
  for (uint16_t cc : {LTC681X_RDCFGB, LTC681X_RDCVE, LTC681X_RDAUXC}) {
    const std::vector<uint8_t> rx = h.read(cc, 1);
    for (uint8_t v : rx) EXPECT_EQ(v, 0xFF) << cc;
  }
}


TEST(Ltc681xConfigFrom, TakesTheSharedSettingsAndKeepsThePartsOwnAdc) {
  MonitorConfig m;
  m.devices = 4;
  m.cells_per_device = 10;
  m.thermistors_per_device = 3;
  m.cell_adc.lsb = 6.25 / 16383.0;  // another part's LSB: not the LTC's
  m.cell_adc.gain_error = 0.002;
  m.channel_offset_sd_V = 1e-3;
  m.baud = 2e6;
  const Ltc681xConfig c = ltc681xConfigFrom(m, Ltc681xPart::Ltc6811);
  EXPECT_EQ(c.part, Ltc681xPart::Ltc6811);
  EXPECT_EQ(c.devices, 4);
  EXPECT_EQ(c.cells_per_device, 10);
  EXPECT_EQ(c.thermistors_per_device, 3);
  EXPECT_DOUBLE_EQ(c.cell_adc.lsb, 100e-6);
  EXPECT_EQ(c.cell_adc.code_max, 65535);
  EXPECT_DOUBLE_EQ(c.cell_adc.gain_error, 0.002);
  EXPECT_DOUBLE_EQ(c.channel_offset_sd_V, 1e-3);
  EXPECT_DOUBLE_EQ(c.spi_clock_Hz, 2e6);
  // A part that cannot hold the cells asked for is refused with its range.
  Ltc681xConfig bad = c;
  bad.cells_per_device = 13;
  try {
    Ltc681xChain chain(bad, 52, 1);
    FAIL() << "13 cells on an LTC6811 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("outside 1..12"), std::string::npos) << e.what();
  }
}

// ADCV's DCP bit (LTC6811/LTC6813 data sheets, command bit table: 0 = discharge not
// permitted): with DCP = 0 the part opens a cell's discharge switch while it converts the
// cell or a neighbour, so the balanced cell 5 reads 3.04 V unloaded, not the 3.0385 V at
// its pins (75 mA through 20 mΩ); with DCP = 1 the switch stays on and the reading shows
// the drop. The all-cell conversion runs in six steps (cells j, j+6): cell 5 (index 4) is
// open during steps 3, 4, 5 -- half the conversion time -- and cell 1 during steps 0, 1.
TEST(Ltc681xDischarge, DcpZeroOpensTheSwitchForItsCellsConversionAndTheCellReadsUnloaded) {
  Ltc681xChain chain(config(Ltc681xPart::Ltc6811, 1), 12, 1);
  fillCells(chain, 3.0);
  DeviceAnalog& a = chain.analog(0);
  a.cell_unloaded_V = a.cell_V;
  a.cell_V[4] -= 0.075 * 0.020;
  Host h{chain};
  h.wake();
  h.write(LTC681X_WRCFGA, {{0xFC, 0, 0, 0, 0x11, 0}});  // REFON; DCC1, DCC5
  ASSERT_TRUE(chain.balancing(0, 4));
  h.wait(5e-3);
  h.wake(10e-6);
  const double conv_s = ltc681x_conversion_us(LTC681X_MD_NORMAL, 0, LTC681X_CONV_CELLS, true) * 1e-6;
  for (uint8_t dcp : {1, 0}) {
    h.wake(10e-6);  // the port idles after 4.3 ms
    const double t0 = h.t;
    h.send(cmd(ltc681x_adcv(LTC681X_MD_NORMAL, dcp, LTC681X_CH_ALL)));
    h.wait(3e-3);
    EXPECT_EQ(word(h.read(LTC681X_RDCVB, 1), 0, 1), dcp ? 30385 : 30400) << "DCP " << int(dcp);  // cell 5
    const double cell5 = chain.balancingDuty(0, 4, t0, t0 + 1.0), cell1 = chain.balancingDuty(0, 0, t0, t0 + 1.0);
    EXPECT_NEAR(cell5, dcp ? 1.0 : 1.0 - conv_s / 2.0, 1e-12) << "DCP " << int(dcp);
    EXPECT_NEAR(cell1, dcp ? 1.0 : 1.0 - conv_s / 3.0, 1e-12) << "DCP " << int(dcp);
    h.wait(1.0);
  }
}

}  // namespace
}  // namespace packsim
