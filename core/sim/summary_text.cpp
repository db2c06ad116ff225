#include "core/sim/summary_text.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace packsim {

std::string clockText(double s) {
  char buf[32];
  const long t = static_cast<long>(s + 0.5);
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  return buf;
}

namespace {

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// SOC error of each estimator against the truth, the capacity estimate, the display.
std::string socErrorLines(const Summary& m) {
  std::string out;
  for (const auto& [name, st] : {std::pair<std::string, const SocErrorStats*>{"coulomb", &m.soc_error_coulomb},
                                 {"ekf", &m.soc_error_ekf}}) {
    if (st->ticks == 0) continue;
    out += (name == "coulomb" ? "SOC error       " : "                ") + name + (name == m.soc_estimator ? "*" : " ") +
           std::string(8 - name.size(), ' ') + "max " + fmt("%.2f", 100.0 * st->max) + " %  rms " +
           fmt("%.2f", 100.0 * st->rms) + " %  end " + fmt("%+.2f", 100.0 * st->end) + " %\n";
  }
  if (m.soc_error_ekf.ticks > 0)
    out += "                ekf per group: worst " + fmt("%.2f", 100.0 * m.soc_error_ekf_group_max) + " % (group " +
           std::to_string(m.soc_error_ekf_group) + ")\n";
  if (!out.empty()) out += "                (* reported; error = estimate - mean cell SOC)\n";
  out += "capacity (SOH)  " + (m.capacity_estimate_Ah > 0.0
                                   ? fmt("%.3f", m.capacity_estimate_Ah) + " Ah estimated, " + fmt("%.3f", m.capacity_true_Ah) + " Ah true"
                                   : "no estimate (needs two rests " + std::string("far enough apart in SOC)")) + "\n";
  out += "SOC display     up to " + std::to_string(m.display_bars_hidden_max) + " bars below and " +
         std::to_string(m.display_bars_extra_max) + " above what the true OCV would show\n";
  return out;
}

}  // namespace

std::string formatSummary(const Scenario& s, const RunResult& r) {
  const Summary& m = r.summary;
  std::ostringstream os;
  os << "scenario        " << s.name << "  (" << s.pack.series << "s" << s.pack.parallel << "p, "
     << fmt("%.2f", s.pack.cell.capacity_Ah) << " Ah cells)\n";
  os << "duration        " << fmt("%.1f", m.duration_s) << " s  (" << clockText(m.duration_s) << ")\n";
  os << "energy out      " << fmt("%.2f", m.energy_delivered_Wh) << " Wh  (" << fmt("%.3f", m.charge_delivered_Ah)
     << " Ah, " << fmt("%.2f", m.heat_Wh) << " Wh heat in cells)\n";
  if (!m.firmware_status.empty()) os << "firmware        " << m.firmware_status << "\n";
  os << "lowest cell     " << fmt("%.3f", m.min_cell_V) << " V  cell " << m.min_cell << " at "
     << fmt("%.2f", m.min_cell_time_s) << " s\n";
  os << "hottest cell    " << fmt("%.2f", m.max_temp_C) << " C  cell " << m.hottest_cell << " at "
     << fmt("%.2f", m.hottest_time_s) << " s\n";
  os << "energy left     " << fmt("%.2f", m.energy_left_Wh) << " Wh "
     << (m.limit_reached ? "when cell " + std::to_string(m.limit_cell) + " hit its limit at " + fmt("%.2f", m.limit_time_s) + " s"
                         : std::string("at the end (no cell reached its limit)"))
     << "; " << fmt("%.2f", m.energy_stranded_Wh) << " Wh (" << fmt("%.2f", 100.0 * m.energy_stranded_Wh / m.energy_start_Wh)
     << " % of the start) stranded by imbalance\n";
  os << "final SOC       " << fmt("%.3f", m.final_soc_min) << " .. " << fmt("%.3f", m.final_soc_max) << "\n";
  os << socErrorLines(m);
  if (m.tripped) {
    os << "BMS             TRIP: isolated at " << fmt("%.2f", m.trip_time_s) << " s  (" << m.trip_reason << ")\n";
    for (const Event& e : r.events)
      if (e.kind == "fault_active") os << "                  " << fmt("%.2f", e.time_s) << " s  " << e.detail << "\n";
  } else {
    os << "BMS             no trip\n";
  }
  if (m.compare.present) {
    const Comparison& c = m.compare;
    const double lost = c.lostWh();
    os << "compared with   " << c.name << ": " << fmt("%.2f", c.energy_delivered_Wh) << " Wh out, "
       << fmt("%.2f", c.losses_Wh) << " Wh lost in the cells there; " << fmt("%.2f", c.this_losses_Wh) << " Wh here: "
       << fmt("%.2f", std::fabs(lost)) << " Wh " << (lost >= 0.0 ? "more" : "less") << " energy lost; lowest cell "
       << fmt("%.3f", c.min_cell_V) << " V there\n";
  }
  // Cells driven past empty or full (never silent): the first of each direction and a count.
  for (const char* dir : {"below SOC 0", "above SOC 1"}) {
    int count = 0;
    const Event* first = nullptr;
    for (const Event& e : r.events)
      if (e.kind == "soc_out_of_range" && e.detail.find(dir) != std::string::npos && count++ == 0) first = &e;
    if (first)
      os << "SOC range       " << first->detail << " at " << fmt("%.2f", first->time_s) << " s"
         << (count > 1 ? "; " + std::to_string(count) + " cells in all" : std::string()) << "\n";
  }
  // What the switching hardware did on its own, and configuration warnings.
  bool contactOpenedAfterTrip = false;
  for (const Event& e : r.events) {
    if (e.kind == "monitor_fault_line" && e.detail == "asserted")
      os << "hardware        " << fmt("%.2f", e.time_s) << " s  monitor FAULT line asserted (opens the relay without the MCU)\n";
    if (e.kind == "fuse") os << "hardware        " << fmt("%.2f", e.time_s) << " s  fuse " << e.detail << "\n";
    if (e.kind == "relay_contact" && e.detail == "opened" && m.tripped && e.time_s >= m.trip_time_s)
      contactOpenedAfterTrip = true;
    if (e.kind == "config_warning") os << "warning         " << e.detail << "\n";
  }
  if (m.tripped && !contactOpenedAfterTrip) {
    bool everClosed = false;
    for (const Event& e : r.events) everClosed = everClosed || (e.kind == "relay_contact" && e.detail == "closed");
    if (everClosed) os << "hardware        relay contact still closed after the open command (welded?)\n";
  }
  return os.str();
}

}  // namespace packsim
