// Inputs a driver outside the scenario sets (an FMU's importer). Each field left unset
// keeps the scenario's own value or profile, so a run with none set is `packsim run`.
//
//   load_A_or_W   the load, in the scenario's load quantity (current A, positive
//                 discharges, or power W); held constant from the tick it is applied
//   ambient_C     ambient temperature, replaces the scenario's ambient profile
//   estop_*       E-switch pins (true = pulled), replace the scripted E-switch faults
//   charger_present  the charger-detect pin the BMS reads (the charger's own current
//                 still comes from the scenario's `charger:` model)
//
// The loop applies them at the start of every tick and of every plant advance.
#pragma once
#include <bms/bms_hal.hpp>

#include <optional>

#include "core/sim/plant.hpp"

namespace packsim {

struct ExternalInputs {
  std::optional<double> load_A_or_W;
  std::optional<double> ambient_C;
  std::optional<bool> estop_internal_pulled;
  std::optional<bool> estop_external_pulled;
  std::optional<bool> charger_present;

  // Into the plant's held inputs at t; true when one of them changed (the integrator
  // restarts there). Both inline: the loop calls them three times a tick, and with none
  // set (every `packsim run`) each call was the whole cost.
  bool applyToPlant(double t, PlantInputs& pin) const { return (load_A_or_W || ambient_C) && applySome(t, pin); }
  // Into the pins the firmware reads, after the hardware sampled them.
  void applyToPins(bms::Inputs& in) const {
    if (estop_internal_pulled) in.eSwitchInternal = *estop_internal_pulled;
    if (estop_external_pulled) in.eSwitchExternal = *estop_external_pulled;
    if (charger_present) in.chargerPresent = *charger_present;
  }

 private:
  bool applySome(double t, PlantInputs& pin) const;  // applyToPlant with the load or ambient set
};

}  // namespace packsim
