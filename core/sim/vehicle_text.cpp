#include "core/sim/vehicle_text.hpp"

#include "core/sim/summary_lines.hpp"
#include "core/text_fmt.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace packsim {

namespace {
std::string km(double m) { return fmt("%.3f", m / 1000.0) + " km"; }

using V = VehicleSummary;

// The route, its time and the lap table (a row per lap; * the lap the run ended in).
void routeLines(LineWriter& w, const V& v) {
  const double driven_s = v.time_s - v.start_s;
  const int complete = static_cast<int>(v.laps.size()) - (!v.laps.empty() && !v.laps.back().complete ? 1 : 0);
  w.line(std::string(v.finished ? "finished " : "did not finish: ") + km(v.distance_m) + " of " + km(v.route_m) + " (" +
         std::to_string(complete) + " lap" + (complete == 1 ? "" : "s") + ") in " + fmt("%.1f", driven_s) + " s, " +
         fmt("%.2f", driven_s > 0.0 ? v.distance_m / driven_s * 3.6 : 0.0) + " km/h on average; set off at " +
         fmt("%.2f", v.start_s) + " s " +
         (v.start_s > v.ready_s ? "(stage 1's start; the BMS ready at " + fmt("%.2f", v.ready_s) + " s)"
                                : std::string("(BMS ready)")));
  w.more(" lap     time_s    km/h   pack_Wh   Wh/km  array_Wh  lost_s");
  for (const LapRecord& l : v.laps) {
    char row[160];
    const double perKm = l.distance_m > 0.0 ? l.pack_Wh / (l.distance_m / 1000.0) : 0.0;
    const std::string lost = l.complete && l.reference_time_s > 0.0 ? fmt("%7.1f", l.time_s - l.reference_time_s)
                                                                    : std::string("      -");
    std::snprintf(row, sizeof row, "%4d%s %10.1f %7.2f %9.3f %7.3f %9.3f %s", l.lap, l.complete ? " " : "*", l.time_s,
                  l.time_s > 0.0 ? l.distance_m / l.time_s * 3.6 : 0.0, l.pack_Wh, perKm, l.array_Wh, lost.c_str());
    w.more(row);
  }
  if (!v.laps.empty() && !v.laps.back().complete)
    w.more(" * the lap the run ended in (" + km(v.laps.back().distance_m) + " of it)");
  // The wait at the start line is in no lap: said here, so the laps and it add up to the run.
  if (v.start_s > v.ready_s)
    w.more(" before setting off, " + fmt("%.1f", v.start_s - v.ready_s) + " s at the start line: " +
           fmt("%.3f", v.prestart_pack_Wh) + " Wh from the pack, " + fmt("%.3f", v.prestart_array_Wh) + " Wh from the array");
}

// route.stages: a row per stage, then the stop after it.
void stageLines(LineWriter& w, const V& v) {
  if (v.stages.empty()) return;
  w.line(" stage  set off (solar)  time_s      km    km/h   pack_Wh  array_Wh | parked_s  pack_Wh  array_Wh");
  for (const StageRecord& g : v.stages) {
    const double h = v.clock_start_hour + g.depart_s / 3600.0;
    const int day = static_cast<int>(std::floor(h / 24.0)) + 1;
    const int minutes = static_cast<int>(std::floor((h - 24.0 * (day - 1)) * 60.0 + 1e-9));
    char row[200];
    std::snprintf(row, sizeof row, "%5d%s  day %d %02d:%02d %9.1f %7.3f %7.2f %9.2f %9.2f | %8.0f %8.2f %9.2f", g.stage,
                  g.complete ? " " : "*", day, minutes / 60, minutes % 60, g.time_s, g.distance_m / 1000.0,
                  g.time_s > 0.0 ? g.distance_m / g.time_s * 3.6 : 0.0, g.pack_Wh, g.array_Wh, g.parked_s,
                  g.parked_pack_Wh, g.parked_array_Wh);
    w.more(row);
  }
  if (!v.stages.back().complete) w.more(" * the stage the run ended in");
  w.more(" (parked: after the stage until the next set off; pack_Wh < 0: the array charged it)");
}

void timeLimitLine(LineWriter& w, const V& v) {
  if (v.time_limit_s <= 0.0) return;
  const double driven_s = v.time_s - v.start_s, left_s = v.time_limit_s - driven_s;
  // Unfinished before the limit, the run decided nothing about it (it may have ended by
  // its duration while the vehicle drove on): the line says what is known.
  w.line(fmt("%.0f", v.time_limit_s) + " s: " +
         (v.finished && left_s >= 0.0 ? "met with " + fmt("%.1f", left_s) + " s to spare"
          : v.finished               ? "missed by " + fmt("%.1f", -left_s) + " s"
          : left_s <= 0.0            ? std::string("not met (the route was not finished)")
                                     : "not reached: the run ended " + fmt("%.1f", driven_s) + " s after setting off, " +
                                           fmt("%.1f", left_s) + " s before the limit, " +
                                           km(std::max(0.0, v.route_m - v.distance_m)) + " of the route left"));
}

// The time the limits cost a finished route, or how far an unfinished one got.
void outcomeLine(LineWriter& w, const V& v) {
  // The reference's time from setting off, as the vehicle line's (both set off at start_s).
  if (v.finished && v.reference_time_s > 0.0)
    w.line(fmt("%.1f", v.time_s - v.reference_time_s) + " s against the same driver on a pack that never limits it (" +
           fmt("%.1f", v.reference_time_s - v.start_s) + " s)");
  else if (!v.finished)
    w.line(v.stood_still ? "range" : "distance",
           km(v.distance_m) +
               (v.stood_still ? (v.distance_m > 0.0 ? ", where the vehicle stood still" : ": it never set off")
                : v.sun_table_end_s >= 0.0
                    ? " when the irradiance table ended at " + fmt("%.0f", v.sun_table_end_s) +
                          " s (load.sun.irradiance_csv; the route not finished)"
                    : std::string(" when the run ended (the route not finished)")) +
               (v.reference_time_s > 0.0
                    ? "; on a pack that never limits it the route takes " + fmt("%.1f", v.reference_time_s - v.start_s) + " s"
                    : std::string()));
}

// clang-format off
const std::vector<VehicleLine> kVehicleLines = {
    {"vehicle", "vehicle_distance_km vehicle_finished vehicle_time_s", routeLines},
    {"stages", "", stageLines},
    {"array full", "", [](LineWriter& w, const V& v) {
       if (v.array_full_s >= 0.0)
         w.line("the BMS first read bms.charge_full_cell_V on the highest module at " + fmt("%.1f", v.array_full_s) +
                " s: the array charged the pack no more until the vehicle next set off"); }},
    {"vehicle energy", "vehicle_pack_Wh vehicle_array_Wh", [](LineWriter& w, const V& v) {
       w.line(fmt("%.2f", v.pack_Wh) + " Wh from the pack" +
              (v.distance_m > 0.0 ? " (" + fmt("%.2f", v.pack_Wh / (v.distance_m / 1000.0)) + " Wh/km)" : std::string()) +
              (v.pack_Wh > 0.0 ? ", " + fmt("%.1f", v.distance_m / v.pack_Wh) + " km/kWh" : std::string()) + ", " +
              fmt("%.2f", v.array_Wh) + " Wh from the array"); }},
    {"time limit", "", timeLimitLine},
    {"pack limit", "vehicle_limit_time_s", [](LineWriter& w, const V& v) {
       w.line(v.limited ? "first at " + fmt("%.2f", v.limit_time_s) + " s: " + v.limit_detail + "; it acted " +
                              fmt("%.1f", v.limited_s) + " s in all"
                        : std::string("none: every tick the pack gave the drive what the driver and motor asked")); }},
    {"time lost", "vehicle_time_lost_s", outcomeLine},
};
// clang-format on

}  // namespace

const std::vector<VehicleLine>& vehicleLines() { return kVehicleLines; }

void writeVehicleLines(LineWriter& w, const VehicleSummary& v) {
  if (!v.present) return;
  for (const VehicleLine& l : kVehicleLines) {
    w.row(l.label);
    l.write(w, v);
  }
}

}  // namespace packsim

