// Time to balance a pack with passive balancing resistors, per resistor value:
//
//   analytic      at constant current I = V_cell / (R + Rds_on): all of ΔQ, and the
//                 charge to remove until the high group's OCV is within target_mV of the
//                 low group's (the simulated true_h's criterion); the OCV-droop form
//                 t = (R + Rds_on)·∫dQ/OCV(Q) to the same target
//                 (core/balance/balance_analytic); the board's steady temperature
//                 T_amb + P/G with every high cell on it balancing at V_cell
//   simulated     the full co-simulation at rest (no load) with the firmware exactly as
//                 the scenario configures it: start/stop thresholds, decision period,
//                 `when`, `no_adjacent`, minimum cell voltage, board pause, averaging,
//                 the monitor's balancing timer. Only the BMS tick is raised to at least
//                 1 s (decisions at 1 Hz are ample; docs/reference-systems.md D), within
//                 half a monitor's link timeout. Two times come out:
//       firmware_h  when the firmware declared balanced (its status went to Balanced
//                   after balancing and stayed there); NaN if it never did, with why
//       true_h      when the true rest voltages (OCV) of all series groups first came
//                   within target_mV: the target only measures, it changes nothing in
//                   the firmware
//                 The run ends once both are known, when the firmware has stopped for
//                 good without reaching the target, or after max_hours.
//   during charge on the scenario's charger (CC-CV) from the same state: top balancing
//                 while the charger holds CV; the run ends when the charge ends (the
//                 charger's own end; or the BMS switched it off, kept it off, and stopped
//                 balancing: the note says when, on what, and the imbalance left), and a
//                 second run without balancing gives the charge time balancing adds.
//
// The imbalance is either given (delta_Ah: `high_cells` series cells start at cell_V,
// the others delta_Ah lower; the scenario's spread is not used) or the scenario's own
// initial state (delta = the most charge a series group holds above the lowest group's
// rest voltage: core/sim/balance_report.hpp groupExcess_Ah; the high cells = the groups
// more than the firmware's stop threshold above the lowest).
//
// Honest columns: the charge each group needed to lose is its charge above the lowest
// group's rest voltage at the start; what a group bled up to that is useful, beyond it (or from a
// group that needed nothing) wasted. Heat is every joule the branches dissipated.
//
// Plain structs in and out, no CLI types: the CLI (`packsim balance-time`) and the
// Python module call the same function.
#pragma once
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "core/balance/balance_analytic.hpp"
#include "core/scenario/scenario.hpp"

namespace packsim {

struct BalanceTimeOptions {
  std::vector<double> resistors_ohm;  // one row each; empty: the scenario's hardware.balancing resistor
  std::optional<double> delta_Ah;     // imbalance to remove per high cell; unset: the scenario's initial state
  std::optional<double> cell_V;       // voltage of the analytic estimate (and of the high cells at the start)
  int high_cells = 1;                 // series cells that start high (with delta_Ah)
  std::optional<double> target_mV;    // truth criterion: OCV max - min below this; unset: 1.5 × the firmware's stop_delta_mV
  double max_hours = 72.0;            // simulation cap
  bool simulate = true;               // false: analytic estimates only
  // Stated changes to the experiment (printed with the table, never silent):
  std::optional<std::string> when;    // replace bms.balancing.when (e.g. "always" for a charge-only firmware at rest)
  bool during_charge = false;         // on the scenario's charger (CC-CV) instead of at rest: top balancing
};

struct BalanceTimeRow {
  double resistor_ohm = 0.0;
  double branch_ohm = 0.0;            // resistor + FET Rds_on
  double current_A = 0.0;             // per cell at cell_V
  double power_W = 0.0;               // per branch at cell_V
  double board_power_W = 0.0;         // the most loaded board, every high cell on it balancing at cell_V
  double resistor_W = 0.0;            // in the resistor alone at the cell's v_max_V (worst case)
  bool within_rating = true;          // resistor_W <= hardware.balancing.resistor_power_rating_W (true if not stated)
  double const_I_all_h = 0.0;         // all of ΔQ / (V_cell / (R + Rds_on))
  double const_I_to_target_h = 0.0;   // the charge until the high OCV is within target_mV of the low, / I
  double droop_to_target_h = 0.0;     // (R + Rds_on)·∫dQ/OCV(Q) until the high OCV is within target_mV of the low
  double board_steady_C = 0.0;        // T_amb + board_power_W / G of the board node; NaN without one
  bool simulated = false;
  double firmware_h = 0.0;            // NaN: never declared balanced (firmware_note says why)
  std::string firmware_note;
  double true_h = 0.0;                // NaN: the rest voltages never came within target_mV
  std::string end_reason;             // both_known | firmware_overran | firmware_stopped | not_started | tripped |
                                      // charge_done | charge_done_unbalanced | charge_ended_by_bms |
                                      // time_limit
  double peak_board_C = 0.0;          // the hottest board's peak; NaN without a board thermal node
  std::vector<double> board_peak_C;   // per monitor board
  double paused_fraction = 0.0;       // of the run up to true_h (or its end), paused on board temperature
  double bled_Ah = 0.0;               // Σ over groups of ∫ I_bal dt
  double pack_useful_Ah = 0.0;        // Σ over groups of what each bled up to the charge it had above the lowest group's rest voltage
  double pack_wasted_Ah = 0.0;        // Σ over groups of what each bled beyond that (bled - useful)
  double needed_Ah = 0.0;             // Σ of the charge above the lowest group's rest voltage at the start
  double pack_heat_Wh = 0.0;          // Σ over the balancing branches of their heat
  double final_spread_Ah = 0.0;       // largest minus smallest series-group charge at the end
  double final_imbalance_Ah = 0.0;    // the most charge a group holds above the lowest group's rest voltage at the end
  bool tripped = false;               // a protection tripped during the run
  bool within_limits = false;         // reached the target, no trip, resistor within its rating
  bool fastest = false;               // the smallest true_h among rows within limits
  // During charge only (NaN otherwise): when the charger last delivered more than its end
  // current with this resistor balancing, the same without balancing (a firmware that ends
  // the charge on its first full cell stops early, the low cells short), and the difference.
  double charge_h = NAN;
  double charge_without_h = NAN;
  double charge_added_h = NAN;
};

struct BalanceTimeResult {
  std::string scenario;
  double delta_Ah = 0.0;
  bool delta_given = false;  // delta_Ah and high_cells as given; else the scenario's own (its highest group)
  double cell_V = 0.0;
  int high_cells = 1;
  int parallel = 1;  // cells in parallel in a series group (a "high cell" is a group of them)
  double target_mV = 0.0;
  double resistor_rating_W = 0.0;     // hardware.balancing.resistor_power_rating_W (0: not stated)
  double board_max_C = 0.0;           // the firmware's board pause threshold
  std::string when;                   // bms.balancing.when as simulated
  bool when_overridden = false;       // --when replaced the scenario's
  bool during_charge = false;
  std::vector<std::string> warnings;  // config_warning events of the simulated runs (once each)
  std::vector<BalanceTimeRow> rows;
};

// Throws std::invalid_argument on a bad option (message names the option and its range).
BalanceTimeResult balanceTime(const Scenario& base, const BalanceTimeOptions& options);

}  // namespace packsim
