#include "core/sim/hw_fet_watch.hpp"

#include <cstdio>

namespace packsim {

namespace {

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f s", s);
  return buf;
}

}  // namespace

void FetWatch::advance(Levels& l, double dt) {
  if (l.pin) l.pin_s += dt;
  if (l.driver) l.driver_s += dt;
  if (l.gate) l.gate_s += dt;
}

void FetWatch::set(Levels& l, bool pin, bool driver, bool gate, const std::string& cause) {
  l.pin = pin;
  l.driver = driver;
  l.gate = gate;
  l.pinEver = l.pinEver || pin;
  l.driverEver = l.driverEver || driver;
  l.gateEver = l.gateEver || gate;
  if (pin && !driver && !cause.empty()) l.cause = cause;
}

void FetWatch::hold(double t, const SwitchDrive& d, const SwitchState& s, const std::string& dsgCause,
                    const std::string& chgCause) {
  const double dt = t > since_s_ ? t - since_s_ : 0.0;
  since_s_ = t > since_s_ ? t : since_s_;
  // A FET whose gate was on once is settled: notes() never reads its levels again, so
  // they are no longer kept (the usual tick: both, and nothing to do).
  if (!dsg_.gateEver) advance(dsg_, dt), set(dsg_, d.dischargePin, d.afeDischarge, s.dsg, dsgCause);
  if (!chg_.gateEver) advance(chg_, dt), set(chg_, d.chargePin, d.afeCharge, s.chg, chgCause);
}

std::string FetWatch::note(const Levels& l, bool discharge, FetControl control, const std::string& part) {
  const std::string fet = discharge ? "discharge FET" : "charge FET";
  const std::string pin = std::string("the MCU's ") + (discharge ? "discharge" : "charge") + " FET pin";
  const std::string driver = "the " + part + "'s " + (discharge ? "DSG" : "CHG") + " driver";
  const std::string why = l.cause.empty() ? "" : " (" + l.cause + ")";
  std::string line = fet + " off all run: ";
  switch (control) {
    case FetControl::Afe:
      if (l.driverEver || !l.pinEver) return "";
      return line + driver + " never on" + why + " while " + pin + " was on for " + seconds(l.pin_s) +
             "; hardware.fet_control: afe -- the pin does not reach the gate, the firmware turns the FETs on over the bus";
    case FetControl::AfeAndMcu:
      if (l.pinEver && !l.driverEver)
        return line + driver + " never on" + why + " while " + pin + " was on for " + seconds(l.pin_s) +
               "; hardware.fet_control: afe_and_mcu -- both must be on";
      if (l.driverEver && !l.pinEver)
        return line + pin + " never on while " + driver + " was on for " + seconds(l.driver_s) +
               "; hardware.fet_control: afe_and_mcu -- the pin holds the gate off (" +
               (discharge ? "DFETOFF" : "CFETOFF") + ")";
      if (l.driverEver && l.pinEver)
        return line + pin + " (on for " + seconds(l.pin_s) + ") and " + driver + " (on for " + seconds(l.driver_s) +
               ") were never on at the same time; hardware.fet_control: afe_and_mcu -- both must be on";
      return "";
    case FetControl::Mcu: return "";  // the gate is the pin: on whenever it was asked
  }
  return "";
}

std::vector<std::string> FetWatch::notes(double end_s, FetControl control, const std::string& part,
                                         bool chargeFet) const {
  Levels d = dsg_, c = chg_;
  const double dt = end_s > since_s_ ? end_s - since_s_ : 0.0;
  advance(d, dt);
  advance(c, dt);
  std::vector<std::string> out;
  if (!d.gateEver) {
    const std::string n = note(d, true, control, part);
    if (!n.empty()) out.push_back(n);
  }
  if (chargeFet && !c.gateEver) {
    const std::string n = note(c, false, control, part);
    if (!n.empty()) out.push_back(n);
  }
  return out;
}

}  // namespace packsim
