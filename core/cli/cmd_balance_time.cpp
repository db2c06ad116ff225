// `packsim balance-time`: time to balance per resistor, analytic and simulated
// (core/balance/balance_time.hpp), printed as a table.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "core/balance/balance_time.hpp"
#include "core/cli/commands.hpp"
#include "core/scenario/yaml_map.hpp"
#include "core/scenario/load_scenario.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

void printTable(const BalanceTimeResult& r, std::ostream& os) {
  char line[256];
  std::snprintf(line, sizeof line, "balance-time  %s: %.3f Ah to remove, cells at %.3f V, %d high cell%s, target %.0f mV\n",
                r.scenario.c_str(), r.delta_Ah, r.cell_V, r.high_cells, r.high_cells == 1 ? "" : "s", r.target_mV);
  os << line;
  os << "  R_ohm    I_mA  P_cell_W  board_W  analytic_h  simulated_h  sim/ana  removed_Ah  peak_board_C  energy_Wh  end\n";
  for (const BalanceTimeRow& w : r.rows) {
    std::snprintf(line, sizeof line, "%7.1f  %6.2f  %8.3f  %7.2f  %10.2f", w.resistor_ohm, w.current_A * 1e3,
                  w.power_W, w.board_power_W, w.analytic_h);
    os << line;
    if (w.simulated) {
      const std::string peak = std::isnan(w.peak_board_C) ? "-" : [&] {
        char b[32];
        std::snprintf(b, sizeof b, "%.1f", w.peak_board_C);
        return std::string(b);
      }();
      std::snprintf(line, sizeof line, "  %11.2f  %7.3f  %10.3f  %12s  %9.3f  %s\n", w.simulated_h,
                    w.analytic_h > 0 ? w.simulated_h / w.analytic_h : 0.0, w.charge_removed_Ah, peak.c_str(),
                    w.energy_Wh, w.end_reason.c_str());
      os << line;
    } else {
      os << "\n";
    }
  }
  os << "analytic: delta / (V_cell / (R + Rds_on)) at constant current and V_cell. simulated: the pack at rest,\n"
        "the BMS policy balancing until the rest voltages are within the target; longer because the current\n"
        "falls as the high cells drain and their voltage drops.\n";
}

}  // namespace

int cmdBalanceTime(const BalanceTimeCliOptions& o) {
  if (!o.scenario.empty() && !o.preset.empty()) throw std::invalid_argument("give a scenario file or --preset, not both");
  const std::string path = !o.scenario.empty() ? o.scenario
                           : presetPath(o.preset.empty() ? std::string("bench_6s_balancing") : o.preset);
  const Scenario s = loadScenarioFile(path);
  BalanceTimeOptions opt;
  opt.resistors_ohm = o.resistors_ohm;
  opt.delta_Ah = o.delta_Ah;
  opt.cell_V = o.cell_V;
  opt.high_cells = o.high_cells;
  opt.target_mV = o.target_mV;
  opt.max_hours = o.max_hours;
  opt.simulate = !o.analytic_only;
  if (o.cell_V && !o.delta_Ah) throw std::invalid_argument("--cell-V needs --delta-Ah (the imbalance it applies to)");
  printTable(balanceTime(s, opt), std::cout);
  return 0;
}

}  // namespace packsim
