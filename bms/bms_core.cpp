#include "bms_core.hpp"

#include "bms_rest.hpp"

namespace bms {

void init(CoreState& s) {
  s.state = State::Init;
  s.firstTick = true;
  protectionReset(s.protection);
  for (uint8_t q = 0; q < kQuantityCount; ++q) s.quantity[q] = 0;
  acquisitionReset(s.acq);
  socReset(s.soc);
  ekfReset(s.ekf);
  s.precharge = PrechargeState{PrechargePhase::Idle, 0, 0, false};
  balanceReset(s.balance);
  packReset(s.pack);
  s.balancePermitted = false;
  s.chargeComplete = false;
  s.relayCmd = false;
  s.prechargeCmd = false;
  s.dischargeFetCmd = false;
  s.chargeFetCmd = false;
  s.relayOpenSince_ms = 0;
}

namespace {

bool eSwitchPulled(const Inputs& in) { return in.eSwitchInternal || in.eSwitchExternal; }
// While driving (state Normal) a MonitorWhileDriving fault only warns.
bool driving(const CoreState& s) { return s.state == State::Normal; }
bool fatal(const Config& cfg, const CoreState& s) { return fatalFaults(cfg, s.protection, driving(s)) != 0; }

// Where a request leads once the pack may be connected.
State connectedState(const Inputs& in) { return in.runRequest ? State::Normal : State::Charge; }

void startPrecharge(PrechargeState& p, uint32_t now_ms) {
  p.phase = PrechargePhase::Charging;
  p.phaseSince_ms = now_ms;
  p.attempts = 1;
}

// Init: every monitor IC must have answered once before anything may close.
State onInit(const Config& cfg, const CoreState& s, const Inputs&) {
  if (fatal(cfg, s)) return State::Error;
  return (!s.firstTick && acquisitionComplete(cfg, s.acq)) ? State::Standby : State::Init;
}

State onStandby(const Config& cfg, CoreState& s, const Inputs& in) {
  if (fatal(cfg, s)) return State::Error;
  if (eSwitchPulled(in) || !(in.runRequest || in.chargerPresent)) return State::Standby;
  if (!cfg.precharge.enabled) return connectedState(in);
  startPrecharge(s.precharge, in.now_ms);
  return State::Precharge;
}

// Precharge: charge the load capacitance through the resistor, then close the main
// relay while precharge still holds, then open precharge.
State onPrecharge(const Config& cfg, CoreState& s, const Inputs& in, const Telemetry& tm) {
  PrechargeState& p = s.precharge;
  if (fatal(cfg, s)) {
    p.phase = p.failed ? PrechargePhase::Failed : PrechargePhase::Idle;
    return State::Error;
  }
  if (eSwitchPulled(in) || !(in.runRequest || in.chargerPresent)) {
    p.phase = PrechargePhase::Idle;
    return State::Standby;
  }
  const uint32_t inPhase_ms = in.now_ms - p.phaseSince_ms;
  switch (p.phase) {
    case PrechargePhase::Charging: {
      const uint32_t pack = tm.packVoltage_mV, bus = tm.busVoltage_mV;
      const uint32_t gap_mV = pack > bus ? pack - bus : bus - pack;
      // The first tick after closing has not seen the path yet: wait one period.
      const bool settled = inPhase_ms >= cfg.tickPeriod_ms;
      if (settled && gap_mV < cfg.precharge.doneDelta_mV && magnitude(tm.packCurrent_mA) < cfg.precharge.doneCurrent_mA) {
        p.phase = PrechargePhase::Closing;
        p.phaseSince_ms = in.now_ms;
      } else if (inPhase_ms >= cfg.precharge.timeout_ms) {
        if (p.attempts > cfg.precharge.retries) {
          p.phase = PrechargePhase::Failed;
          p.failed = true;
        } else {
          p.phase = PrechargePhase::Pause;
          p.phaseSince_ms = in.now_ms;
        }
      }
      return State::Precharge;
    }
    case PrechargePhase::Pause:
      // Guard against rapid cycling: the resistor cools during the pause.
      if (inPhase_ms >= cfg.precharge.pause_ms) {
        p.phase = PrechargePhase::Charging;
        p.phaseSince_ms = in.now_ms;
        ++p.attempts;
      }
      return State::Precharge;
    case PrechargePhase::Closing:
      if (inPhase_ms >= cfg.precharge.overlap_ms) {
        p.phase = PrechargePhase::Done;
        return connectedState(in);
      }
      return State::Precharge;
    case PrechargePhase::Idle:
    case PrechargePhase::Done:
    case PrechargePhase::Failed:
      break;
  }
  return State::Precharge;
}

State onNormal(const Config& cfg, const CoreState& s, const Inputs& in) {
  if (fatal(cfg, s)) return State::Error;
  if (eSwitchPulled(in)) return State::Standby;
  if (!in.runRequest) return in.chargerPresent ? State::Charge : State::Standby;
  return State::Normal;
}

State onCharge(const Config& cfg, const CoreState& s, const Inputs& in) {
  if (fatal(cfg, s)) return State::Error;
  if (eSwitchPulled(in) || !in.chargerPresent) return State::Standby;
  if (in.runRequest) return State::Normal;
  return State::Charge;
}

// Error: leave only when no fatal fault is present any more *and* a person asks.
State onError(const Config& cfg, CoreState& s, const Inputs& in) {
  if (!in.resetRequest) return State::Error;
  clearLatched(s.protection);
  s.precharge.failed = false;
  s.precharge.phase = PrechargePhase::Idle;
  return fatal(cfg, s) ? State::Error : State::Standby;
}

// Quantities that depend on the core's own history rather than on a measurement.
void historyQuantities(const Config& cfg, const CoreState& s, const Inputs& in, const Telemetry& tm,
                       int32_t quantity[kQuantityCount]) {
  const bool openLongEnough =
      !s.relayCmd && !s.prechargeCmd && in.now_ms - s.relayOpenSince_ms >= cfg.weldSettle_ms && !s.firstTick;
  const bool flowing = magnitude(tm.packCurrent_mA) > cfg.weldCurrent_mA;
  const bool auxClosed = cfg.relayAuxFeedback && in.relayAux;
  quantity[static_cast<uint8_t>(Quantity::RelayStuckClosed)] = (openLongEnough && (flowing || auxClosed)) ? 1 : 0;
  quantity[static_cast<uint8_t>(Quantity::PrechargeFailed)] = s.precharge.failed ? 1 : 0;
}

// Both SOC estimates, the selected one as soc_permille, the capacity estimate and the
// SOC display.
void estimateTelemetry(const Config& cfg, const CoreState& s, uint16_t meanCell_mV, Telemetry& tm) {
  tm.socCoulomb = socValue(cfg.soc, s.soc);
  tm.socCoulombValid = s.soc.anchored;
  tm.socEkf = ekfPackSoc(s.ekf, cfg.cellCount, tm.socGroup_permille);
  tm.socEkfValid = s.ekf.started;
  const float soc = cfg.soc.estimator == SocEstimator::Ekf ? tm.socEkf : tm.socCoulomb;
  tm.soc_permille = static_cast<uint16_t>(soc * 1000.0f + 0.5f);
  tm.capacityEstimate_mAh = s.soc.capacityEstimate_mAh;
  tm.socDisplayBars = socDisplayBars(cfg.soc, meanCell_mV);
}

}  // namespace

void step(const Config& cfg, CoreState& s, const Inputs& in, Outputs& out) {
  Telemetry& tm = out.telemetry;
  const bool tempsMoved = measure(cfg, in, s.acq, tm, s.quantity);
  const bool complete = acquisitionComplete(cfg, s.acq);
  // Cell readings new since the last tick (a read-out arrived): the estimators correct
  // with them once; between read-outs they only predict with the current.
  const bool fresh = complete && s.acq.fresh;
  s.acq.fresh = false;
  s.acq.readOut = false;
  const uint16_t meanCell = static_cast<uint16_t>(cfg.cellCount > 0 ? tm.packVoltage_mV / cfg.cellCount : 0u);
  const bool member = packMember(cfg);
  if (member)
    packApplyShare(s.pack, tm, s.quantity);
  else if (cfg.pack.boards > 1)
    packMerge(cfg, s.pack, in.now_ms, tm, s.quantity);
  socUpdate(cfg.soc, s.soc, fresh, meanCell, tm.packCurrent_mA, in.now_ms);
  // A part measuring in a loop of its own: its cells go with the current of that loop.
  int32_t loop_mA = 0;
  const bool paired = loopCurrent(cfg, s.acq, loop_mA);
  ekfUpdate(cfg.soc, cfg.therm, s.ekf, cfg.cellCount, fresh, tm.cellVoltage_mV, tm.packCurrent_mA, tm.temperature_dC,
            in.now_ms, !tempsMoved, paired ? &loop_mA : nullptr);
  historyQuantities(cfg, s, in, tm, s.quantity);
  if (!member) protectionUpdate(cfg, s.quantity, in.now_ms, driving(s), s.protection);  // a member has no relay

  State next = s.state;
  switch (s.state) {
    case State::Init: next = onInit(cfg, s, in); break;
    case State::Standby: next = onStandby(cfg, s, in); break;
    case State::Precharge: next = onPrecharge(cfg, s, in, tm); break;
    case State::Normal: next = onNormal(cfg, s, in); break;
    case State::Charge: next = onCharge(cfg, s, in); break;
    case State::Error: next = onError(cfg, s, in); break;
  }
  s.state = next;
  s.firstTick = false;

  // Commands by state, then whatever the fault table keeps open.
  const PrechargePhase ph = s.precharge.phase;
  bool relay = false, precharge = false, dsg = false, chg = false;
  switch (s.state) {
    case State::Precharge:
      precharge = ph == PrechargePhase::Charging || ph == PrechargePhase::Closing;
      relay = ph == PrechargePhase::Closing;
      dsg = chg = true;  // the precharge path runs through the FETs
      break;
    case State::Normal: relay = dsg = chg = true; break;
    case State::Charge: relay = chg = true; break;
    case State::Error:
      // An error never closes anything; FETs stay as they were unless a fault opens
      // them (a relay-only fault leaves them closed, so a welded relay shows as current).
      dsg = s.dischargeFetCmd;
      chg = s.chargeFetCmd;
      break;
    case State::Init:
    case State::Standby: break;
  }
  const uint8_t blocked = openedActuators(cfg, s.protection, driving(s));
  const bool anyFatal = fatal(cfg, s);
  const bool pulled = eSwitchPulled(in);
  out.relayClose = relay && !anyFatal && !pulled && (blocked & kActRelay) == 0;
  out.prechargeClose = precharge && !anyFatal && !pulled && (blocked & kActRelay) == 0;
  out.dischargeFetOn = dsg && !pulled && (blocked & kActDischargeFet) == 0;
  out.chargeFetOn = chg && !pulled && (blocked & kActChargeFet) == 0;
  if (s.relayCmd && !out.relayClose) s.relayOpenSince_ms = in.now_ms;
  if (s.prechargeCmd && !out.prechargeClose && !out.relayClose) s.relayOpenSince_ms = in.now_ms;
  s.relayCmd = out.relayClose;
  s.prechargeCmd = out.prechargeClose;
  s.dischargeFetCmd = out.dischargeFetOn;
  s.chargeFetCmd = out.chargeFetOn;

  out.afeClearFaults = in.resetRequest;
  // Balancing: only with every monitor answering, no fatal fault, and in a state where
  // the pack is idle, driving or charging.
  // A member balances as the pack host permits.
  const bool balancePermitted =
      member ? complete && s.pack.share.seen && s.pack.share.balancePermitted
             : complete && !anyFatal && (s.state == State::Standby || s.state == State::Normal || s.state == State::Charge);
  const bool charging = member ? s.pack.share.charging : s.state == State::Charge;
  s.balancePermitted = balancePermitted;
  uint16_t packRange[2];
  const bool others = cfg.pack.boards > 1 && packBalanceRange(cfg, s.pack, packRange);
  balanceStep(cfg, s.balance, tm, balancePermitted, charging, fresh, in.now_ms, out.balanceMask, out.balanceArmCount,
              others ? packRange : nullptr);
  out.balanceStatus = static_cast<uint8_t>(s.balance.status);
  out.balanceTime_s = cfg.balanceTime_s;
  // Charger: enabled only while charging with the charge path closed and nothing acting
  // on the charge side; charging stops on any such fault.
  const bool chargeSideFault = (blocked & (kActRelay | kActChargeFet)) != 0;
  if (!in.chargerPresent) s.chargeComplete = false;
  if (cfg.chargeFullCell_mV > 0 && s.state == State::Charge && tm.maxCell_mV >= cfg.chargeFullCell_mV)
    s.chargeComplete = true;  // the first full cell ends the charge; balancing may go on
  out.chargerEnable = s.state == State::Charge && !anyFatal && !chargeSideFault && out.relayClose &&
                      out.chargeFetOn && cfg.chargeRequest_mA > 0 && !s.chargeComplete;
  out.chargerCurrentRequest_mA = out.chargerEnable ? cfg.chargeRequest_mA : 0;
  out.state = s.state;
  out.faultActive = s.protection.active;
  out.faultLatched = s.protection.latched;
  estimateTelemetry(cfg, s, meanCell, tm);
  tm.prechargePhase = static_cast<uint8_t>(s.precharge.phase);
  tm.prechargeAttempts = s.precharge.attempts;
}

}  // namespace bms
