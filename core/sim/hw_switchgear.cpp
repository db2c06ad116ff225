#include "core/sim/hw_switchgear.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <type_traits>

#include "core/sim/hw_status.hpp"
#include "core/sim/same_instant.hpp"
#include "models/hw/mosfet.hpp"
#include "models/hw/precharge.hpp"

namespace packsim {

HwSwitchgear::HwSwitchgear(const HardwareConfig& hw) : hw_(hw) {
  for (int dsg = 0; dsg < 2; ++dsg)
    for (int chg = 0; chg < 2; ++chg) {
      passesDischarge_[dsg][chg] = fetPairConducts(hw.fet_paths, hw.discharge_fet, dsg != 0, hw.charge_fet, chg != 0, 1.0);
      passesCharge_[dsg][chg] = fetPairConducts(hw.fet_paths, hw.discharge_fet, dsg != 0, hw.charge_fet, chg != 0, -1.0);
    }
}

// The lines compared as their bytes (one or two loads, not a key built bit by bit).
static_assert(std::has_unique_object_representations_v<SwitchDrive>, "SwitchDrive's bytes are its lines");

SwitchState HwSwitchgear::gates(double t, const SwitchDrive& d, const HardwareFaults& f) {
  const bool same = std::memcmp(&d, &gatesDrive_, sizeof d) == 0 && f.relay_welded == gatesWelded_ &&
                    fuse_.blown == gatesBlown_;
  if (gatesKept_ && same) return gates_;
  gates_ = gatesAnew(t, d, f);
  gatesDrive_ = d;
  gatesWelded_ = f.relay_welded;
  gatesBlown_ = fuse_.blown;
  // Both relays where their coils take them: the same lines step neither (relayStep's
  // settled test), and the gates and paths follow from the lines and the fuse alone.
  gatesKept_ = relay_.closed == relay_.coil && precharge_.closed == precharge_.coil;
  return gates_;
}

SwitchState HwSwitchgear::gatesAnew(double t, const SwitchDrive& d, const HardwareFaults& f) {
  // The monitor FAULT line sits in series with the relay drive: it opens the relay
  // whatever the MCU commands.
  const bool drive = !(hw_.fault_line_opens_relay && d.faultLine);
  relayWelded_ = f.relay_welded;
  relayStep(hw_.relay, relay_, d.relayPin && drive, f.relay_welded, t);
  relayStep(hw_.precharge_relay, precharge_, d.prechargePin && drive, false, t);
  SwitchState s;
  s.dsg = fetGateOn(hw_.fet_control, d.dischargePin, d.afeDischarge);
  s.chg = fetGateOn(hw_.fet_control, d.chargePin, d.afeCharge);
  s.dischargeBlocked = fuse_.blown || !passesDischarge_[s.dsg][s.chg];
  s.chargeBlocked = fuse_.blown || !passesCharge_[s.dsg][s.chg];
  s.mainClosed = relay_.closed && !fuse_.blown;
  return s;
}

SwitchState HwSwitchgear::tick(double t, double dt, const SwitchDrive& d, const HardwareFaults& f,
                               const PlantSignals& sig) {
  // The current of the tick that just ended heats the fuse (before the paths are
  // judged: a fuse that blew opens them now).
  fuseStep(hw_.fuse, fuse_, sig.pack_current_A, dt);
  SwitchState s = gates(t, d, f);
  if (s.mainClosed) {
    bus_V_ = sig.pack_voltage_V;
  } else if (precharge_.closed && !s.dischargeBlocked) {
    s.precharge_A = prechargeStep(hw_.precharge, sig.pack_voltage_V, bus_V_, dt);
  } else {
    busIdleStep(hw_.precharge, bus_V_, dt);
  }
  return s;
}

SwitchState HwSwitchgear::atPin(double t, double tEnd, const SwitchDrive& d, const HardwareFaults& f,
                                const PlantSignals& sig, const PlantInputs& held) {
  const bool prechargeWas = !held.relay_closed && precharge_.closed && !held.discharge_blocked;  // the RC already runs
  SwitchState s = gates(t, d, f);
  s.precharge_A = held.precharge_A;
  if (s.mainClosed) {
    bus_V_ = sig.pack_voltage_V;
    s.precharge_A = 0.0;
  } else if (precharge_.closed && !s.dischargeBlocked) {
    if (!prechargeWas && tEnd > t) s.precharge_A = prechargeStep(hw_.precharge, sig.pack_voltage_V, bus_V_, tEnd - t);
  } else {
    s.precharge_A = 0.0;
  }
  return s;
}

double HwSwitchgear::nextSwitch_s(double t) const {
  double next = std::numeric_limits<double>::infinity();
  const auto pending = [&](const RelayConfig& c, const RelayState& r, bool welded) {
    double at = std::numeric_limits<double>::infinity();
    if (r.coil && !r.closed) at = r.coilChanged_s + c.close_delay_s;
    if (!r.coil && r.closed && !welded) at = r.coilChanged_s + c.open_delay_s;
    if (at > t + sameInstantTol_s(at)) next = std::min(next, at);
  };
  pending(hw_.relay, relay_, relayWelded_);
  pending(hw_.precharge_relay, precharge_, false);
  return next;
}

bool HwSwitchgear::apply(const SwitchState& s, bool fetHeats, PlantInputs& pin) {
  const bool changed = pin.relay_closed != s.mainClosed || pin.precharge_A != s.precharge_A ||
                       pin.discharge_blocked != s.dischargeBlocked || pin.charge_blocked != s.chargeBlocked ||
                       (fetHeats && (pin.discharge_fet_on != s.dsg || pin.charge_fet_on != s.chg));
  pin.relay_closed = s.mainClosed;
  pin.precharge_A = s.precharge_A;
  pin.discharge_blocked = s.dischargeBlocked;
  pin.charge_blocked = s.chargeBlocked;
  pin.discharge_fet_on = s.dsg;
  pin.charge_fet_on = s.chg;
  return changed;
}

void HwSwitchgear::report(const SwitchState& s, const PlantSignals& sig, HardwareStatus& st) const {
  st.relay_closed = relay_.closed;
  st.precharge_closed = precharge_.closed;
  st.fuse_blown = fuse_.blown;
  st.discharge_fet_on = s.dsg;
  st.charge_fet_on = s.chg;
  st.bus_V = bus_V_;
  st.precharge_A = s.precharge_A;
  st.fet_loss_W = mosfetLoss_W(hw_.discharge_fet, s.dsg, fetCurrent_A(hw_.fet_paths, true, sig.pack_current_A)) +
                  mosfetLoss_W(hw_.charge_fet, s.chg, fetCurrent_A(hw_.fet_paths, false, sig.pack_current_A));
}

}  // namespace packsim
