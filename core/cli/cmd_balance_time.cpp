// `packsim balance-time`: time to balance per resistor, analytic and simulated
// (core/balance/balance_time.hpp), printed as a table.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include "core/balance/balance_table.hpp"
#include "core/balance/balance_time.hpp"
#include "core/cli/commands.hpp"
#include "core/cli/python_module.hpp"
#include "core/scenario/yaml_map.hpp"
#include "core/scenario/load_scenario.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

// The table as CSV beside the PNG, then `python3 -m packsim.balance_plot CSV PNG` draws it.
void plotBalanceTime(const BalanceTimeResult& r, const std::string& png) {
  const std::string csv = fs::path(png).replace_extension(".csv").string();
  {
    std::ofstream f(csv);
    if (!f) throw std::runtime_error("--plot: cannot write " + csv);
    f << "resistor_ohm,const_I_all_h,const_I_to_target_h,droop_to_target_h,firmware_h,true_h,board_steady_C,"
         "peak_board_C,paused_fraction,resistor_W,within_rating,within_limits,fastest\n";
    f.precision(10);
    for (const BalanceTimeRow& w : r.rows)
      f << w.resistor_ohm << ',' << w.const_I_all_h << ',' << w.const_I_to_target_h << ',' << w.droop_to_target_h
        << ',' << w.firmware_h << ',' << w.true_h << ',' << w.board_steady_C << ',' << w.peak_board_C << ',' << w.paused_fraction << ',' << w.resistor_W << ','
        << w.within_rating << ',' << w.within_limits << ',' << w.fastest << '\n';
  }
  const int rc = runPythonModule("packsim.balance_plot", {csv, png, "--title", r.scenario, "--board-max-C",
                                                     std::to_string(r.board_max_C)},
                                 "numpy and matplotlib");
  if (rc != 0) throw std::runtime_error("--plot: python3 -m packsim.balance_plot failed (exit " + std::to_string(rc) + ")");
  std::cout << "wrote " << png << " (table in " << csv << ")\n";
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
  if (!o.when.empty()) opt.when = o.when;
  opt.during_charge = o.during_charge;
  if (o.cell_V && !o.delta_Ah) throw std::invalid_argument("--cell-V needs --delta-Ah (the imbalance it applies to)");
  const BalanceTimeResult r = balanceTime(s, opt);
  std::cout << balanceTimeTable(r);
  if (!o.plot.empty()) plotBalanceTime(r, o.plot);
  return 0;
}

}  // namespace packsim
