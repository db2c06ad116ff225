#include "models/vehicle/vehicle.hpp"

#include "models/vehicle/lap_energy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace packsim {

namespace {
// A vehicle standing within this of a stop's line is at the stop (braking to the line
// ends within rounding of it).
constexpr double kAtStop_m = 0.01;
}  // namespace

const char* driveLimitName(DriveLimit l) {
  switch (l) {
    case DriveLimit::None: return "none";
    case DriveLimit::MotorPower: return "motor_power";
    case DriveLimit::DriverCap: return "driver_power_cap";
    case DriveLimit::ControllerCurrent: return "controller_current_limit";
    case DriveLimit::VoltageFoldback: return "low_voltage_foldback";
    case DriveLimit::PackShortfall: return "pack_shortfall";
  }
  return "?";
}

Vehicle::Vehicle(const VehicleParams& p, const Route& r, const DriverParams& d) : p_(p), route_(r), driver_(d) {
  paceLap();
}

// The constant-energy-per-lap driver picks the lap's cruise speed at its start.
void Vehicle::paceLap() {
  if (driver_.lap_energy_J <= 0.0 || route_.segments.empty()) return;
  double umax = 0.0;
  for (const RouteSegment& g : route_.segments) umax = std::max(umax, g.speed_m_per_s);
  if (driver_.max_speed_m_per_s > 0.0) umax = std::min(umax, driver_.max_speed_m_per_s);
  lapSpeed_ = lapSpeedFor(p_, route_, driver_.lap_energy_J, v_, umax);
}

VehiclePlan Vehicle::plan(double dt, const PackSource& pack, double array_W, bool limits) const {
  VehiclePlan pl;
  if (parked_) {  // parked: no drive; the auxiliaries stay on at a control stop, off between stages
    const RouteStop& st = route_.stops[next_];
    pl.parked = true;
    pl.array_W = array_W;
    pl.net_W = (st.stage_end < 0 ? p_.aux_power_W : 0.0) - array_W;
    return pl;
  }
  const int seg = route_.segmentAt(s_);
  pl.grade = route_.segments[static_cast<size_t>(seg)].grade;
  pl.headwind_m_per_s = route_.segments[static_cast<size_t>(seg)].headwind_m_per_s;
  pl.target_m_per_s = route_.targetSpeed_m_per_s(s_, driver_.brake_m_per_s2);
  if (driver_.max_speed_m_per_s > 0.0) pl.target_m_per_s = std::min(pl.target_m_per_s, driver_.max_speed_m_per_s);
  if (lapSpeed_ > 0.0) pl.target_m_per_s = std::min(pl.target_m_per_s, lapSpeed_);
  // A stop ahead at distance d: never aim faster than braking at b allows, and once
  // stopping there takes b (v²/2d >= b), brake at exactly v²/2d: over ticks of constant
  // deceleration the vehicle then stands still at the line (docs/vehicle.md).
  const bool stopAhead = next_ < route_.stops.size();
  const double toStop_m = stopAhead ? route_.stops[next_].at_m - s_ : 0.0;
  double stopBrake = 0.0;  // > 0: the deceleration that stops the vehicle at the line
  if (stopAhead) {
    pl.target_m_per_s = toStop_m > kAtStop_m ? std::min(pl.target_m_per_s, std::sqrt(2.0 * driver_.brake_m_per_s2 * toStop_m)) : 0.0;
    if (toStop_m <= kAtStop_m) stopBrake = driver_.brake_m_per_s2;  // at or past the line
    else if (v_ * v_ / (2.0 * toStop_m) >= driver_.brake_m_per_s2) stopBrake = v_ * v_ / (2.0 * toStop_m);
  }
  pl.array_W = array_W;
  double a = (pl.target_m_per_s - v_) / std::max(driver_.response_s, dt);
  a = std::clamp(a, -driver_.brake_m_per_s2, driver_.accel_m_per_s2);
  if (stopBrake > 0.0) a = -stopBrake;
  a = std::max(a, -v_ / dt);  // braking ends at a standstill
  const double wheel = wheelPower_W(p_, v_, pl.grade, a, dt, pl.headwind_m_per_s);
  const double eta = drivetrainEfficiency(p_, v_, resistanceForce_N(p_, v_, pl.grade, pl.headwind_m_per_s) + p_.mass_kg * a);
  pl.efficiency = eta;
  if (wheel <= 0.0) {  // coasting or braking: regeneration up to its limit, the rest friction
    pl.drive_W = std::max(wheel * eta, -p_.max_regen_power_W);
    pl.wanted_W = pl.own_W = pl.drive_W;
  } else {
    pl.wanted_W = wheel / eta;
    double cap = pl.wanted_W;
    auto cut = [&](double most, DriveLimit why) {
      if (most < cap) {
        cap = std::max(0.0, most);
        pl.limit = why;
      }
    };
    cut(p_.max_drive_power_W, DriveLimit::MotorPower);
    if (driver_.power_cap_W > 0.0) cut(driver_.power_cap_W, DriveLimit::DriverCap);
    pl.own_W = cap;
    pl.ownLimit = pl.limit;
    if (limits) {  // the controller's current where its limit meets the pack (not a lagged voltage: that rings)
      const double fullI = allowedCurrent_A(p_, std::numeric_limits<double>::infinity());
      const double i = allowedCurrentOn_A(p_, pack);
      if (std::isfinite(i)) {
        pl.controller_A = i;
        pl.controller_V = pack.e_V - pack.r_ohm * i;
        cut(i * pl.controller_V - p_.aux_power_W + array_W,
            i < fullI ? DriveLimit::VoltageFoldback : DriveLimit::ControllerCurrent);
      }
    }
    pl.drive_W = cap;
    if (cap < pl.wanted_W) a = accelerationFor(p_, v_, pl.grade, cap * eta, dt, pl.headwind_m_per_s);
  }
  pl.accel_m_per_s2 = a;
  pl.net_W = pl.drive_W + p_.aux_power_W - array_W;
  return pl;
}

StopEvent Vehicle::serveStops(double t) {
  if (parked_) {
    if (t < departAt_s_) return StopEvent::None;
    parked_ = false;
    ++next_;
    return StopEvent::Departed;
  }
  if (next_ >= route_.stops.size() || v_ > 0.0 || s_ < route_.stops[next_].at_m - kAtStop_m) return StopEvent::None;
  const RouteStop& st = route_.stops[next_];
  parked_ = true;
  departAt_s_ = std::max(t + st.duration_s, st.not_before_s);
  return StopEvent::Arrived;
}

DriveLimit Vehicle::advance(const VehiclePlan& pl, double delivered_W, double dt) {
  if (pl.parked) return DriveLimit::None;
  double a = pl.accel_m_per_s2;
  DriveLimit limit = pl.limit;
  // Integration tolerance of the pack's energy (a relative 1e-6 or so) is no shortfall.
  const double shortfall = pl.net_W - delivered_W;
  if (pl.drive_W > 0.0 && shortfall > 1e-4 * std::fabs(pl.net_W) + 1e-3) {
    const double drive = std::max(0.0, pl.drive_W - shortfall);
    a = accelerationFor(p_, v_, pl.grade, drive * pl.efficiency, dt, pl.headwind_m_per_s);
    limit = DriveLimit::PackShortfall;
  }
  if (v_ + a * dt <= 0.0) {  // comes to a standstill inside the tick and holds there (no rolling back)
    s_ += a < 0.0 ? v_ * v_ / (-2.0 * a) : 0.0;
    v_ = 0.0;
  } else {
    s_ += v_ * dt + 0.5 * a * dt * dt;
    v_ += a * dt;
  }
  if (const int lap = route_.lapAt(s_); lap != lap_) {  // a new lap: its pace
    lap_ = lap;
    if (lap < route_.laps) paceLap();
  }
  return limit;
}

}  // namespace packsim
