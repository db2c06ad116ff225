#include "core/sim/summary_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>
#include <cstdio>

#include "core/sim/relay_contact_text.hpp"
#include "core/sim/run_end.hpp"
#include "core/sim/summary_lines.hpp"
#include "core/sim/vehicle_text.hpp"
#include "core/text_fmt.hpp"

namespace packsim {

std::string chargeOffText(const ChargeSummary& c, int parallel) {
  return "the highest cell, " + cellName(c.off_cell, parallel) +
         fmt(", at %.3f V under %.2f A of charge, mean SOC %.3f (truth)", c.off_cell_V, c.off_current_A, c.off_soc_mean);
}

std::string clockText(double s) {
  char buf[32];
  const long t = static_cast<long>(s + 0.5);
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  return buf;
}

namespace {

// Cells past a protection limit before the BMS saw it (the limit_unseen events): per
// limit the longest episode, and how many cells had one.
void unseenLimitLines(LineWriter& w, const RunResult& r) {
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
    w.line(worst->detail + (subjects.size() > 1 ? "; " + std::to_string(subjects.size()) + " cells in all" : std::string()));
  }
}

}  // namespace

std::string cellName(int cell, int parallel) {
  if (parallel <= 1) return "cell " + std::to_string(cell);
  return "cell " + std::to_string(cell) + " (group " + std::to_string((cell - 1) / parallel + 1) + ")";
}

namespace {

using S = Scenario;
using R = RunResult;

// The relay_contact events' word on the trip and the welded contact (never the command's).
void weldedLine(LineWriter& w, const S& s, const R& r) {
  // A contact closed at the end although the relay has been commanded open for longer
  // than it takes to release: the contact is stuck (welded).
  const Summary& m = r.summary;
  const Event* lastCommand = nullptr;
  for (const Event& e : r.events)
    if (e.kind == "relay") lastCommand = &e;
  const double release_s = s.hardware.relay.open_delay_s + s.bms.image.weldSettle_ms * 1e-3;
  if (!lastCommand || lastCommand->detail != "open" || !contactClosedBefore(r, m.duration_s + 1.0) ||
      m.duration_s - lastCommand->time_s <= release_s)
    return;
  const Event* welded = nullptr;
  for (const Event& e : r.events)
    if (e.kind == "fault_injected" && e.detail.rfind("welded_relay", 0) == 0) welded = &e;
  w.line("relay contact still closed at the end, " + fmt("%.2f", m.duration_s - lastCommand->time_s) +
         " s after the open command at " + fmt("%.2f", lastCommand->time_s) + " s" +
         (welded ? " (welded_relay injected at " + fmt("%.2f", welded->time_s) + " s)" : std::string(" (welded?)")));
}

// A hung pack host (host_dead without a board, or board 1): the BMS decided nothing
// from then on, so "no trip" (or a first trip before it) says nothing of the rest of the
// run. Its outputs held their last levels; the contact's state is the events' word.
void hostDeadLines(LineWriter& w, const R& r) {
  const std::string name = "host_dead";
  for (size_t i = 0; i < r.events.size(); ++i) {
    const Event& e = r.events[i];
    if (e.kind != "fault_injected" || !injectionDetailIs(e.detail, name)) continue;
    double until_s = -1.0;
    for (size_t j = i + 1; j < r.events.size() && until_s < 0.0; ++j)
      if (r.events[j].kind == "fault_removed" && r.events[j].detail == name) until_s = r.events[j].time_s;
    w.more("  " + fmt("%.2f", e.time_s) + " s  the pack host's MCU hung (host_dead" +
           (until_s < 0.0 ? "): no BMS decision from then to the end (" : "): no BMS decision until " +
                                                                               fmt("%.2f", until_s) + " s (") +
           fmt("%.2f", (until_s < 0.0 ? r.summary.duration_s : until_s) - e.time_s) + " s); its outputs held their last levels (the relay contact " +
           (contactClosedBefore(r, e.time_s + 1e-6) ? "closed" : "open") + " then)");
  }
}

// Passive balancing: the firmware's balancing events, the resistors' quadratures and the
// groups' imbalance (and charge spread, where it differs) in the truth
// (core/sim/balance_report.hpp).
void balancingLine(LineWriter& w, const S& s, const R& r) {
  const BalanceSummary& b = r.summary.balance;
  if (!b.present) return;
  std::string when;
  if (s.bms.firmware.library) {
    // A user's firmware's balancing status is its own: what packsim sees is the monitor
    // ICs' switches it set ("never reported balancing, yet" read as a firmware that failed
    // to report what it could not).
    when = b.bled_Ah > 0.0 ? "by the switches the firmware set on the monitor ICs (its status is its own)"
                           : "the firmware set no balancing switch";
  } else if (b.started_s < 0.0) {
    // packsim's core's last status.
    const Event* last = nullptr;
    for (const Event& e : r.events)
      if (e.kind == "balancing") last = &e;
    when = "the firmware never reported balancing" + (last ? " (its last status: " + last->detail + ")" : std::string()) +
           (b.bled_Ah > 0.0 ? ", yet" : "");
  } else {
    when = "from " + fmt("%.2f", b.started_s) + " s, " +
           (b.balanced_s >= 0.0 ? "balanced (the firmware's word) at " + fmt("%.2f", b.balanced_s) + " s (" +
                                      clockText(b.balanced_s) + ")"
                                : std::string("not balanced by the end"));
  }
  w.line(when + "; bled " + fmt("%.3f", b.bled_Ah) + " Ah, " + fmt("%.2f", b.heat_Wh) + " Wh of heat");
  w.more("series groups' imbalance " + fmt("%.3f", b.imbalance_start_Ah) + " Ah at the start, " +
         fmt("%.3f", b.imbalance_end_Ah) + " Ah at the end (truth: the most charge a group held above the lowest "
         "group's rest voltage)");
  // The charge spread says the same with alike cells; where the capacities differ it
  // also counts charge that no balancing removes, so it is printed, and why.
  const auto shown = [](double ah) { return std::lround(ah * 1e3); };
  if (shown(b.spread_start_Ah) != shown(b.imbalance_start_Ah) || shown(b.spread_end_Ah) != shown(b.imbalance_end_Ah))
    w.more("charge spread " + fmt("%.3f", b.spread_start_Ah) + " Ah at the start, " + fmt("%.3f", b.spread_end_Ah) +
           " Ah at the end: it also counts the groups' capacities, which differ");
}

// A run on a charger: what the BMS did with it (core/sim/charge_summary.hpp), and the
// charger's own end at its taper current (its `charger` event).
void chargeLine(LineWriter& w, const S& s, const R& r) {
  const ChargeSummary& c = r.summary.charge;
  if (!c.present) return;
  if (c.on_s < 0.0) {
    w.line("the BMS never enabled the charger");
    return;
  }
  const std::string on = "enabled by the BMS at " + fmt("%.2f", c.on_s) + " s";
  if (c.off_s >= 0.0) {
    w.line(on + ", switched off at " + fmt("%.2f", c.off_s) + " s (" + clockText(c.off_s) + ") and kept off");
    w.more("then the highest cell, " + cellName(c.off_cell, s.pack.parallel) + ", was at " + fmt("%.3f", c.off_cell_V) +
           " V under " + fmt("%.2f", c.off_current_A) + " A of charge; mean SOC " + fmt("%.3f", c.off_soc_mean) + " (truth)");
    return;
  }
  const Event* done = nullptr;
  for (const Event& e : r.events)
    if (e.kind == "charger" && e.detail.rfind("done", 0) == 0 && e.time_s >= c.on_s) done = &e;
  w.line(on + (done ? "; the charger ended at its taper end current at " + fmt("%.2f", done->time_s) + " s"
                    : std::string(", on at the end of the run")));
}

// SOC error of each estimator against the truth; the first printed takes the label.
void socErrorLines(LineWriter& w, const S&, const R& r) {
  const Summary& m = r.summary;
  bool any = false;
  for (const auto& [name, st] : {std::pair<std::string, const SocErrorStats*>{"coulomb", &m.soc_error_coulomb},
                                 {"ekf", &m.soc_error_ekf}}) {
    if (st->ticks == 0) continue;
    const std::string body = name + (name == m.soc_estimator ? "*" : " ") + std::string(8 - name.size(), ' ') + "max " +
                             fmt("%.2f", 100.0 * st->max) + " %  rms " + fmt("%.2f", 100.0 * st->rms) + " %  end " +
                             fmt("%+.2f", 100.0 * st->end) + " %";
    any ? w.more(body) : w.line(body);
    any = true;
  }
  if (m.soc_error_ekf.ticks > 0)
    w.more("ekf per group: worst " + fmt("%.2f", 100.0 * m.soc_error_ekf_group_max) + " % (group " +
           std::to_string(m.soc_error_ekf_group) + ")");
  if (any) w.more("(* reported; error = estimate - mean cell SOC)");
}

// Each MCU reset (mcu_reset events: the watchdog's or a brown-out's) with its cause and
// when the MCU booted again (the next firmware_loaded event): the first five, then a count.
void mcuResetLines(LineWriter& w, const S&, const R& r) {
  int n = 0;
  for (size_t i = 0; i < r.events.size(); ++i) {
    const Event& e = r.events[i];
    if (e.kind != "mcu_reset" || ++n > 5) continue;
    const Event* boot = nullptr;
    for (size_t j = i + 1; j < r.events.size() && !boot; ++j)
      if (r.events[j].kind == "firmware_loaded") boot = &r.events[j];
    w.line(fmt("%.3f", e.time_s) + " s  " + e.detail.substr(0, e.detail.find(';')) +
           (boot ? "; booted again at " + fmt("%.3f", boot->time_s) + " s" : std::string("; not booted again before the end")));
  }
  if (n > 5) w.line(std::to_string(n - 5) + " more (" + std::to_string(n) + " in all)");
}

// Cells driven past empty or full (never silent): the first of each direction and a count.
void socRangeLines(LineWriter& w, const S&, const R& r) {
  for (const char* dir : {"below SOC 0", "above SOC 1"}) {
    int count = 0;
    const Event* first = nullptr;
    for (const Event& e : r.events)
      if (e.kind == "soc_out_of_range" && e.detail.find(dir) != std::string::npos && count++ == 0) first = &e;
    if (first)
      w.line(first->detail + " at " + fmt("%.2f", first->time_s) + " s" +
             (count > 1 ? "; " + std::to_string(count) + " cells in all" : std::string()));
  }
}

// What the part says holds its FAULT line, from the event at the line's rising edge.
std::string protectionAt(const R& r, double t) {
  for (const Event& e : r.events)
    if (e.kind == "monitor_protection" && e.time_s == t) return ": " + e.detail;
  return "";
}

// What the switching hardware did on its own, and configuration warnings, in event order.
// A line per event of `kind`: its detail.
void detailLines(LineWriter& w, const R& r, const char* kind) {
  for (const Event& e : r.events)
    if (e.kind == kind) w.line(e.detail);
}

void hardwareEventLines(LineWriter& w, const S& s, const R& r) {
  for (const Event& e : r.events) {
    if (e.kind == "monitor_fault_line" && e.detail == "asserted")
      w.line("hardware", fmt("%.2f", e.time_s) + " s  monitor FAULT line asserted (" +
                             (s.hardware.fault_line_opens_relay ? "it opens the relay without the MCU"
                                                                : "it does not drive the relay here") +
                             ")" + protectionAt(r, e.time_s) + "; " + contactFrom(r, e.time_s));
    if (e.kind == "fuse") w.line("hardware", fmt("%.2f", e.time_s) + " s  fuse " + e.detail);
    if (e.kind == "config_warning") w.line("warning", e.detail);
    if (e.kind == "register_misuse") w.line("bus misuse", fmt("%.4f", e.time_s) + " s  " + e.detail);
    if (e.kind == "firmware_misuse") w.line("board misuse", fmt("%.4f", e.time_s) + " s  " + e.detail);
  }
}

}  // namespace

std::string relayNeverClosed(const Scenario& s, const RunResult& r) {
  if (r.summary.relay_closed) return "";
  // The profile's peaks in its own unit (a power profile in W), the charger's current.
  const bool watts = s.load.quantity == LoadProfile::Quantity::Power_W;
  double discharge = 0.0, charge = 0.0;
  for (double v : s.load.i_A) {
    discharge = std::max(discharge, v);
    charge = std::max(charge, -v);
  }
  std::string asked;
  if (discharge > 0.0) asked = fmt("%.2f", discharge) + (watts ? " W" : " A") + " discharge";
  if (charge > 0.0) asked += (asked.empty() ? "" : ", ") + fmt("%.2f", charge) + (watts ? " W" : " A") + " regeneration";
  if (s.charger.present && s.charger.current_A > 0.0)
    asked += (asked.empty() ? "" : ", ") + fmt("%.2f", s.charger.current_A) + " A from the charger";
  if (asked.empty()) return "";  // nothing asked for current
  // The BMS's last state: packsim's core's. A user's firmware keeps its own state, which
  // packsim does not see: the run's bms_state channel stays at its first value ("init")
  // there, which named a state the firmware was not in.
  std::string state;
  if (!s.bms.firmware.library)
    for (const Event& e : r.events)
      if (e.kind == "bms_state") state = e.detail.substr(e.detail.rfind(' ') + 1);
  return "never closed in the run's " + fmt("%.2f", r.summary.duration_s) + " s: the load asked for up to " +
         asked + " and drew " + fmt("%.3f", r.summary.charge_delivered_Ah) + " Ah" +
         (state.empty() ? std::string() : "; the BMS's last state: " + state);
}

namespace {

// A profile that ended before the run did (the load_end event): the rest of the run had
// no load, which the energy line above includes.
void loadEndLine(LineWriter& w, const S&, const R& r) {
  for (const Event& e : r.events)
    if (e.kind == "load_limited") w.line(e.detail);  // a power load past the pack's maximum power
  for (const Event& e : r.events)
    if (e.kind == "load_end")
      w.line("the profile ended at " + fmt("%.2f", e.time_s) + " s; no load for the run's last " +
             fmt("%.2f", r.summary.duration_s - e.time_s) + " s");
}

// The run's length and, when it ended for another reason than its scheduled end (a trip,
// a full charge, the vehicle's route), that reason as the `run` event gives it.
void durationLine(LineWriter& w, const S& s, const R& r) {
  std::string line = fmt("%.1f", r.summary.duration_s) + " s  (" + clockText(r.summary.duration_s) + ")";
  const std::string prefix = kRunEndEventPrefix;
  for (const Event& e : r.events) {
    if (e.kind != "run" || e.detail.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string why = e.detail.substr(prefix.size());
    if (why == kRunEndScheduled) continue;
    line += "; ended: " + why;
    if (s.run.duration_s > 0.0) line += ", before run.duration_s = " + fmt("%g", s.run.duration_s) + " s";
  }
  w.line(line);
}

// Each row: its label, the /summary figures it prints (summaryFields() names; the test
// checks every figure is on a line), how it writes. In the order printed.
// clang-format off
const std::vector<SummaryLine> kLines = {
    {"scenario", "", [](LineWriter& w, const S& s, const R&) {
       w.line(s.name + "  (" + std::to_string(s.pack.series) + "s" + std::to_string(s.pack.parallel) + "p, " +
              fmt("%.2f", s.pack.cell.capacity_Ah) + " Ah cells)"); }},
    {"duration", "duration_s", durationLine},
    {"energy out", "energy_delivered_Wh charge_delivered_Ah heat_Wh energy_in_Wh", [](LineWriter& w, const S&, const R& r) {
       const Summary& m = r.summary;
       const bool back = fmt("%.2f", m.energy_in_Wh) != "0.00";  // else nothing flowed in: out is the net
       const std::string split = back ? " Wh net  (" + fmt("%.2f", m.energy_delivered_Wh + m.energy_in_Wh) + " Wh out, " +
                                            fmt("%.2f", m.energy_in_Wh) + " Wh back in; "
                                      : " Wh  (";
       w.line(fmt("%.2f", m.energy_delivered_Wh) + split + fmt("%.3f", m.charge_delivered_Ah) + (back ? " Ah net, " : " Ah, ") +
              fmt("%.2f", m.heat_Wh) + " Wh heat in cells)"); }},
    {"load", "", loadEndLine},
    {"firmware", "", [](LineWriter& w, const S&, const R& r) {
       if (!r.summary.firmware_status.empty()) w.line(r.summary.firmware_status); }},
    {"target", "", [](LineWriter& w, const S&, const R& r) {
       for (const std::string& line : r.summary.firmware_target) w.line(line); }},
    {"MCU reset", "", mcuResetLines},
    {"lowest cell", "min_cell_V min_cell min_cell_time_s", [](LineWriter& w, const S& s, const R& r) {
       const Summary& m = r.summary;
       w.line(fmt("%.3f", m.min_cell_V) + " V  " + cellName(m.min_cell, s.pack.parallel) + " at " +
              fmt("%.2f", m.min_cell_time_s) + " s"); }},
    {"hottest cell", "max_temp_C hottest_cell hottest_time_s", [](LineWriter& w, const S& s, const R& r) {
       const Summary& m = r.summary;
       w.line(fmt("%.2f", m.max_temp_C) + " C  " + cellName(m.hottest_cell, s.pack.parallel) + " at " +
              fmt("%.2f", m.hottest_time_s) + " s"); }},
    {"energy left", "energy_left_Wh limit_reached limit_by_bms_trip limit_time_s limit_cell energy_stranded_Wh energy_start_Wh",
     [](LineWriter& w, const S& s, const R& r) {
       const Summary& m = r.summary;
       const int P = s.pack.parallel;
       w.line(fmt("%.2f", m.energy_left_Wh) + " Wh " +
              (m.limit_reached && m.limit_by_bms_trip
                   ? "when the BMS tripped on under-voltage at " + fmt("%.2f", m.limit_time_s) + " s (lowest " +
                         cellName(m.limit_cell, P) + ", no cell at its v_min)"
               : m.limit_reached ? "when " + cellName(m.limit_cell, P) + " hit its limit at " + fmt("%.2f", m.limit_time_s) + " s"
                                 : std::string("at the end (no cell reached its limit)")) +
              "; " + fmt("%.2f", m.energy_stranded_Wh) + " Wh (" + fmt("%.2f", 100.0 * m.energy_stranded_Wh / m.energy_start_Wh) +
              " % of the start) stranded by imbalance"); }},
    {"balancing", "balance_bled_Ah balance_heat_Wh balance_started_s balance_balanced_s balance_spread_start_Ah "
                  "balance_spread_end_Ah balance_imbalance_start_Ah balance_imbalance_end_Ah", balancingLine},
    {"charge", "charge_on_s charge_off_s charge_off_cell charge_off_cell_V charge_off_current_A charge_off_soc_mean",
     chargeLine},
    {"final SOC", "final_soc_min final_soc_max", [](LineWriter& w, const S&, const R& r) {
       w.line(fmt("%.3f", r.summary.final_soc_min) + " .. " + fmt("%.3f", r.summary.final_soc_max)); }},
    {"SOC error", "soc_estimator soc_error_coulomb_max soc_error_coulomb_rms soc_error_coulomb_end soc_error_ekf_max "
                  "soc_error_ekf_rms soc_error_ekf_end soc_error_ekf_group_max soc_error_ekf_group", socErrorLines},
    // The capacity and display estimates are packsim's core's: a user's firmware keeps its
    // own, which packsim does not see ("no estimate (needs two rests ...)" and "0 bars below
    // and 0 above" judged a core that did not run).
    {"capacity (SOH)", "capacity_estimate_Ah capacity_true_Ah", [](LineWriter& w, const S& s, const R& r) {
       const Summary& m = r.summary;
       if (s.bms.firmware.library) return;
       w.line(m.capacity_estimate_Ah > 0.0
                  ? fmt("%.3f", m.capacity_estimate_Ah) + " Ah estimated, " + fmt("%.3f", m.capacity_true_Ah) + " Ah true"
                  : std::string("no estimate (needs two rests far enough apart in SOC)")); }},
    {"SOC display", "display_bars_hidden_max display_bars_extra_max", [](LineWriter& w, const S& s, const R& r) {
       if (s.bms.firmware.library) return;
       w.line("up to " + std::to_string(r.summary.display_bars_hidden_max) + " bars below and " +
              std::to_string(r.summary.display_bars_extra_max) + " above what the true OCV would show"); }},
    {"BMS", "tripped trip_time_s trip_reason", [](LineWriter& w, const S&, const R& r) {
       const Summary& m = r.summary;
       if (!m.tripped) {
         w.line("no trip");
       } else {
         // What the contact did is the relay_contact events' word, not the command's.
         w.line("TRIP at " + fmt("%.2f", m.trip_time_s) + " s  (" + m.trip_reason + "): " + contactFrom(r, m.trip_time_s));
         for (const Event& e : r.events)
           if (e.kind == "fault_active") w.more("  " + fmt("%.2f", e.time_s) + " s  " + e.detail);
       }
       hostDeadLines(w, r); }},
    {"relay", "relay_closed", [](LineWriter& w, const S& s, const R& r) {  // a run whose load never got current
       const std::string line = relayNeverClosed(s, r);
       if (!line.empty()) w.line(line); }},
    {"FETs", "", [](LineWriter& w, const S&, const R& r) {  // a FET asked for that never conducted
       for (const std::string& line : r.summary.fet_notes) w.line(line); }},
    {"unseen limit", "limit_unseen_longest_s limit_unseen_longest", [](LineWriter& w, const S&, const R& r) {
       unseenLimitLines(w, r); }},
    {"false fault", "", [](LineWriter& w, const S&, const R& r) {  // protections raised on readings, not on the cells
       detailLines(w, r, "false_fault"); }},
    {"unmonitored", "unmonitored_groups", [](LineWriter& w, const S&, const R& r) {  // inputs the firmware never read
       detailLines(w, r, "monitor_unread"); }},
    {"compared with", "", [](LineWriter& w, const S&, const R& r) {
       const Comparison& c = r.summary.compare;
       if (!c.present) return;
       const double lost = c.lostWh();
       w.line(c.name + ": " + fmt("%.2f", c.energy_delivered_Wh) + " Wh out, " + fmt("%.2f", c.losses_Wh) +
              " Wh lost in the cells there; " + fmt("%.2f", c.this_losses_Wh) + " Wh here: " + fmt("%.2f", std::fabs(lost)) +
              " Wh " + (lost >= 0.0 ? "more" : "less") + " energy lost; lowest cell " + fmt("%.3f", c.min_cell_V) + " V there"); }},
    {"SOC range", "", socRangeLines},
    {"model range", "", [](LineWriter& w, const S&, const R& r) {  // cells past the model's temperatures
       for (const Event& e : r.events)
         if (e.kind == "cell_model_range") w.line(fmt("%.2f", e.time_s) + " s  " + e.detail); }},
    {"hardware", "", hardwareEventLines},
    {"hardware", "", weldedLine},
    {"vehicle", "", [](LineWriter& w, const S&, const R& r) {  // a vehicle on its route (docs/vehicle.md)
       writeVehicleLines(w, r.summary.vehicle); }},
    {"fault script", "", [](LineWriter& w, const S&, const R& r) {  // scripted faults that tested nothing
       for (const Event& e : r.events)
         if (e.kind == "fault_not_reached") w.line("not reached: " + e.detail);
         else if (e.kind == "fault_no_effect") w.line("no effect: " + e.detail); }},
};
// clang-format on

}  // namespace

const std::vector<SummaryLine>& summaryLines() { return kLines; }

std::string formatSummary(const Scenario& s, const RunResult& r) {
  std::string out;
  LineWriter w(out);
  for (const SummaryLine& l : kLines) {
    w.row(l.label);
    l.write(w, s, r);
  }
  return out;
}

}  // namespace packsim
