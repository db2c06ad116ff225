// Passive balancing hardware: per series cell (group) a resistor and a FET switch
// across its terminals.
//
//   I_bal = V_cell / (R + Rds_on)          while the monitor IC holds the switch on
//   heat  = I_bal² · (R + Rds_on) = V_cell · I_bal   into the balancing-board node
//
// The cell sees I_bal as extra discharge current. With the group as a Thevenin source
// (E, R_g) carrying the string current I, the terminal voltage is closed-form:
//   V = (E - R_g·I) · k,   k = 1 / (1 + R_g/(R + Rds_on))
// Units: Ω, A, V, W.
#pragma once
#include <string>

namespace packsim {

struct PassiveBalancerConfig {
  bool present = false;
  double resistor_ohm = 47.0;
  double rds_on_ohm = 0.0;
  std::string board_node;     // thermal node that takes the heat; "" = lost to ambient directly
  int board_thermistors = 0;  // thermistors on the board node (channels after the cell thermistors)

  double branch_ohm() const { return resistor_ohm + rds_on_ohm; }
  double current_A(double cell_V) const { return cell_V > 0.0 ? cell_V / branch_ohm() : 0.0; }
  // Factor on the group's open-circuit-under-load voltage when its switch is on.
  double loadedFactor(double group_r_ohm) const { return 1.0 / (1.0 + group_r_ohm / branch_ohm()); }
};

}  // namespace packsim
