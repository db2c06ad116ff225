// Property tests of the firmware core: seeded random input sequences (cell, thermistor
// and current codes, GPIO, comm faults, irregular time steps including jumps across the
// 32-bit millisecond wrap) and three properties checked after every step:
//   1. the relay (and precharge) is never commanded closed while a fatal fault is active
//      or latched;
//   2. no cell is balanced while it reads below the balancing minimum;
//   3. a fatal rule whose quantity stays beyond its threshold from t0 on has isolated the
//      pack (fault active, relay open) at the first step with now - t0 >= its delay,
//      i.e. within delay + one tick. The quantity is taken independently from the inputs
//      for over-current and the E-switch, and from the core's own measurement for the
//      rest (the measurement itself is covered by measure_test).
// Inputs change in "regimes" held for a random number of ticks so that faults persist
// long enough to trip, clear, and be reset. Seeded and deterministic (the generator is
// std::mt19937 with the modulo taken by hand), bounded to about a second.
#include <bms/bms_core.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <sstream>

#include "fake_stack.hpp"

namespace {

constexpr uint16_t kCells = 12;
constexpr uint8_t kTherms = 4;

struct Rng {
  std::mt19937 g;
  explicit Rng(uint32_t seed) : g(seed) {}
  uint32_t below(uint32_t n) { return static_cast<uint32_t>(g() % n); }
  bool chance(uint32_t percent) { return below(100) < percent; }
  int32_t between(int32_t lo, int32_t hi) { return lo + static_cast<int32_t>(below(static_cast<uint32_t>(hi - lo + 1))); }
};

bms::Config propertyConfig() {
  bms::Config c = bms_test::config(kCells, kTherms);
  c.balance.enabled = true;
  c.balance.when = bms::BalanceWhen::Always;
  c.balance.startDelta_mV = 20;
  c.balance.stopDelta_mV = 5;
  c.balance.minCell_mV = 3300;
  c.balance.period_ms = 1000;
  return c;
}

// One regime: the inputs held (with per-tick jitter) for `ticks` steps.
struct Regime {
  int ticks = 1;
  std::vector<int32_t> cell_mV = std::vector<int32_t>(kCells, 3700);
  std::vector<uint16_t> thermCode = std::vector<uint16_t>(kTherms, 2048);
  int32_t current_mA = 0;
  bool eStop = false, faultPin = false, charger = false, run = true, auxFollows = true;
  std::vector<int> silent;
  int jitter_mV = 0;
};

Regime drawRegime(Rng& r) {
  Regime g;
  g.ticks = r.between(1, 400);
  if (r.chance(55)) {  // a healthy pack, so the relay closes again after resets
    const int32_t base = r.between(3400, 4000);
    for (auto& v : g.cell_mV) v = base + r.between(-60, 60);
    for (auto& t : g.thermCode) t = static_cast<uint16_t>(r.between(1800, 2300));
    g.current_mA = r.between(-3000, 20000);
    g.charger = r.chance(20);
    g.jitter_mV = r.between(0, 5);
    return g;
  }
  const int32_t base = r.chance(70) ? r.between(3250, 4150) : r.between(2600, 4500);
  for (auto& v : g.cell_mV) v = r.chance(85) ? base + r.between(-40, 40) : r.between(2600, 4500);
  for (auto& t : g.thermCode) {
    const uint32_t k = r.below(100);
    t = k < 75 ? static_cast<uint16_t>(r.between(1500, 2600)) : k < 85 ? static_cast<uint16_t>(r.between(400, 4000))
                                                                       : k < 93 ? 0 : 4095;
  }
  const uint32_t k = r.below(100);
  g.current_mA = k < 60 ? r.between(-4000, 25000) : k < 80 ? r.between(-9000, 40000) : r.between(-32768, 32767);
  g.eStop = r.chance(5);
  g.faultPin = r.chance(4);
  g.charger = r.chance(30);
  g.run = r.chance(85);
  g.auxFollows = r.chance(90);
  if (r.chance(5)) g.silent.push_back(r.between(0, 1));
  g.jitter_mV = r.chance(50) ? 0 : r.between(1, 15);
  return g;
}

uint32_t nextStep_ms(Rng& r, uint32_t tick_ms) {
  const uint32_t k = r.below(100);
  if (k < 80) return tick_ms;
  if (k < 88) return r.below(tick_ms);  // early or repeated tick
  if (k < 97) return tick_ms + r.below(5 * tick_ms);
  return 1000u + r.below(60000u);  // a long stall
}

struct Violations {
  int count = 0;
  std::ostringstream first;
  template <typename... A>
  void add(uint32_t seed, long step, uint32_t now, A&&... what) {
    if (count++ == 0) {
      first << "seed " << seed << " step " << step << " now_ms " << now << ": ";
      (first << ... << what);
    }
  }
};

bool beyond(const bms::ProtectionRule& rule, int32_t v) { return rule.tripAbove ? v > rule.threshold : v < rule.threshold; }

// One seeded sequence: draws the inputs, steps the core and hands every step to `each`
// (step index, now_ms, regime, rig, the ms to the next step).
template <typename Each>
void drive(uint32_t seed, long steps, Each each) {
  Rng r(seed);
  const bms::Config cfg = propertyConfig();
  bms_test::FakeStack stack(kCells, kTherms);
  bms_test::Rig rig;
  // Start anywhere, often just before the 32-bit wrap.
  uint32_t now = r.chance(50) ? 0xFFFFFFFFu - r.below(120000u) : static_cast<uint32_t>(r.g());
  Regime g = drawRegime(r);
  int left = g.ticks;
  for (long k = 0; k < steps; ++k) {
    if (--left <= 0) {
      g = drawRegime(r);
      left = g.ticks;
    }
    for (uint16_t c = 0; c < kCells; ++c)
      stack.cell_mV[c] = static_cast<uint16_t>(g.cell_mV[c] + (g.jitter_mV ? r.between(-g.jitter_mV, g.jitter_mV) : 0));
    stack.thermCode = g.thermCode;
    stack.silent = g.silent;
    stack.fill(cfg, rig.s);
    rig.in.currentCode = 32768 + g.current_mA;
    rig.in.eSwitchInternal = g.eStop;
    rig.in.eSwitchExternal = false;
    rig.in.monitorFaultPin = g.faultPin;
    rig.in.chargerPresent = g.charger;
    rig.in.runRequest = g.run;
    rig.in.resetRequest = r.chance(10);
    rig.in.relayAux = g.auxFollows ? rig.s.relayCmd : r.chance(50);
    rig.in.now_ms = now;
    bms::step(cfg, rig.s, rig.in, rig.out);
    const uint32_t next = nextStep_ms(r, cfg.tickPeriod_ms);
    each(k, now, g, rig, next);
    now += next;
  }
}

constexpr uint32_t kSeeds = 60;
constexpr long kSteps = 4000;

TEST(FirmwareProperties, RandomSequencesKeepTheSafetyProperties) {
  const bms::Config cfg = propertyConfig();
  uint32_t fatalMask = 0;
  for (uint8_t i = 0; i < bms::kFaultCount; ++i)
    if (cfg.rules[i].enabled && cfg.rules[i].severity == bms::Severity::Fatal) fatalMask |= 1u << i;
  Violations bad;
  for (uint32_t seed = 1; seed <= kSeeds; ++seed) {
    // Oracle for property 3: since when each rule's quantity has been beyond its threshold.
    bool violating[bms::kFaultCount] = {};
    uint32_t since[bms::kFaultCount] = {};
    drive(seed, kSteps, [&](long k, uint32_t now, const Regime& g, const bms_test::Rig& rig, uint32_t) {
      const bms::Outputs& o = rig.out;
      // 1. never closed with a fatal fault present or latched
      const uint32_t fatalNow = (o.faultActive | o.faultLatched) & fatalMask;
      if (fatalNow && (o.relayClose || o.prechargeClose))
        bad.add(seed, k, now, "relay commanded closed with fatal faults 0x", std::hex, fatalNow);
      // 2. never balance a cell that reads below the minimum
      for (uint16_t c = 0; c < kCells; ++c) {
        const bool on = (o.balanceMask[c / 32] >> (c % 32)) & 1u;
        if (on && o.telemetry.cellVoltage_mV[c] < cfg.balance.minCell_mV)
          bad.add(seed, k, now, "cell ", c, " balanced at ", o.telemetry.cellVoltage_mV[c], " mV");
      }
      // 3. isolation within delay + one tick of a continuous violation
      for (uint8_t i = 0; i < bms::kFaultCount; ++i) {
        const bms::ProtectionRule& rule = cfg.rules[i];
        const auto id = static_cast<bms::FaultId>(i);
        if (!((fatalMask >> i) & 1u)) continue;
        int32_t q = rig.s.quantity[static_cast<uint8_t>(rule.quantity)];
        if (id == bms::FaultId::OverCurrentDischarge) q = g.current_mA;  // independent of the core
        if (id == bms::FaultId::OverCurrentCharge) q = -g.current_mA;
        if (id == bms::FaultId::EStop) q = g.eStop ? 1 : 0;
        if (!beyond(rule, q)) {
          violating[i] = false;
          continue;
        }
        if (!violating[i]) violating[i] = true, since[i] = now;
        if (now - since[i] < rule.delay_ms) continue;
        if (!(o.faultActive & (1u << i)))
          bad.add(seed, k, now, bms::faultName(id), " beyond its threshold for ", now - since[i], " ms (delay ",
                  rule.delay_ms, ") but not active");
        if (o.relayClose && (rule.opens & bms::kActRelay))
          bad.add(seed, k, now, bms::faultName(id), " active but the relay is commanded closed");
      }
    });
  }
  EXPECT_EQ(bad.count, 0) << bad.count << " violations; first: " << bad.first.str();
}

// The generator must reach the states the properties are about: trips of many kinds,
// resets that clear them (the relay closes again after Error), balancing, and wraps of
// the millisecond clock.
TEST(FirmwareProperties, SequencesCoverTripsResetsBalancingAndTheWrap) {
  uint32_t faultsSeen = 0;
  long balancingSteps = 0, closedSteps = 0, wraps = 0, recoveries = 0;
  for (uint32_t seed = 1; seed <= kSeeds; ++seed) {
    bool inError = false;
    drive(seed, kSteps, [&](long, uint32_t now, const Regime&, const bms_test::Rig& rig, uint32_t next) {
      const bms::Outputs& o = rig.out;
      faultsSeen |= o.faultLatched;
      bool balancing = false;
      for (uint8_t w = 0; w < bms::kBalanceWords; ++w) balancing = balancing || o.balanceMask[w] != 0;
      balancingSteps += balancing;
      closedSteps += o.relayClose;
      if (o.state == bms::State::Error) inError = true;
      if (inError && o.relayClose) ++recoveries, inError = false;
      if (now + next < now) ++wraps;
    });
  }
  int kinds = 0;
  for (uint8_t i = 0; i < bms::kFaultCount; ++i) kinds += (faultsSeen >> i) & 1u;
  std::printf("%u sequences x %ld steps: %d fault kinds latched, %ld steps balancing, %ld closed, %ld recoveries, "
              "%ld clock wraps\n", kSeeds, kSteps, kinds, balancingSteps, closedSteps, recoveries, wraps);
  EXPECT_GE(kinds, 8) << "fault kinds latched: 0x" << std::hex << faultsSeen;
  EXPECT_GT(balancingSteps, 100);
  EXPECT_GT(closedSteps, 20000);
  EXPECT_GT(recoveries, 20);
  EXPECT_GT(wraps, 3);
}

}  // namespace
