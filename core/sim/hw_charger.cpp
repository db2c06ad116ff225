#include "core/sim/hw_charger.hpp"

namespace packsim {

bool HwCharger::tick(bool enable, double request_A, const PlantSignals& sig, const HardwareFaults& f,
                     PlantInputs& pin) {
  const double setpoint = c_.voltage_V + f.charger_overvoltage_V;
  const double limit = chargerStep(c_, state_, enable, request_A, sig.charger_A, sig.pack_voltage_V, setpoint);
  const bool changed = limit != pin.charger_limit_A || setpoint != pin.charger_setpoint_V;
  pin.charger_limit_A = limit;
  pin.charger_setpoint_V = setpoint;
  return changed;
}

bool HwCharger::atPin(bool enable, PlantInputs& pin) const {
  if (enable || pin.charger_limit_A == 0.0) return false;
  pin.charger_limit_A = 0.0;
  return true;
}

}  // namespace packsim
