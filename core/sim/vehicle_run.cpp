#include "core/sim/vehicle_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/sim/run_tracker.hpp"
#include "core/text_fmt.hpp"

namespace packsim {

namespace {
constexpr double kArrayHold_s = 1.0;
}  // namespace

VehicleRun::VehicleRun(const VehicleConfig& c, double tick_s, double fullCell_V)
    : cfg_(c), dt_(tick_s), fullCell_V_(fullCell_V), car_(c.params, c.route, c.driver), ref_(c.params, c.route, c.driver) {
  sum_.present = true;
  sum_.clock_start_hour = c.array.start_solar_hour;
  sum_.route_m = c.route.total_m();
  sum_.time_limit_s = c.route.time_limit_s;
}

void VehicleRun::account(double t0, double dt, double e0, double e1, double s0, double s1, double a0, double a1) {
  const Route& r = cfg_.route;
  const double lap = r.lap_m();
  for (int n = static_cast<int>(std::floor(s0 / lap)) + 1; n <= r.laps && n * lap <= s1; ++n) {
    const double f = (n * lap - s0) / (s1 - s0);  // the line is crossed this far into the tick
    const double tc = t0 + f * dt, ec = e0 + f * (e1 - e0), ac = a0 + f * (a1 - a0);
    LapRecord l;
    l.lap = n;
    l.start_s = lapStart_s_;
    l.time_s = tc - lapStart_s_;
    l.distance_m = lap;
    l.pack_Wh = (ec - lapStartE_J_) / 3600.0;
    l.array_Wh = (ac - lapStartA_J_) / 3600.0;
    l.complete = true;
    sum_.laps.push_back(l);
    lapStart_s_ = tc;
    lapStartE_J_ = ec;
    lapStartA_J_ = ac;
    if (n == r.laps) {
      finish_s_ = tc;
      finishE_J_ = ec;
      finishA_J_ = ac;
    }
  }
}

std::string VehicleRun::clock(double t) const {
  const double h = cfg_.array.start_solar_hour + t / 3600.0;
  const int day = static_cast<int>(std::floor(h / 24.0)) + 1;
  const double hd = h - 24.0 * (day - 1);
  const int minutes = static_cast<int>(std::floor(hd * 60.0 + 1e-9));
  char buf[48];
  std::snprintf(buf, sizeof buf, "day %d %02d:%02d", day, minutes / 60, minutes % 60);
  return buf;
}

// A stage's start and end, and the stop after it (route.stages).
void VehicleRun::stageEvent(StopEvent ev, double t, double e_J, RunTracker& tracker) {
  const Route& r = cfg_.route;
  if (ev == StopEvent::Departed) {
    const RouteStop& st = r.stops[car_.nextStop() - 1];
    full_ = false;  // the array may charge the pack again
    if (st.stage_end < 0) return;
    if (st.stage_end == 0) {  // stage 1 sets off from the start line: the race, and lap 1, begin now
      sum_.start_s = t;
      sum_.prestart_pack_Wh = (e_J - lapStartE_J_) / 3600.0;
      sum_.prestart_array_Wh = (array_J_ - lapStartA_J_) / 3600.0;
      lapStart_s_ = t;
      lapStartE_J_ = e_J;
      lapStartA_J_ = array_J_;
    }
    if (parkOpen_ && !sum_.stages.empty()) {
      StageRecord& prev = sum_.stages.back();
      prev.parked_s = t - parkT_s_;
      prev.parked_pack_Wh = (e_J - parkE_J_) / 3600.0;
      prev.parked_array_Wh = (array_J_ - parkA_J_) / 3600.0;
      parkOpen_ = false;
    }
    StageRecord g;
    g.stage = st.stage_end + 1;
    g.depart_s = t;
    sum_.stages.push_back(g);
    stageOpen_ = true;
    stageE_J_ = e_J;
    stageA_J_ = array_J_;
    stageS_m_ = car_.distance_m();
    tracker.event(t, "vehicle_stop", "stage " + std::to_string(g.stage) + " set off at km " +
                                         fmt("%.3f", car_.distance_m() / 1000.0) + " (" + clock(t) + " solar time)");
    return;
  }
  const RouteStop& st = r.stops[car_.nextStop()];
  if (st.stage_end < 1) {
    tracker.event(t, "vehicle_stop", "control stop at km " + fmt("%.3f", car_.distance_m() / 1000.0) + " (" +
                                         clock(t) + " solar time) for " + fmt("%.0f", st.duration_s) + " s");
    return;
  }
  if (stageOpen_ && !sum_.stages.empty()) {
    StageRecord& g = sum_.stages.back();
    g.time_s = t - g.depart_s;
    g.distance_m = car_.distance_m() - stageS_m_;
    g.pack_Wh = (e_J - stageE_J_) / 3600.0;
    g.array_Wh = (array_J_ - stageA_J_) / 3600.0;
    g.complete = true;
    stageOpen_ = false;
  }
  parkOpen_ = true;
  parkT_s_ = t;
  parkE_J_ = e_J;
  parkA_J_ = array_J_;
  tracker.event(t, "vehicle_stop", "stage " + std::to_string(st.stage_end) + " ended at km " +
                                       fmt("%.3f", car_.distance_m() / 1000.0) + " (" + clock(t) + " solar time)");
}

double VehicleRun::tick(double t, double e_J, const PackSource& pack, bool ready, double maxCell_V, RunTracker& tracker) {
  if (!first_ && started_) {
    const double t0 = t - dt_;
    const double delivered_W = (e_J - energy_J_) / dt_;
    // Array power the pack did not take (a charge it refused) is curtailed by the MPPT.
    const double taken_W = std::clamp(plan_.array_W - std::max(0.0, delivered_W - plan_.net_W), 0.0, plan_.array_W);
    const double a0 = array_J_;
    array_J_ += taken_W * dt_;
    availJ_ += availPlan_W_ * dt_;
    const double s0 = car_.distance_m();
    const bool wasFinished = car_.finished();
    const DriveLimit lim = wasFinished ? DriveLimit::None : car_.advance(plan_, delivered_W, dt_);
    if (!wasFinished) account(t0, dt_, energy_J_, e_J, s0, car_.distance_m(), a0, array_J_);
    sample_.limit = static_cast<uint8_t>(lim);
    if (packLimit(lim)) {
      sum_.limited_s += dt_;
      if (!sum_.limited) {
        sum_.limited = true;
        sum_.limit_time_s = t0;
        sum_.limit_distance_m = s0;
        sum_.limit_lap = cfg_.route.lapAt(s0) + 1;
        std::string d = std::string(driveLimitName(lim)) + " at km " + fmt("%.3f", s0 / 1000.0) + " (lap " +
                        std::to_string(sum_.limit_lap) + "), " + fmt("%.1f", car_.speed_m_per_s() * 3.6) +
                        " km/h: the drive got ";
        // The drive asked the bus for drive_W; the pack was asked net_W (drive + aux - array:
        // /vehicle/pack_request_W) and gave delivered_W; the array's taken power fed the rest.
        if (lim == DriveLimit::PackShortfall)
          d += fmt("%.2f", std::max(0.0, delivered_W - cfg_.params.aux_power_W + taken_W)) + " W of the " +
               fmt("%.2f", plan_.drive_W) + " W it asked for (the pack gave " + fmt("%.2f", delivered_W) + " W of the " +
               fmt("%.2f", plan_.net_W) + " W asked of it)";
        else  // short of what the motor and the driver's cap left: the pack's share of the cut
          d += fmt("%.2f", plan_.drive_W) + " W of the " + fmt("%.2f", plan_.own_W) + " W " +
               (plan_.ownLimit == DriveLimit::None ? std::string("the driver wanted")
                                                   : std::string(plan_.ownLimit == DriveLimit::MotorPower
                                                                     ? "the motor allowed"
                                                                     : "the driver's power cap allowed") +
                                                         " (the driver wanted " + fmt("%.2f", plan_.wanted_W) + " W)") +
               ", " + fmt("%.3g", plan_.own_W - plan_.drive_W) + " W short (pack " + fmt("%.2f", plan_.controller_V) +
               " V, the controller allowed " + fmt("%.2f", plan_.controller_A) + " A)";
        sum_.limit_detail = d;
        tracker.event(t0, "vehicle_limited", d);
      }
    }
    if (!ref_.finished()) {
      const double r0 = ref_.distance_m();
      ref_.advance(refPlan_, refPlan_.net_W, dt_);
      const double lap = cfg_.route.lap_m();
      for (int n = static_cast<int>(std::floor(r0 / lap)) + 1; n <= cfg_.route.laps && n * lap <= ref_.distance_m(); ++n) {
        const double tc = t0 + dt_ * (n * lap - r0) / (ref_.distance_m() - r0);
        refLapEnd_s_.push_back(tc);
        if (n == cfg_.route.laps) refFinish_s_ = tc;
      }
    }
    if (!car_.finished() && car_.speed_m_per_s() == 0.0 && plan_.target_m_per_s > 0.0) {
      still_s_ += dt_;
      if (still_s_ >= cfg_.standstill_end_s && !stood_) {
        stood_ = true;
        tracker.event(t, "vehicle_stopped",
                      "standing at km " + fmt("%.3f", car_.distance_m() / 1000.0) + " for " + fmt("%.0f", still_s_) +
                          " s although the driver wants " + fmt("%.1f", plan_.target_m_per_s * 3.6) + " km/h");
      }
    } else {
      still_s_ = 0.0;
    }
  }
  if (!started_ && !ready && !stood_ && t >= cfg_.standstill_end_s) {  // the ready light never came on
    stood_ = true;
    tracker.event(t, "vehicle_stopped",
                  "never set off: the BMS was not ready (normal state) within " + fmt("%.0f", t) + " s");
  }
  if (!started_ && ready) {
    started_ = true;
    sum_.start_s = sum_.ready_s = t;
    lapStart_s_ = t;
    lapStartE_J_ = e_J;
    lapStartA_J_ = array_J_;
  }
  if (started_) {  // stops: park at one reached, set off from one whose time is up
    const StopEvent ev = car_.serveStops(t);
    if (ev != StopEvent::None) stageEvent(ev, t, e_J, tracker);
    ref_.serveStops(t);
  }
  if (cfg_.array.area_m2 > 0.0 && t >= cfg_.array.table.end_s() && !car_.finished() && !sunEnded_) {
    sunEnded_ = true;  // the irradiance is not known past the table's last row: the run ends (its end reason)
  }
  first_ = false;
  energy_J_ = e_J;
  // The irradiance changes over minutes: the array's power is held for a second at a time
  // (a power load that changed every tick would restart the integrator every tick).
  const double array_W = cfg_.array.power_W(std::floor(t / kArrayHold_s) * kArrayHold_s);
  availPlan_W_ = started_ ? array_W : 0.0;
  if (started_) {
    plan_ = car_.plan(dt_, pack, array_W, true);
    refPlan_ = ref_.plan(dt_, pack, array_W, false);
    // The BMS reads its full voltage on the highest module: the array's MPPT charges the
    // pack no more (it still feeds the drive and the auxiliaries) until the vehicle next
    // sets off, as the BMS ends a charger's charge.
    if (fullCell_V_ > 0.0 && array_W > 0.0 && !full_ && maxCell_V >= fullCell_V_) {
      full_ = true;
      if (sum_.array_full_s < 0.0) sum_.array_full_s = t;
      tracker.event(t, "vehicle_stop", "array charge ended: the BMS read " + fmt("%.3f", maxCell_V) +
                                           " V on the highest module (bms.charge_full_cell_V " + fmt("%.3f", fullCell_V_) +
                                           " V) at km " + fmt("%.3f", car_.distance_m() / 1000.0));
    }
    if (full_ && plan_.net_W < 0.0 && plan_.array_W > 0.0) {
      const double loads_W = plan_.net_W + plan_.array_W;  // drive (regeneration: negative) + aux
      plan_.array_W = std::clamp(loads_W, 0.0, plan_.array_W);
      plan_.net_W = loads_W - plan_.array_W;  // regeneration alone may still charge it
    }
  } else {
    plan_ = VehiclePlan{};  // waiting for the ready light: nothing drawn yet
  }
  sample_.distance_m = car_.distance_m();
  sample_.speed_m_per_s = car_.speed_m_per_s();
  sample_.pack_request_W = plan_.net_W;
  // The array over the interval since the last sample, not the plan for the next tick:
  // the pack may refuse the charge inside the tick, and only its energy tells.
  const double span_s = t - recT_s_;
  sample_.array_W = span_s > 0.0 ? (array_J_ - recJ_) / span_s : 0.0;
  sample_.array_available_W = span_s > 0.0 ? (availJ_ - recAvailJ_) / span_s : 0.0;
  return plan_.net_W;
}

void VehicleRun::recorded(double t) {
  recT_s_ = t;
  recJ_ = array_J_;
  recAvailJ_ = availJ_;
}

std::string VehicleRun::endReason() const {
  if (car_.finished()) return "the vehicle finished its route";
  if (stood_) return "the vehicle stood still";
  if (sunEnded_)
    return "the irradiance table (load.sun.irradiance_csv) ended at " + fmt("%.0f", cfg_.array.table.end_s()) + " s, at km " +
           fmt("%.3f", car_.distance_m() / 1000.0);
  return "";
}

VehicleSummary VehicleRun::summary(double end_s) const {
  VehicleSummary s = sum_;
  s.distance_m = std::min(car_.distance_m(), cfg_.route.total_m());
  s.finished = car_.finished();
  s.stood_still = stood_;
  if (sunEnded_ && !stood_) s.sun_table_end_s = cfg_.array.table.end_s();
  s.time_s = s.finished ? finish_s_ : end_s;
  s.reference_time_s = refFinish_s_ > 0.0 ? refFinish_s_ : 0.0;
  s.pack_Wh = energy_J_ / 3600.0;
  s.array_Wh = array_J_ / 3600.0;
  if (!s.finished && started_ && car_.distance_m() > 0.0) {  // the lap the run ended in
    LapRecord l;
    l.lap = static_cast<int>(s.laps.size()) + 1;
    l.start_s = lapStart_s_;
    l.time_s = end_s - lapStart_s_;
    l.distance_m = car_.distance_m() - cfg_.route.lap_m() * static_cast<double>(s.laps.size());
    l.pack_Wh = (energy_J_ - lapStartE_J_) / 3600.0;
    l.array_Wh = (array_J_ - lapStartA_J_) / 3600.0;
    s.laps.push_back(l);
  }
  if (stageOpen_ && !s.stages.empty()) {  // the last stage: to the finish line, or the run's end
    StageRecord& g = s.stages.back();
    g.complete = car_.finished();
    g.time_s = (g.complete ? finish_s_ : end_s) - g.depart_s;
    g.distance_m = (g.complete ? cfg_.route.total_m() : car_.distance_m()) - stageS_m_;
    g.pack_Wh = ((g.complete ? finishE_J_ : energy_J_) - stageE_J_) / 3600.0;
    g.array_Wh = ((g.complete ? finishA_J_ : array_J_) - stageA_J_) / 3600.0;
  }
  if (parkOpen_ && !s.stages.empty()) {  // the run ended parked after a stage
    StageRecord& g = s.stages.back();
    g.parked_s = end_s - parkT_s_;
    g.parked_pack_Wh = (energy_J_ - parkE_J_) / 3600.0;
    g.parked_array_Wh = (array_J_ - parkA_J_) / 3600.0;
  }
  for (LapRecord& l : s.laps) {
    const size_t i = static_cast<size_t>(l.lap - 1);
    if (l.complete && i < refLapEnd_s_.size())
      l.reference_time_s = refLapEnd_s_[i] - (i == 0 ? sum_.start_s : refLapEnd_s_[i - 1]);
  }
  return s;
}

}  // namespace packsim
