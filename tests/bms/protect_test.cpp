// The protection table: debounce, hysteresis, latching and reset, tick by tick.
#include <bms/bms_core.hpp>
#include <bms/bms_protect.hpp>
#include <gtest/gtest.h>

namespace {

bms::Config oneRuleConfig() {
  bms::Config c = bms::defaultConfig(4, 1);
  for (auto& r : c.rules) r.enabled = false;
  auto& uv = c.rules[static_cast<int>(bms::FaultId::CellUnderVoltage)];
  uv.enabled = true;
  uv.threshold = 3000;
  uv.hysteresis = 100;
  uv.delay_ms = 500;
  uv.latch = false;
  return c;
}

int32_t q(bms::Quantity which, int32_t v, int32_t out[bms::kQuantityCount]) {
  for (uint8_t i = 0; i < bms::kQuantityCount; ++i) out[i] = 0;
  out[static_cast<uint8_t>(bms::Quantity::MinCell_mV)] = 3500;
  out[static_cast<uint8_t>(which)] = v;
  return v;
}

TEST(Protection, TripsExactlyAfterDelayNotBefore) {
  const bms::Config cfg = oneRuleConfig();
  bms::ProtectionState ps;
  bms::protectionReset(ps);
  int32_t quantity[bms::kQuantityCount];
  const uint32_t bit = bms::faultBit(bms::FaultId::CellUnderVoltage);
  q(bms::Quantity::MinCell_mV, 2999, quantity);
  for (uint32_t t = 1000; t < 1500; t += 10) {
    bms::protectionUpdate(cfg, quantity, t, ps);
    ASSERT_EQ(ps.active & bit, 0u) << "tripped early at " << t;
  }
  bms::protectionUpdate(cfg, quantity, 1500, ps);
  EXPECT_NE(ps.active & bit, 0u);
}

TEST(Protection, AtThresholdDoesNotTrip) {
  const bms::Config cfg = oneRuleConfig();
  bms::ProtectionState ps;
  bms::protectionReset(ps);
  int32_t quantity[bms::kQuantityCount];
  q(bms::Quantity::MinCell_mV, 3000, quantity);
  for (uint32_t t = 0; t < 10000; t += 10) bms::protectionUpdate(cfg, quantity, t, ps);
  EXPECT_EQ(ps.active, 0u);
}

TEST(Protection, InterruptedViolationRestartsDebounce) {
  const bms::Config cfg = oneRuleConfig();
  bms::ProtectionState ps;
  bms::protectionReset(ps);
  int32_t quantity[bms::kQuantityCount];
  q(bms::Quantity::MinCell_mV, 2900, quantity);
  for (uint32_t t = 0; t <= 400; t += 10) bms::protectionUpdate(cfg, quantity, t, ps);
  q(bms::Quantity::MinCell_mV, 3100, quantity);
  bms::protectionUpdate(cfg, quantity, 410, ps);
  q(bms::Quantity::MinCell_mV, 2900, quantity);
  for (uint32_t t = 420; t < 920; t += 10) bms::protectionUpdate(cfg, quantity, t, ps);
  EXPECT_EQ(ps.active, 0u);
  bms::protectionUpdate(cfg, quantity, 920, ps);
  EXPECT_NE(ps.active, 0u);
}

TEST(Protection, HysteresisHoldsUntilRecovered) {
  const bms::Config cfg = oneRuleConfig();
  bms::ProtectionState ps;
  bms::protectionReset(ps);
  int32_t quantity[bms::kQuantityCount];
  q(bms::Quantity::MinCell_mV, 2900, quantity);
  for (uint32_t t = 0; t <= 500; t += 10) bms::protectionUpdate(cfg, quantity, t, ps);
  ASSERT_NE(ps.active, 0u);
  q(bms::Quantity::MinCell_mV, 3050, quantity);  // above threshold, inside hysteresis band
  bms::protectionUpdate(cfg, quantity, 510, ps);
  EXPECT_NE(ps.active, 0u);
  q(bms::Quantity::MinCell_mV, 3101, quantity);
  bms::protectionUpdate(cfg, quantity, 520, ps);
  EXPECT_EQ(ps.active, 0u);
}

TEST(Protection, DebounceSurvivesMillisecondWrap) {
  const bms::Config cfg = oneRuleConfig();
  bms::ProtectionState ps;
  bms::protectionReset(ps);
  int32_t quantity[bms::kQuantityCount];
  q(bms::Quantity::MinCell_mV, 2900, quantity);
  const uint32_t start = 0xFFFFFF00u;
  bms::protectionUpdate(cfg, quantity, start, ps);
  bms::protectionUpdate(cfg, quantity, start + 400u, ps);  // wrapped
  EXPECT_EQ(ps.active, 0u);
  bms::protectionUpdate(cfg, quantity, start + 500u, ps);
  EXPECT_NE(ps.active, 0u);
}

// The whole core: a latched fatal fault keeps the relay open until a person resets it.
TEST(Core, LatchedFaultKeepsRelayOpenUntilReset) {
  bms::Config cfg = bms::defaultConfig(2, 0);
  cfg.scaling.cellLsb_uV = 1000.0f;  // 1 mV per code
  cfg.scaling.currentZeroCode = 0.0f;
  bms::CoreState s;
  bms::init(s);
  bms::Inputs in{};
  bms::Outputs out{};
  in.runRequest = true;
  in.cellCode[0] = in.cellCode[1] = 3700;
  uint32_t t = 0;
  for (; t < 100; t += 10) {
    in.now_ms = t;
    bms::step(cfg, s, in, out);
  }
  ASSERT_TRUE(out.relayClose);
  in.cellCode[1] = 2500;  // under-voltage
  for (; t < 700; t += 10) {
    in.now_ms = t;
    bms::step(cfg, s, in, out);
  }
  EXPECT_FALSE(out.relayClose);
  EXPECT_EQ(out.state, bms::State::Error);
  in.cellCode[1] = 3700;  // condition gone, but latched
  for (; t < 2000; t += 10) {
    in.now_ms = t;
    bms::step(cfg, s, in, out);
    ASSERT_FALSE(out.relayClose);
  }
  in.resetRequest = true;
  in.now_ms = t;
  bms::step(cfg, s, in, out);
  in.resetRequest = false;
  for (t += 10; t < 2100; t += 10) {
    in.now_ms = t;
    bms::step(cfg, s, in, out);
  }
  EXPECT_TRUE(out.relayClose);
  EXPECT_EQ(out.faultLatched, 0u);
}

TEST(Core, ResetWhileFaultPresentStaysInError) {
  bms::Config cfg = bms::defaultConfig(1, 0);
  cfg.scaling.cellLsb_uV = 1000.0f;
  bms::CoreState s;
  bms::init(s);
  bms::Inputs in{};
  bms::Outputs out{};
  in.runRequest = true;
  in.cellCode[0] = 2500;
  for (uint32_t t = 0; t < 1000; t += 10) {
    in.now_ms = t;
    in.resetRequest = t > 800;
    bms::step(cfg, s, in, out);
  }
  EXPECT_EQ(out.state, bms::State::Error);
  EXPECT_FALSE(out.relayClose);
}

TEST(Core, EStopOpensRelayWithinOneTick) {
  bms::Config cfg = bms::defaultConfig(1, 0);
  cfg.scaling.cellLsb_uV = 1000.0f;
  bms::CoreState s;
  bms::init(s);
  bms::Inputs in{};
  bms::Outputs out{};
  in.runRequest = true;
  in.cellCode[0] = 3700;
  for (uint32_t t = 0; t < 100; t += 10) {
    in.now_ms = t;
    bms::step(cfg, s, in, out);
  }
  ASSERT_TRUE(out.relayClose);
  in.eStopPulled = true;
  in.now_ms = 100;
  bms::step(cfg, s, in, out);
  EXPECT_FALSE(out.relayClose);
}

}  // namespace
