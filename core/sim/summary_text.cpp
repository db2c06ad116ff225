#include "core/sim/summary_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>
#include <cstdio>
#include <sstream>

#include "core/sim/vehicle_text.hpp"

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

// The relay contact as the events record it: open until a relay_contact event says otherwise.
bool contactClosedBefore(const RunResult& r, double t) {
  bool closed = false;
  for (const Event& e : r.events)
    if (e.kind == "relay_contact" && e.time_s < t - 1e-9) closed = e.detail == "closed";
  return closed;
}

// What the relay contact did from time t on (a command, a trip, the FAULT line): from
// the relay_contact events, never from what was commanded.
std::string contactFrom(const RunResult& r, double t) {
  const Event* lastBefore = nullptr;  // the contact's state before t: its last event then
  const Event* openedFrom = nullptr;  // the first opening at or after t
  for (const Event& e : r.events) {
    if (e.kind != "relay_contact") continue;
    if (e.time_s < t - 1e-9) lastBefore = &e;
    else if (!openedFrom && e.detail == "opened") openedFrom = &e;
  }
  if (!lastBefore) return "the relay contact was open (never closed before)";
  if (lastBefore->detail == "opened") return "the relay contact had opened at " + fmt("%.2f", lastBefore->time_s) + " s";
  if (openedFrom) return "the relay contact opened at " + fmt("%.2f", openedFrom->time_s) + " s";
  return "the relay contact stayed closed to the end";
}

// Cells past a protection limit before the BMS saw it (the limit_unseen events): per
// limit the longest episode, and how many cells had one.
std::string unseenLimitLines(const RunResult& r) {
  std::string out;
  std::vector<std::string> names;
  for (const Event& e : r.events)
    if (e.kind == "limit_unseen") {
      const std::string name = e.detail.substr(0, e.detail.find(':'));
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
  for (const std::string& name : names) {
    const Event* worst = nullptr;
    double worst_s = -1.0;
    std::vector<std::string> subjects;
    for (const Event& e : r.events) {
      if (e.kind != "limit_unseen" || e.detail.compare(0, name.size() + 1, name + ":") != 0) continue;
      const size_t a = name.size() + 2, b = e.detail.find(e.detail.find(" above the ") != std::string::npos ? " above the " : " below the ");
      const std::string subject = e.detail.substr(a, b - a);
      if (std::find(subjects.begin(), subjects.end(), subject) == subjects.end()) subjects.push_back(subject);
      const size_t from = e.detail.find(" limit from ");
      const double from_s = from == std::string::npos ? e.time_s : std::atof(e.detail.c_str() + from + 12);
      if (e.time_s - from_s > worst_s) {
        worst_s = e.time_s - from_s;
        worst = &e;
      }
    }
    out += "unseen limit    " + worst->detail +
           (subjects.size() > 1 ? "; " + std::to_string(subjects.size()) + " cells in all" : std::string()) + "\n";
  }
  return out;
}

// Each MCU reset (mcu_reset events: the watchdog's or a brown-out's) with its cause and
// when the MCU booted again (the next firmware_loaded event): the first five, then a count.
std::string mcuResetLines(const RunResult& r) {
  std::string out;
  int n = 0;
  for (size_t i = 0; i < r.events.size(); ++i) {
    const Event& e = r.events[i];
    if (e.kind != "mcu_reset" || ++n > 5) continue;
    const Event* boot = nullptr;
    for (size_t j = i + 1; j < r.events.size() && !boot; ++j)
      if (r.events[j].kind == "firmware_loaded") boot = &r.events[j];
    out += "MCU reset       " + fmt("%.3f", e.time_s) + " s  " + e.detail.substr(0, e.detail.find(';')) +
           (boot ? "; booted again at " + fmt("%.3f", boot->time_s) + " s" : std::string("; not booted again before the end")) +
           "\n";
  }
  if (n > 5) out += "MCU reset       " + std::to_string(n - 5) + " more (" + std::to_string(n) + " in all)\n";
  return out;
}

}  // namespace

std::string cellName(int cell, int parallel) {
  if (parallel <= 1) return "cell " + std::to_string(cell);
  return "cell " + std::to_string(cell) + " (group " + std::to_string((cell - 1) / parallel + 1) + ")";
}

std::string formatSummary(const Scenario& s, const RunResult& r) {
  const Summary& m = r.summary;
  std::ostringstream os;
  os << "scenario        " << s.name << "  (" << s.pack.series << "s" << s.pack.parallel << "p, "
     << fmt("%.2f", s.pack.cell.capacity_Ah) << " Ah cells)\n";
  os << "duration        " << fmt("%.1f", m.duration_s) << " s  (" << clockText(m.duration_s) << ")\n";
  os << "energy out      " << fmt("%.2f", m.energy_delivered_Wh) << " Wh  (" << fmt("%.3f", m.charge_delivered_Ah)
     << " Ah, " << fmt("%.2f", m.heat_Wh) << " Wh heat in cells)\n";
  if (!m.firmware_status.empty()) os << "firmware        " << m.firmware_status << "\n";
  for (const std::string& line : m.firmware_target) os << "target          " << line << "\n";
  os << mcuResetLines(r);
  const int P = s.pack.parallel;
  os << "lowest cell     " << fmt("%.3f", m.min_cell_V) << " V  " << cellName(m.min_cell, P) << " at "
     << fmt("%.2f", m.min_cell_time_s) << " s\n";
  os << "hottest cell    " << fmt("%.2f", m.max_temp_C) << " C  " << cellName(m.hottest_cell, P) << " at "
     << fmt("%.2f", m.hottest_time_s) << " s\n";
  os << "energy left     " << fmt("%.2f", m.energy_left_Wh) << " Wh "
     << (m.limit_reached && m.limit_by_bms_trip
             ? "when the BMS tripped on under-voltage at " + fmt("%.2f", m.limit_time_s) + " s (lowest " +
                   cellName(m.limit_cell, P) + ", no cell at its v_min)"
         : m.limit_reached ? "when " + cellName(m.limit_cell, P) + " hit its limit at " + fmt("%.2f", m.limit_time_s) + " s"
                         : std::string("at the end (no cell reached its limit)"))
     << "; " << fmt("%.2f", m.energy_stranded_Wh) << " Wh (" << fmt("%.2f", 100.0 * m.energy_stranded_Wh / m.energy_start_Wh)
     << " % of the start) stranded by imbalance\n";
  os << "final SOC       " << fmt("%.3f", m.final_soc_min) << " .. " << fmt("%.3f", m.final_soc_max) << "\n";
  os << socErrorLines(m);
  if (m.tripped) {
    // What the contact did is the relay_contact events' word, not the command's.
    os << "BMS             TRIP at " << fmt("%.2f", m.trip_time_s) << " s  (" << m.trip_reason << "): "
       << contactFrom(r, m.trip_time_s) << "\n";
    for (const Event& e : r.events)
      if (e.kind == "fault_active") os << "                  " << fmt("%.2f", e.time_s) << " s  " << e.detail << "\n";
  } else {
    os << "BMS             no trip\n";
  }
  os << unseenLimitLines(r);
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
  for (const Event& e : r.events) {
    if (e.kind == "monitor_fault_line" && e.detail == "asserted")
      os << "hardware        " << fmt("%.2f", e.time_s) << " s  monitor FAULT line asserted ("
         << (s.hardware.fault_line_opens_relay ? "it opens the relay without the MCU" : "it does not drive the relay here")
         << "); " << contactFrom(r, e.time_s) << "\n";
    if (e.kind == "fuse") os << "hardware        " << fmt("%.2f", e.time_s) << " s  fuse " << e.detail << "\n";
    if (e.kind == "config_warning") os << "warning         " << e.detail << "\n";
    if (e.kind == "register_misuse") os << "bus misuse      " << fmt("%.4f", e.time_s) << " s  " << e.detail << "\n";
  }
  // A contact closed at the end although the relay has been commanded open for longer
  // than it takes to release: the contact is stuck (welded).
  {
    const Event* lastCommand = nullptr;
    for (const Event& e : r.events)
      if (e.kind == "relay") lastCommand = &e;
    const double release_s = s.hardware.relay.open_delay_s + s.bms.image.weldSettle_ms * 1e-3;
    if (lastCommand && lastCommand->detail == "open" && contactClosedBefore(r, m.duration_s + 1.0) &&
        m.duration_s - lastCommand->time_s > release_s) {
      const Event* welded = nullptr;
      for (const Event& e : r.events)
        if (e.kind == "fault_injected" && e.detail.rfind("welded_relay", 0) == 0) welded = &e;
      os << "hardware        relay contact still closed at the end, " << fmt("%.2f", m.duration_s - lastCommand->time_s)
         << " s after the open command at " << fmt("%.2f", lastCommand->time_s) << " s"
         << (welded ? " (welded_relay injected at " + fmt("%.2f", welded->time_s) + " s)" : std::string(" (welded?)"))
         << "\n";
    }
  }
  os << vehicleSummaryLines(m.vehicle);  // a vehicle on its route (docs/vehicle.md)
  // Scripted faults the run never reached: it ended first.
  for (const Event& e : r.events)
    if (e.kind == "fault_not_reached") os << "fault script    not reached: " << e.detail << "\n";
  return os.str();
}

}  // namespace packsim
