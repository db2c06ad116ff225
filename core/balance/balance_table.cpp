#include "core/balance/balance_table.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace packsim {

namespace {

std::string num(double v, const char* f) {
  if (std::isnan(v)) return "-";
  char b[32];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

std::string balanceTimeTable(const BalanceTimeResult& r) {
  std::ostringstream os;
  char line[400];
  // With cells in parallel a "cell" of the table is a series group: its resistor bleeds them all.
  const std::string high = std::to_string(r.high_cells) + (r.parallel > 1 ? " high series group" : " high cell") +
                           (r.high_cells == 1 ? "" : "s") +
                           (r.parallel > 1 ? " (" + std::to_string(r.parallel) + " cells in parallel each)" : "");
  std::snprintf(line, sizeof line, "balance-time  %s: %.3f Ah to remove%s, cells at %.3f V, %s, true target %.1f mV\n",
                r.scenario.c_str(), r.delta_Ah, r.delta_given ? "" : " (the scenario's highest group)", r.cell_V,
                high.c_str(), r.target_mV);
  os << line;
  os << "firmware as configured (bms.balancing.when: " << r.when << (r.when_overridden ? ", set by --when" : "")
     << ")" << (r.during_charge ? ", on the scenario's charger" : ", at rest") << "\n";
  for (const std::string& w : r.warnings) os << "warning: " << w << "\n";
  os << "  R_ohm  cell_I_mA  board_W  resistor_W  const_I_all_h  const_I_to_target_h  droop_to_target_h  "
        "true_h  firmware_h  board_steady_C  peak_board_C  paused_%  pack_useful_Ah  pack_wasted_Ah  pack_heat_Wh  end\n";
  for (const BalanceTimeRow& w : r.rows) {
    std::snprintf(line, sizeof line, "%c%6.1f  %9.2f  %7.2f  %9.3f%c  %13.2f  %19.2f  %17.2f", w.fastest ? '*' : ' ',
                  w.resistor_ohm, w.current_A * 1e3, w.board_power_W, w.resistor_W, w.within_rating ? ' ' : '!',
                  w.const_I_all_h, w.const_I_to_target_h, w.droop_to_target_h);
    os << line;
    if (w.simulated) {
      std::snprintf(line, sizeof line, "  %6s  %10s  %14s  %12s  %8.1f  %14.3f  %14.3f  %12.2f  %s\n",
                    num(w.true_h, "%.2f").c_str(), num(w.firmware_h, "%.2f").c_str(),
                    num(w.board_steady_C, "%.1f").c_str(), num(w.peak_board_C, "%.1f").c_str(),
                    100.0 * w.paused_fraction, w.pack_useful_Ah, w.pack_wasted_Ah, w.pack_heat_Wh, w.end_reason.c_str());
      os << line;
    } else {
      std::snprintf(line, sizeof line, "  %6s  %10s  %14s\n", "-", "-", num(w.board_steady_C, "%.1f").c_str());
      os << line;
    }
  }
  for (const BalanceTimeRow& w : r.rows) {
    if (!w.firmware_note.empty()) os << "  " << num(w.resistor_ohm, "%.1f") << " ohm: " << w.firmware_note << "\n";
    if (w.board_peak_C.size() > 1) {
      os << "  " << num(w.resistor_ohm, "%.1f") << " ohm: peak per board (C):";
      for (double t : w.board_peak_C) os << " " << num(t, "%.1f");
      os << "\n";
    }
  }
  // Where the board pause binds, the V/R estimate's choice is not the fastest.
  const BalanceTimeRow* byVr = nullptr;
  const BalanceTimeRow* best = nullptr;
  for (const BalanceTimeRow& w : r.rows) {
    if (w.within_rating && (!byVr || w.const_I_all_h < byVr->const_I_all_h)) byVr = &w;
    if (w.fastest) best = &w;
  }
  if (best && byVr && best != byVr) {
    os << "V/R estimate picks " << num(byVr->resistor_ohm, "%.0f") << " ohm; simulated it ";
    if (std::isnan(byVr->true_h)) os << "never reaches the target (" << byVr->end_reason << ")";
    else os << "takes " << num(byVr->true_h, "%.2f") << " h with " << num(100.0 * byVr->paused_fraction, "%.0f") << " % paused on board temperature";
    os << "; the fastest within limits is " << num(best->resistor_ohm, "%.0f") << " ohm (" << num(best->true_h, "%.2f")
       << " h)\n";
  }
  os << "* fastest within limits (target reached, no trip, resistor within "
     << (r.resistor_rating_W > 0 ? num(r.resistor_rating_W, "%.3g") + " W" : std::string("its rating (not stated)"))
     << "); ! resistor_W above the rating.\n"
        "cell_I_mA: bleed current of one cell at V_cell; board_W: the most loaded board, its high cells balancing.\n";
  if (!r.delta_given)
    os << "(the scenario's imbalance: delta is the most charge a group holds above the lowest group's rest voltage;\n"
          "a high cell is one resting more than the firmware's stop_delta_mV above the lowest.)\n";
  if (r.parallel > 1)
    os << "(" << r.parallel << " cells in parallel: a cell here is a series group, one resistor bleeding all "
       << r.parallel << ", and delta is the group's.)\n";
  os << "const_I_all_h: all of delta at constant I = V_cell / (R + Rds_on); const_I_to_target_h: at that I until the\n"
        "high cell's rest voltage is within the target of the low cell's; droop_to_target_h: (R + Rds_on) * integral\n"
        "dQ / OCV(Q) to the same target; true_h: simulated, when the true rest voltages came within the target;\n"
        "firmware_h: when the firmware (as configured) declared balanced. board_steady_C: T_amb + board_W / G of the\n"
        "board node; peak_board_C: simulated peak. resistor_W at the cell's v_max_V. paused_%: time paused on board\n"
        "temperature. pack_useful_Ah: summed over cells, what each bled up to its charge above the lowest group's\n"
        "rest voltage; pack_wasted_Ah: summed over cells, the rest; pack_heat_Wh: all branch heat.\n";
  if (r.during_charge)
    for (const BalanceTimeRow& w : r.rows)
      os << "  " << num(w.resistor_ohm, "%.1f") << " ohm: the charger delivers until " << num(w.charge_h, "%.2f")
         << " h, without balancing until " << num(w.charge_without_h, "%.2f") << " h: balancing adds "
         << num(w.charge_added_h, "%.2f") << " h\n";
  return os.str();
}

}  // namespace packsim
