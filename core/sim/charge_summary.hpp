// What the BMS did with the charger in a run on one (load.charger): when it first
// enabled it, and when it switched it off for good with the truth at that tick -- the
// highest cell's voltage and the charge current it was read under, the pack's mean SOC
// -- so a charge that ends on a cell's loaded voltage, far from full, says so. The
// summary's `charge` line and the /summary attributes charge_* (core/sim/summary_fields.cpp).
#pragma once

namespace packsim {

struct ChargeSummary {
  bool present = false;        // the scenario has a charger
  double on_s = -1.0;          // the BMS first enabled the charger (-1: never)
  double off_s = -1.0;         // it last disabled it and never enabled it again (-1: on at the end, or never on)
  int off_cell = 0;            // 1-based: the highest cell at off_s (truth)
  double off_cell_V = 0.0;     // its terminal voltage then
  double off_current_A = 0.0;  // the charge current then (> 0: into the pack)
  double off_soc_mean = 0.0;   // the pack's mean true SOC then
};

}  // namespace packsim
