// The protection table: debounce, hysteresis, latching and reset, tick by tick.
#include <bms/bms_core.hpp>
#include <bms/bms_protect.hpp>
#include <gtest/gtest.h>

#include "fake_stack.hpp"

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
    bms::protectionUpdate(cfg, quantity, t, false, ps);
    ASSERT_EQ(ps.active & bit, 0u) << "tripped early at " << t;
  }
  bms::protectionUpdate(cfg, quantity, 1500, false, ps);
  EXPECT_NE(ps.active & bit, 0u);
}

TEST(Protection, AtThresholdDoesNotTrip) {
  const bms::Config cfg = oneRuleConfig();
  bms::ProtectionState ps;
  bms::protectionReset(ps);
  int32_t quantity[bms::kQuantityCount];
  q(bms::Quantity::MinCell_mV, 3000, quantity);
  for (uint32_t t = 0; t < 10000; t += 10) bms::protectionUpdate(cfg, quantity, t, false, ps);
  EXPECT_EQ(ps.active, 0u);
}

TEST(Protection, InterruptedViolationRestartsDebounce) {
  const bms::Config cfg = oneRuleConfig();
  bms::ProtectionState ps;
  bms::protectionReset(ps);
  int32_t quantity[bms::kQuantityCount];
  q(bms::Quantity::MinCell_mV, 2900, quantity);
  for (uint32_t t = 0; t <= 400; t += 10) bms::protectionUpdate(cfg, quantity, t, false, ps);
  q(bms::Quantity::MinCell_mV, 3100, quantity);
  bms::protectionUpdate(cfg, quantity, 410, false, ps);
  q(bms::Quantity::MinCell_mV, 2900, quantity);
  for (uint32_t t = 420; t < 920; t += 10) bms::protectionUpdate(cfg, quantity, t, false, ps);
  EXPECT_EQ(ps.active, 0u);
  bms::protectionUpdate(cfg, quantity, 920, false, ps);
  EXPECT_NE(ps.active, 0u);
}

TEST(Protection, HysteresisHoldsUntilRecovered) {
  const bms::Config cfg = oneRuleConfig();
  bms::ProtectionState ps;
  bms::protectionReset(ps);
  int32_t quantity[bms::kQuantityCount];
  q(bms::Quantity::MinCell_mV, 2900, quantity);
  for (uint32_t t = 0; t <= 500; t += 10) bms::protectionUpdate(cfg, quantity, t, false, ps);
  ASSERT_NE(ps.active, 0u);
  q(bms::Quantity::MinCell_mV, 3050, quantity);  // above threshold, inside hysteresis band
  bms::protectionUpdate(cfg, quantity, 510, false, ps);
  EXPECT_NE(ps.active, 0u);
  q(bms::Quantity::MinCell_mV, 3101, quantity);
  bms::protectionUpdate(cfg, quantity, 520, false, ps);
  EXPECT_EQ(ps.active, 0u);
}

TEST(Protection, DebounceSurvivesMillisecondWrap) {
  const bms::Config cfg = oneRuleConfig();
  bms::ProtectionState ps;
  bms::protectionReset(ps);
  int32_t quantity[bms::kQuantityCount];
  q(bms::Quantity::MinCell_mV, 2900, quantity);
  const uint32_t start = 0xFFFFFF00u;
  bms::protectionUpdate(cfg, quantity, start, false, ps);
  bms::protectionUpdate(cfg, quantity, start + 400u, false, ps);  // wrapped
  EXPECT_EQ(ps.active, 0u);
  bms::protectionUpdate(cfg, quantity, start + 500u, false, ps);
  EXPECT_NE(ps.active, 0u);
}

// The whole core: a latched fatal fault keeps the relay open until a person resets it.
TEST(Core, LatchedFaultKeepsRelayOpenUntilReset) {
  const bms::Config cfg = bms_test::config(2, 0);
  bms_test::Rig rig;
  auto& [s, in, out] = rig;
  bms_test::FakeStack st(2, 0);
  uint32_t t = bms_test::run(cfg, s, in, out, st, 0, 100);
  ASSERT_TRUE(out.relayClose);
  st.cell_mV[1] = 2500;  // under-voltage
  t = bms_test::run(cfg, s, in, out, st, t, 700);
  EXPECT_FALSE(out.relayClose);
  EXPECT_EQ(out.state, bms::State::Error);
  st.cell_mV[1] = 3700;  // condition gone, but latched
  t = bms_test::run(cfg, s, in, out, st, t, 2000, [&](uint32_t) { ASSERT_FALSE(out.relayClose); });
  in.resetRequest = true;
  t = bms_test::run(cfg, s, in, out, st, t, t + 10);
  in.resetRequest = false;
  bms_test::run(cfg, s, in, out, st, t, t + 100);
  EXPECT_TRUE(out.relayClose);
  EXPECT_EQ(out.faultLatched, 0u);
}

TEST(Core, ResetWhileFaultPresentStaysInError) {
  const bms::Config cfg = bms_test::config(1, 0);
  bms_test::Rig rig;
  auto& [s, in, out] = rig;
  bms_test::FakeStack st(1, 0, 2500);
  bms_test::run(cfg, s, in, out, st, 0, 1000, [&](uint32_t t) {
    in.resetRequest = t > 800;
  });
  EXPECT_EQ(out.state, bms::State::Error);
}

// Either E-switch isolates in the tick that sees it (relay and both FETs), latches,
// and the relay stays open until the switch is released *and* a reset arrives.
TEST(Core, EitherESwitchIsolatesWithinOneTickAndLatches) {
  for (const bool external : {false, true}) {
    const bms::Config cfg = bms_test::config(1, 0);
    bms_test::Rig rig;
    auto& [s, in, out] = rig;
    bms_test::FakeStack st(1, 0);
    uint32_t t = bms_test::run(cfg, s, in, out, st, 0, 100);
    ASSERT_TRUE(out.relayClose && out.dischargeFetOn && out.chargeFetOn);
    (external ? in.eSwitchExternal : in.eSwitchInternal) = true;
    t = bms_test::run(cfg, s, in, out, st, t, t + 10);
    EXPECT_FALSE(out.relayClose);
    EXPECT_FALSE(out.dischargeFetOn);
    EXPECT_FALSE(out.chargeFetOn);
    EXPECT_NE(out.faultLatched & bms::faultBit(bms::FaultId::EStop), 0u);
    in.resetRequest = true;  // reset while still pulled: nothing closes
    t = bms_test::run(cfg, s, in, out, st, t, t + 100, [&](uint32_t) { ASSERT_FALSE(out.relayClose); });
    in.resetRequest = false;
    (external ? in.eSwitchExternal : in.eSwitchInternal) = false;  // released, no reset yet
    t = bms_test::run(cfg, s, in, out, st, t, t + 500, [&](uint32_t) { ASSERT_FALSE(out.relayClose); });
    in.resetRequest = true;
    t = bms_test::run(cfg, s, in, out, st, t, t + 10);
    in.resetRequest = false;
    bms_test::run(cfg, s, in, out, st, t, t + 50);
    EXPECT_TRUE(out.relayClose);
  }
}

}  // namespace
