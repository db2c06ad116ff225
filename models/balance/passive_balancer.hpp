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
  int board_thermistors = 0;  // thermistors on each board node (channels after the cell thermistors)
  // Monitor boards: cells [b·cells_per_board, (b+1)·cells_per_board) bleed into board b's
  // node (board_node for the first, copies "board_node 2", "board_node 3", … for the
  // others); 0 = one board for every cell. `boards` is set by the loader from the pack.
  int cells_per_board = 0;
  int boards = 1;
  double resistor_power_rating_W = 0.0;  // per resistor; 0 = not stated

  int boardOf(int group) const { return cells_per_board > 0 ? group / cells_per_board : 0; }
  // Thermal node name of board b.
  std::string boardNodeName(int b) const { return b == 0 ? board_node : board_node + " " + std::to_string(b + 1); }

  double branch_ohm() const { return resistor_ohm + rds_on_ohm; }
  double current_A(double cell_V) const { return cell_V > 0.0 ? cell_V / branch_ohm() : 0.0; }
  // Factor on the group's open-circuit-under-load voltage when its switch is on.
  double loadedFactor(double group_r_ohm) const { return 1.0 / (1.0 + group_r_ohm / branch_ohm()); }
};

}  // namespace packsim
