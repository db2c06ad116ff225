// Time to balance a pack with passive balancing resistors: for each resistor value,
//
//   analytic    t = ΔQ / I,  I = V_cell / (R + Rds_on)   (constant current at V_cell)
//   simulated   the full co-simulation at rest (no load, balancing always allowed,
//               1 s BMS tick): the firmware's policy (start at target_mV, stop at half
//               of it) drives the monitor ICs, the cells drain through their resistors
//               and heat the board node. It ends when the true rest voltages (OCV) are
//               within target_mV or the charge difference is removed, or when the BMS
//               has stopped balancing for a minute (then the time it last balanced is
//               reported), or after max_hours.
//
// The imbalance is either given (delta_Ah: `high_cells` series cells start at cell_V,
// the others delta_Ah lower; the scenario's spread is not used) or the scenario's own
// initial state (delta = largest minus smallest series-group charge). The simulated time
// is longer than the analytic one mainly because the current falls as the high cells'
// voltage drops while they drain (the analytic figure holds the starting voltage).
//
// Plain structs in and out, no CLI types: the CLI (`packsim balance-time`) and the
// Python module call the same function.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"

namespace packsim {

struct BalanceTimeOptions {
  std::vector<double> resistors_ohm;  // one row each; empty: the scenario's hardware.balancing resistor
  std::optional<double> delta_Ah;     // imbalance to remove per high cell; unset: the scenario's initial state
  std::optional<double> cell_V;       // voltage of the analytic estimate (and of the high cells at the start)
  int high_cells = 1;                 // series cells that start high (with delta_Ah)
  double target_mV = 5.0;             // balanced when max - min is below this
  double max_hours = 72.0;            // simulation cap
  bool simulate = true;               // false: analytic estimate only
};

struct BalanceTimeRow {
  double resistor_ohm = 0.0;
  double branch_ohm = 0.0;            // resistor + FET Rds_on
  double current_A = 0.0;             // per cell at cell_V
  double power_W = 0.0;               // per cell at cell_V
  double board_power_W = 0.0;         // every high cell balancing at cell_V
  double analytic_h = 0.0;
  bool simulated = false;
  double simulated_h = 0.0;
  std::string end_reason;             // within_target | charge_removed | bms_stopped | time_limit | not_started
  double peak_board_C = 0.0;          // NaN without a board thermal node
  double energy_Wh = 0.0;             // dissipated in the balancing branches
  double charge_removed_Ah = 0.0;     // Σ ∫ I_bal dt over every cell
  double final_spread_Ah = 0.0;       // largest minus smallest series-group charge at the end
};

struct BalanceTimeResult {
  std::string scenario;
  double delta_Ah = 0.0;
  double cell_V = 0.0;
  int high_cells = 1;
  double target_mV = 0.0;
  std::vector<BalanceTimeRow> rows;
};

// Throws std::invalid_argument on a bad option (message names the option and its range).
BalanceTimeResult balanceTime(const Scenario& base, const BalanceTimeOptions& options);

// SOC at which the cell's OCV equals v (bisection on the increasing OCV curve).
double socAtOcv(const CellParams& cell, double v);

}  // namespace packsim
