#include "bms_protect.hpp"

namespace bms {

void protectionReset(ProtectionState& ps) {
  for (uint8_t i = 0; i < kFaultCount; ++i) ps.violatingSince_ms[i] = 0;
  ps.violating = 0;
  ps.active = 0;
  ps.latched = 0;
}

namespace {

bool beyond(const ProtectionRule& r, int32_t value, int32_t margin) {
  return r.tripAbove ? value > r.threshold - margin : value < r.threshold + margin;
}

// Whether a fatal rule's action isolates now (bms_faults.hpp FaultAction).
bool isolates(const ProtectionRule& r, bool driving) {
  return r.action == FaultAction::Isolate || (r.action == FaultAction::MonitorWhileDriving && !driving);
}

// Pass 1 of protectionUpdate for one rule: is its quantity beyond the threshold now,
// by `margin` (its hysteresis while active)?
bool ruleBeyond(const ProtectionRule& r, const int32_t quantity[kQuantityCount], int32_t margin) {
  return r.enabled && beyond(r, quantity[static_cast<uint8_t>(r.quantity)], margin);
}

// v beyond t with no margin, v > t (tripAbove) or v < t, without a branch on the
// direction: v < t is ~v > ~t (bitwise NOT reverses the order of int32_t, without
// overflow), so with flip = 0 or all ones by the direction it is (v ^ flip) > (t ^ flip).
constexpr bool beyondNoMargin(int32_t v, int32_t t, bool tripAbove) {
  const int32_t flip = static_cast<int32_t>(tripAbove) - 1;
  return (v ^ flip) > (t ^ flip);
}
// The same as beyond()'s comparisons at margin 0, at the ends of the range too.
constexpr bool sameAsPlain(int32_t v, int32_t t) {
  return beyondNoMargin(v, t, true) == (v > t) && beyondNoMargin(v, t, false) == (v < t);
}
static_assert(sameAsPlain(INT32_MIN, INT32_MAX) && sameAsPlain(INT32_MAX, INT32_MIN) && sameAsPlain(INT32_MIN, INT32_MIN) &&
                  sameAsPlain(INT32_MAX, INT32_MAX) && sameAsPlain(-1, 0) && sameAsPlain(0, -1) && sameAsPlain(0, 0) &&
                  sameAsPlain(4200, 4199) && sameAsPlain(-300, -250) && sameAsPlain(INT32_MIN, -1),
              "beyondNoMargin is beyond() at margin 0");

// Pass 1 on the usual tick, no fault active: every margin is 0. No branch on a rule's
// direction or on `enabled`; the table has a fixed length: unrolled, last rule first,
// each bit added in (11 instructions a rule instead of some 13 with the branches on a
// host, 25 a tick; about 1.2 KiB more code on a Cortex-M4 than a loop).
uint32_t beyondIdle(const Config& cfg, const int32_t quantity[kQuantityCount]) {
  uint32_t bad = 0;
#pragma GCC unroll 32
  for (uint8_t i = kFaultCount; i-- > 0;) {
    const ProtectionRule& r = cfg.rules[i];
    const bool over = beyondNoMargin(quantity[static_cast<uint8_t>(r.quantity)], r.threshold, r.tripAbove);
    bad = bad * 2u + static_cast<uint32_t>(r.enabled & over);
  }
  return bad;
}

// Pass 1 with faults active: once active, a fault holds until its quantity is back past
// threshold - hysteresis.
uint32_t beyondHeld(const Config& cfg, const int32_t quantity[kQuantityCount], uint32_t active) {
  uint32_t bad = 0;
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const ProtectionRule& r = cfg.rules[i];
    if (ruleBeyond(r, quantity, ((active >> i) & 1u) != 0 ? r.hysteresis : 0)) bad |= 1u << i;
  }
  return bad;
}

}  // namespace

uint32_t isolatingRules(const Config& cfg, bool driving) {
  uint32_t mask = 0;
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const ProtectionRule& r = cfg.rules[i];
    if (r.severity == Severity::Fatal && isolates(r, driving)) mask |= 1u << i;
  }
  return mask;
}

void protectionUpdate(const Config& cfg, const int32_t quantity[kQuantityCount], uint32_t now_ms, bool driving,
                      ProtectionState& ps) {
  // The three masks live in registers for the pass (the quantities, int32_t, could alias
  // them in memory): one load and one store each per tick instead of one per rule.
  uint32_t violating = ps.violating, active = ps.active, latched = ps.latched;
  // Pass 1, every rule, every tick (an idle rule costs this one compare).
  const uint32_t bad = active != 0 ? beyondHeld(cfg, quantity, active) : beyondIdle(cfg, quantity);
  // A disabled rule, or one back inside its limit, is neither violating nor active.
  violating &= bad;
  active &= bad;
  // Pass 2, only the rules beyond their threshold (none on the usual tick): debounce
  // and latch.
  for (uint32_t left = bad; left != 0; left &= left - 1) {
    const uint8_t i = static_cast<uint8_t>(__builtin_ctz(left));
    const ProtectionRule& r = cfg.rules[i];
    const uint32_t b = 1u << i;
    if ((violating & b) == 0) {
      violating |= b;
      ps.violatingSince_ms[i] = now_ms;
    }
    // Unsigned difference stays correct across the 32-bit millisecond wrap.
    if (now_ms - ps.violatingSince_ms[i] >= r.delay_ms) {
      active |= b;
      // A fatal fault only monitored now reports active and latches once it isolates.
      if (r.latch && (r.severity != Severity::Fatal || isolates(r, driving))) latched |= b;
    }
  }
  ps.violating = violating;
  ps.active = active;
  ps.latched = latched;
}

// Both below look only at the rules of the faults present, never walk the whole table.
uint32_t fatalFaultsOfPresent(const Config& cfg, const ProtectionState& ps, bool driving) {
  const uint32_t present = ps.active | ps.latched;
  uint32_t fatal = 0;
  for (uint8_t i = 0; i < kFaultCount && (present >> i) != 0; ++i) {
    const ProtectionRule& r = cfg.rules[i];
    if ((present & (1u << i)) && r.severity == Severity::Fatal && isolates(r, driving)) fatal |= 1u << i;
  }
  return fatal;
}

uint8_t openedActuatorsOfPresent(const Config& cfg, const ProtectionState& ps, bool driving) {
  // A fatal rule that only monitors now opens nothing; the lower tiers open what they say.
  const uint32_t present = ps.active | ps.latched;
  uint8_t opens = 0;
  for (uint8_t i = 0; i < kFaultCount && (present >> i) != 0; ++i) {
    const ProtectionRule& r = cfg.rules[i];
    if ((present & (1u << i)) && (r.severity != Severity::Fatal || isolates(r, driving))) opens |= r.opens;
  }
  return opens;
}

void clearLatched(ProtectionState& ps) { ps.latched &= ps.active; }

}  // namespace bms
