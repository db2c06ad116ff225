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

}  // namespace

uint32_t isolatingRules(const Config& cfg, bool driving) {
  uint32_t mask = 0;
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const ProtectionRule& r = cfg.rules[i];
    const bool isolates = r.action == FaultAction::Isolate || (r.action == FaultAction::MonitorWhileDriving && !driving);
    if (r.severity == Severity::Fatal && isolates) mask |= 1u << i;
  }
  return mask;
}

void protectionUpdate(const Config& cfg, const int32_t quantity[kQuantityCount], uint32_t now_ms, bool driving,
                      ProtectionState& ps) {
  const uint32_t isolating = isolatingRules(cfg, driving);
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const ProtectionRule& r = cfg.rules[i];
    const uint32_t bit = 1u << i;
    if (!r.enabled) {
      ps.violating &= ~bit;
      ps.active &= ~bit;
      continue;
    }
    const int32_t value = quantity[static_cast<uint8_t>(r.quantity)];
    // Once active, the fault holds until the quantity is back past threshold - hysteresis.
    const bool isActive = (ps.active & bit) != 0;
    const bool bad = beyond(r, value, isActive ? r.hysteresis : 0);
    if (!bad) {
      ps.violating &= ~bit;
      ps.active &= ~bit;
      continue;
    }
    if ((ps.violating & bit) == 0) {
      ps.violating |= bit;
      ps.violatingSince_ms[i] = now_ms;
    }
    // Unsigned difference stays correct across the 32-bit millisecond wrap.
    if (now_ms - ps.violatingSince_ms[i] >= r.delay_ms) {
      ps.active |= bit;
      // A fatal fault only monitored now reports active and latches once it isolates.
      if (r.latch && (r.severity != Severity::Fatal || (isolating & bit))) ps.latched |= bit;
    }
  }
}

uint32_t fatalFaults(const Config& cfg, const ProtectionState& ps, bool driving) {
  return (ps.active | ps.latched) & isolatingRules(cfg, driving);
}

uint8_t openedActuators(const Config& cfg, const ProtectionState& ps, bool driving) {
  uint8_t opens = 0;
  // A fatal rule that only monitors now opens nothing; the lower tiers open what they say.
  uint32_t lowerTiers = 0;
  for (uint8_t i = 0; i < kFaultCount; ++i)
    if (cfg.rules[i].severity != Severity::Fatal) lowerTiers |= 1u << i;
  const uint32_t present = (ps.active | ps.latched) & (isolatingRules(cfg, driving) | lowerTiers);
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    if (present & (1u << i)) opens |= cfg.rules[i].opens;
  }
  return opens;
}

void clearLatched(ProtectionState& ps) { ps.latched &= ps.active; }

}  // namespace bms
