#include "bms_core.hpp"

#include "bms_measure.hpp"

namespace bms {

void init(CoreState& s) {
  s.state = State::Init;
  s.stateEntered_ms = 0;
  s.firstTick = true;
  protectionReset(s.protection);
  for (uint8_t q = 0; q < kQuantityCount; ++q) s.quantity[q] = 0;
}

const char* stateName(State st) {
  switch (st) {
    case State::Init: return "init";
    case State::Standby: return "standby";
    case State::Normal: return "normal";
    case State::Error: return "error";
  }
  return "unknown";
}

namespace {

// Init: one complete measurement must have been taken before anything may close.
State onInit(const Config&, const CoreState& s, const Inputs&) {
  return s.firstTick ? State::Init : State::Standby;
}

State onStandby(const Config& cfg, const CoreState& s, const Inputs& in) {
  if (fatalFaults(cfg, s.protection) != 0) return State::Error;
  if (in.runRequest && !in.eStopPulled) return State::Normal;
  return State::Standby;
}

State onNormal(const Config& cfg, const CoreState& s, const Inputs& in) {
  if (fatalFaults(cfg, s.protection) != 0) return State::Error;
  if (!in.runRequest || in.eStopPulled) return State::Standby;
  return State::Normal;
}

// Error: leave only when no fatal fault is present any more *and* a person asks.
State onError(const Config& cfg, CoreState& s, const Inputs& in) {
  if (!in.resetRequest) return State::Error;
  clearLatched(s.protection);
  return fatalFaults(cfg, s.protection) == 0 ? State::Standby : State::Error;
}

}  // namespace

void step(const Config& cfg, CoreState& s, const Inputs& in, Outputs& out) {
  measure(cfg, in, out.telemetry, s.quantity);
  protectionUpdate(cfg, s.quantity, in.now_ms, s.protection);

  State next = s.state;
  switch (s.state) {
    case State::Init: next = onInit(cfg, s, in); break;
    case State::Standby: next = onStandby(cfg, s, in); break;
    case State::Normal: next = onNormal(cfg, s, in); break;
    case State::Error: next = onError(cfg, s, in); break;
  }
  if (next != s.state) {
    s.state = next;
    s.stateEntered_ms = in.now_ms;
  }
  s.firstTick = false;

  const uint8_t blocked = openedActuators(cfg, s.protection);
  const bool closed = s.state == State::Normal && !in.eStopPulled;
  out.relayClose = closed && (blocked & kActRelay) == 0;
  out.dischargeFetOn = closed && (blocked & kActDischargeFet) == 0;
  out.chargeFetOn = closed && (blocked & kActChargeFet) == 0;
  out.state = s.state;
  out.faultActive = s.protection.active;
  out.faultLatched = s.protection.latched;
}

}  // namespace bms
