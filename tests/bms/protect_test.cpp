// The protection table: debounce, hysteresis, latching and reset, tick by tick.
#include <bms/bms_core.hpp>
#include <bms/bms_protect.hpp>
#include <gtest/gtest.h>

#include <random>

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

// protectionUpdate, fatalFaults and openedActuators against the straightforward table
// walk they replaced (each derived from isolatingRules over every rule, the masks read
// and written in memory rule by rule), over random tables, quantities and times.
namespace reference {

uint32_t isolating(const bms::Config& cfg, bool driving) {
  uint32_t mask = 0;
  for (uint8_t i = 0; i < bms::kFaultCount; ++i) {
    const bms::ProtectionRule& r = cfg.rules[i];
    const bool iso = r.action == bms::FaultAction::Isolate ||
                     (r.action == bms::FaultAction::MonitorWhileDriving && !driving);
    if (r.severity == bms::Severity::Fatal && iso) mask |= 1u << i;
  }
  return mask;
}

void update(const bms::Config& cfg, const int32_t* quantity, uint32_t now_ms, bool driving, bms::ProtectionState& ps) {
  const uint32_t iso = isolating(cfg, driving);
  for (uint8_t i = 0; i < bms::kFaultCount; ++i) {
    const bms::ProtectionRule& r = cfg.rules[i];
    const uint32_t bit = 1u << i;
    if (!r.enabled) {
      ps.violating &= ~bit;
      ps.active &= ~bit;
      continue;
    }
    const int32_t value = quantity[static_cast<uint8_t>(r.quantity)];
    const int32_t margin = (ps.active & bit) ? r.hysteresis : 0;
    const bool bad = r.tripAbove ? value > r.threshold - margin : value < r.threshold + margin;
    if (!bad) {
      ps.violating &= ~bit;
      ps.active &= ~bit;
      continue;
    }
    if ((ps.violating & bit) == 0) {
      ps.violating |= bit;
      ps.violatingSince_ms[i] = now_ms;
    }
    if (now_ms - ps.violatingSince_ms[i] >= r.delay_ms) {
      ps.active |= bit;
      if (r.latch && (r.severity != bms::Severity::Fatal || (iso & bit))) ps.latched |= bit;
    }
  }
}

uint32_t fatal(const bms::Config& cfg, const bms::ProtectionState& ps, bool driving) {
  return (ps.active | ps.latched) & isolating(cfg, driving);
}

uint8_t opened(const bms::Config& cfg, const bms::ProtectionState& ps, bool driving) {
  uint32_t lower = 0;
  for (uint8_t i = 0; i < bms::kFaultCount; ++i)
    if (cfg.rules[i].severity != bms::Severity::Fatal) lower |= 1u << i;
  const uint32_t present = (ps.active | ps.latched) & (isolating(cfg, driving) | lower);
  uint8_t opens = 0;
  for (uint8_t i = 0; i < bms::kFaultCount; ++i)
    if (present & (1u << i)) opens |= cfg.rules[i].opens;
  return opens;
}

}  // namespace reference

TEST(Protection, MatchesTheStraightforwardTableWalkOnRandomTables) {
  std::mt19937 rng(11);
  uint32_t idleTicks = 0, heldTicks = 0;
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<uint32_t>(n)); };
  for (int table = 0; table < 300; ++table) {
    bms::Config cfg = bms::defaultConfig(4, 1);
    for (bms::ProtectionRule& r : cfg.rules) {
      r.enabled = pick(5) != 0;
      r.tripAbove = pick(2) != 0;
      r.threshold = pick(200) - 100;
      r.hysteresis = pick(20);
      r.delay_ms = static_cast<uint32_t>(pick(4) * 30);
      r.severity = static_cast<bms::Severity>(pick(3));
      r.action = static_cast<bms::FaultAction>(pick(3));
      r.latch = pick(2) != 0;
      r.opens = static_cast<uint8_t>(pick(8));
    }
    bms::ProtectionState mine, ref;
    bms::protectionReset(mine);
    bms::protectionReset(ref);
    int32_t quantity[bms::kQuantityCount];
    for (int32_t& v : quantity) v = 0;
    uint32_t now = 4294967000u;  // across the millisecond wrap
    for (int tick = 0; tick < 400; ++tick, now += 10) {
      for (int32_t& v : quantity)
        if (pick(4) == 0) v = pick(240) - 120;  // values drift around the thresholds
      const bool driving = pick(3) == 0;
      if (pick(40) == 0) {  // a rule switched off or on mid-run (its state, if any, dropped)
        bms::ProtectionRule& r = cfg.rules[pick(bms::kFaultCount)];
        r.enabled = !r.enabled;
      }
      ++(mine.active != 0 ? heldTicks : idleTicks);  // the pass with and without hysteresis margins
      bms::protectionUpdate(cfg, quantity, now, driving, mine);
      reference::update(cfg, quantity, now, driving, ref);
      ASSERT_EQ(mine.violating, ref.violating) << "table " << table << " tick " << tick;
      ASSERT_EQ(mine.active, ref.active) << "table " << table << " tick " << tick;
      ASSERT_EQ(mine.latched, ref.latched) << "table " << table << " tick " << tick;
      for (uint8_t i = 0; i < bms::kFaultCount; ++i)
        if (ref.violating & (1u << i)) ASSERT_EQ(mine.violatingSince_ms[i], ref.violatingSince_ms[i]);
      for (const bool d : {false, true}) {
        ASSERT_EQ(bms::fatalFaults(cfg, mine, d), reference::fatal(cfg, ref, d));
        ASSERT_EQ(bms::openedActuators(cfg, mine, d), reference::opened(cfg, ref, d));
        ASSERT_EQ(bms::isolatingRules(cfg, d), reference::isolating(cfg, d));
      }
      if (pick(50) == 0) {  // an operator reset now and then
        bms::clearLatched(mine);
        bms::clearLatched(ref);
      }
    }
  }
  EXPECT_GT(idleTicks, 500u);
  EXPECT_GT(heldTicks, 10000u);
}

}  // namespace
