// HardwareSim's charger: the CC-CV controller (models/hw/charger.hpp) under the BMS's
// enable pin and current request, with a scripted output overvoltage on its setpoint.
//
//   tick()    the controller's step, once per tick: the limit and setpoint for the next one
//   atPin()   inside a tick, the enable dropped: the charger stops at once (it starts, and
//             follows a new request, at the controller's next step)
#pragma once
#include "core/sim/hardware_faults.hpp"
#include "core/sim/plant.hpp"
#include "models/hw/charger.hpp"

namespace packsim {

class HwCharger {
 public:
  explicit HwCharger(const ChargerConfig& c) : c_(c) {}

  // True when the limit or setpoint in `pin` changed.
  bool tick(bool enable, double request_A, const PlantSignals& sig, const HardwareFaults& f, PlantInputs& pin);
  bool atPin(bool enable, PlantInputs& pin) const;

  bool present() const { return c_.present; }
  bool cv() const { return state_.cv; }
  bool done() const { return state_.done; }

 private:
  const ChargerConfig& c_;
  ChargerState state_;
};

}  // namespace packsim
