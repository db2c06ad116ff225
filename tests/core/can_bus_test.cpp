// The CAN bus between the monitor boards' MCUs (core/firmware/can_bus.hpp): frame time
// from the stuffed bit count, arbitration by identifier, delivery at the end of the
// frame to every other node, queue limits.
#include <gtest/gtest.h>

#include <string>

#include "core/firmware/can_bus.hpp"

namespace packsim {
namespace {

// A second, textbook construction of a classic data frame as text: CRC-15 by long
// division of the bit string, then a stuff bit after every run of five equal bits.
int stuffedBitsAsText(uint32_t id, const uint8_t* data, int len) {
  std::string bits = "0";
  for (int i = 10; i >= 0; --i) bits += ((id >> i) & 1u) ? '1' : '0';
  bits += "000";
  for (int i = 3; i >= 0; --i) bits += ((len >> i) & 1) ? '1' : '0';
  for (int k = 0; k < len; ++k)
    for (int i = 7; i >= 0; --i) bits += ((data[k] >> i) & 1) ? '1' : '0';
  const std::string poly = "1100010110011001";  // x^15 + x^14 + x^10 + x^8 + x^7 + x^4 + x^3 + 1
  std::string rem = bits + std::string(15, '0');
  for (size_t i = 0; i + 15 < rem.size(); ++i)
    if (rem[i] == '1')
      for (size_t j = 0; j < poly.size(); ++j) rem[i + j] = rem[i + j] == poly[j] ? '0' : '1';
  bits += rem.substr(rem.size() - 15);
  std::string stuffed;
  int run = 0;
  char last = 'x';
  for (char b : bits) {
    stuffed += b;
    run = b == last ? run + 1 : 1;
    last = b;
    if (run == 5) {
      last = b == '0' ? '1' : '0';
      stuffed += last;
      run = 1;
    }
  }
  return static_cast<int>(stuffed.size()) + 13;  // delimiter, ACK slot + delimiter, EOF, intermission
}

TEST(CanBus, FrameBitsAreTheStuffedFrame) {
  // Identifier 0, no data: 34 zero bits (CRC of zeros is zero), a stuff bit after each
  // five: 6 of them; 34 + 6 + 13 = 53.
  EXPECT_EQ(CanBus::frameBits(0, nullptr, 0), 53);
  const uint8_t data[8] = {0x12, 0x00, 0xFF, 0xA5, 0x5A, 0x0F, 0xF0, 0x81};
  for (uint32_t id : {0x080u, 0x101u, 0x7FFu, 0x555u})
    for (int len = 0; len <= 8; ++len) {
      const int bits = CanBus::frameBits(id, data, static_cast<uint8_t>(len));
      EXPECT_EQ(bits, stuffedBitsAsText(id, data, len)) << id << " " << len;
      EXPECT_GE(bits, 47 + 8 * len);                        // unstuffed length
      EXPECT_LE(bits, 47 + 8 * len + (34 + 8 * len - 1) / 4);  // the worst case of stuffing
    }
}

TEST(CanBus, LowestIdentifierWinsAndFramesArriveAtTheirEnd) {
  CanBus bus(3, 500000.0);
  const uint8_t a[2] = {1, 2}, b[2] = {3, 4};
  ASSERT_TRUE(bus.send(0, 0.0, 0x200, a, 2));
  ASSERT_TRUE(bus.send(1, 0.0, 0x100, b, 2));
  const double first = bus.frameTime_s(0x100, b, 2), second = bus.frameTime_s(0x200, a, 2);
  uint32_t id = 0;
  uint8_t got[8];
  EXPECT_EQ(bus.receive(2, first * 0.99, id, got), -1) << "still on the wire";
  ASSERT_EQ(bus.receive(2, first, id, got), 2);
  EXPECT_EQ(id, 0x100u) << "lower identifier first";
  EXPECT_EQ(got[0], 3);
  EXPECT_EQ(bus.receive(2, first + second * 0.99, id, got), -1);
  ASSERT_EQ(bus.receive(2, first + second, id, got), 2);
  EXPECT_EQ(id, 0x200u);
  // The sender does not hear its own frame; the other node hears both.
  EXPECT_EQ(bus.receive(1, 1.0, id, got), 2);
  EXPECT_EQ(id, 0x200u);
  EXPECT_EQ(bus.receive(1, 1.0, id, got), -1);
  EXPECT_NEAR(bus.busyTime_s(), first + second, 1e-15);
}

TEST(CanBus, AFullTransmitQueueRefusesAndAFullReceiveFifoLoses) {
  CanBus bus(2, 500000.0, 4, 3);
  const uint8_t d[1] = {0};
  for (int k = 0; k < 4; ++k) EXPECT_TRUE(bus.send(0, 0.0, 0x10, d, 1));
  EXPECT_FALSE(bus.send(0, 0.0, 0x10, d, 1)) << "four mailboxes";
  bus.runUntil(1.0);
  EXPECT_EQ(bus.framesSent(), 4u);
  EXPECT_EQ(bus.framesLost(), 1u) << "node 1's three-frame FIFO";
}

}  // namespace
}  // namespace packsim
