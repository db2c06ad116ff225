#include "core/sim/bms_bridge.hpp"

#include <algorithm>

namespace packsim {

HardwareSim::HardwareSim(const Scenario& s, const Plant& plant)
    : s_(s), plant_(plant), sensors_(s, plant), switchgear_(s.hardware), balancing_(s), charger_(s.charger) {}

void HardwareSim::sample(double t, const PlantSignals& sig, const PlantSignals& unloaded, const HardwareFaults& f,
                         Rng& rng, bms::Inputs& in) {
  sensors_.sample(t, sig, unloaded, f, switchgear_.bus_V(), switchgear_.relayClosed(), rng, in);
}

SwitchDrive HardwareSim::switchDrive(const bms::Outputs& out) const {
  SwitchDrive d;
  d.relayPin = out.relayClose;
  d.prechargePin = out.prechargeClose;
  d.dischargePin = out.dischargeFetOn;
  d.chargePin = out.chargeFetOn;
  d.afeDischarge = sensors_.afeDischargeOn();
  d.afeCharge = sensors_.afeChargeOn();
  d.faultLine = st_.fault_line;
  return d;
}

void HardwareSim::report(const SwitchState& sw, const PlantSignals& sig) {
  switchgear_.report(sw, sig, st_);
  balancing_.report(st_);
  st_.charger_cv = charger_.cv();
  st_.charger_done = charger_.done();
}

void HardwareSim::watchUnsettledFets(double t, const SwitchDrive& d, const SwitchState& sw) {
  // The part's reason is asked for only where it tells something: the pin on, the driver off
  // (the usual tick: neither, and no string is made).
  static const std::string kNoCause;
  const bool askDsg = d.dischargePin && !d.afeDischarge, askChg = d.chargePin && !d.afeCharge;
  if (!askDsg && !askChg) return fets_.hold(t, d, sw, kNoCause, kNoCause);
  fets_.hold(t, d, sw, askDsg ? sensors_.afeFetOffCause(true) : kNoCause,
             askChg ? sensors_.afeFetOffCause(false) : kNoCause);
}

UnreadReport HardwareSim::unreadReport(double end_s) const {
  std::vector<const MonitorChainPath*> chains;
  for (size_t b = 0; b < boards().size(); ++b) chains.push_back(&sensors_.chain(static_cast<int>(b)));
  return packsim::unreadReport(s_, boards(), chains, end_s);
}

std::vector<std::string> HardwareSim::fetNotes(double end_s) const {
  const HardwareConfig& hw = s_.hardware;
  if (!hw.discharge_fet.present) return {};
  return fets_.notes(end_s, hw.fet_control, hw.afe.model, hw.charge_fet.present);
}

bool HardwareSim::actuate(double t, const bms::Outputs& out, const PlantSignals& sig, const HardwareFaults& f,
                          PlantInputs& pin) {
  st_.fault_line = sensors_.faultLine();
  const SwitchDrive d = switchDrive(out);
  const SwitchState sw = switchgear_.tick(t, s_.bms.tick_s, d, f, sig);
  watchFets(t, d, sw);
  bool changed = HwSwitchgear::apply(sw, plant_.fetNode() >= 0, pin);
  changed = balancing_.tick(t, sensors_, out, sig, pin) || changed;
  if (charger_.present())
    changed = charger_.tick(out.chargerEnable, out.chargerCurrentRequest_mA * 1e-3, sig, f, pin) || changed;
  changed = sensors_.applyBias(pin) || changed;
  report(sw, sig);
  return changed;
}

bool HardwareSim::actuatePins(double t, double tEnd, const bms::Outputs& out, const PlantSignals& sig,
                              const HardwareFaults& f, PlantInputs& pin) {
  const SwitchDrive d = switchDrive(out);
  const SwitchState sw = switchgear_.atPin(t, tEnd, d, f, sig, pin);
  watchFets(t, d, sw);
  bool changed = HwSwitchgear::apply(sw, plant_.fetNode() >= 0, pin);
  // The charger stops at once when its enable drops; it starts (and follows a new
  // current request) at its controller's next step, the tick's.
  if (charger_.present()) changed = charger_.atPin(out.chargerEnable, pin) || changed;
  report(sw, sig);
  return changed;
}

const PlantSignals& HardwareSim::measurementView(double t, const double* x, const PlantInputs& pin,
                                                 const PlantSignals& sig) {
  if (std::none_of(pin.balancing.begin(), pin.balancing.end(), [](uint8_t b) { return b != 0; })) return sig;
  if (pausedSig_.cell_current_A.empty()) pausedSig_ = plant_.makeSignals();
  pausedInputs_ = pin;
  std::fill(pausedInputs_.balancing.begin(), pausedInputs_.balancing.end(), 0);
  plant_.evaluate(t, x, pausedInputs_, pausedSig_);
  return pausedSig_;
}

}  // namespace packsim
