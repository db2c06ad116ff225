// A vehicle on its route under a simple driver, one BMS tick at a time
// (docs/vehicle.md). The driver aims for the route's target speed (braking in time for
// a slower segment ahead) with a proportional response and acceleration / braking
// bounds, and never asks the drive for more than its power cap. Each tick:
//
//   plan     the acceleration the driver wants -> wheel power -> pack power, cut back
//            by the motor's power, the driver's cap and the controller's battery-current
//            limit (with its low-voltage fold-back) where it meets the pack's E - R·I;
//            where cut back, the acceleration that the remaining power gives
//   advance  with the pack power that actually flowed over the tick (a trip, a FET
//            that blocks, a pack that cannot give the power): a shortfall comes off the
//            drive and slows the vehicle; braking the regeneration cannot take goes to
//            the friction brakes.
#pragma once
#include <cstddef>
#include <cstdint>

#include "models/vehicle/road_load.hpp"
#include "models/vehicle/route.hpp"

namespace packsim {

struct DriverParams {
  double accel_m_per_s2 = 1.0;   // most the driver accelerates
  double brake_m_per_s2 = 1.0;   // most the driver brakes (and plans braking with)
  double response_s = 2.0;       // a = (v_target - v) / response_s, within the bounds
  double power_cap_W = 0.0;      // most drive power the driver asks for (0: the motor's own)
  double max_speed_m_per_s = 0.0;  // never faster than this, whatever the route allows (0: no cap)
  // The constant-energy-per-lap strategy: each lap at the one cruise speed whose
  // road-load energy is this (models/vehicle/lap_energy.hpp; 0: none).
  double lap_energy_J = 0.0;
};

// What cut the drive power back (in order of precedence when several apply).
enum class DriveLimit : uint8_t {
  None = 0,
  MotorPower,        // the drive's max_drive_power_W (the vehicle's own)
  DriverCap,         // the driver's power_cap_W (the strategy)
  ControllerCurrent, // the controller's max_current_A at the pack voltage
  VoltageFoldback,   // the controller's low-voltage fold-back
  PackShortfall,     // the pack gave less than asked (trip, blocked FET, power beyond the pack)
};
const char* driveLimitName(DriveLimit l);
// A limit set by the pack (not by the vehicle's own motor or its driver).
inline bool packLimit(DriveLimit l) { return l >= DriveLimit::ControllerCurrent; }

struct VehiclePlan {
  bool parked = false;    // standing at a stop: no drive
  double accel_m_per_s2 = 0.0;
  double grade = 0.0;
  double headwind_m_per_s = 0.0;
  double target_m_per_s = 0.0;
  double drive_W = 0.0;   // pack-side drive power (negative: regeneration)
  double array_W = 0.0;   // solar array into the bus
  double net_W = 0.0;     // asked of the pack: drive + aux - array
  double wanted_W = 0.0;  // drive power the driver wanted before any limit
  // what the vehicle's own limits (the motor's power, the driver's cap) left of it, before
  // the pack's (the controller's current, its fold-back), and which of them cut it
  double own_W = 0.0;
  DriveLimit ownLimit = DriveLimit::None;
  double efficiency = 1.0;  // the drivetrain's at the planned speed and wheel force
  DriveLimit limit = DriveLimit::None;
  // With the controller's limit: the pack current it allows over the tick and the pack
  // voltage at that current (allowedCurrentOn_A; 0 without a limit).
  double controller_A = 0.0;
  double controller_V = 0.0;
};

// What happened at a stop at the start of a tick (Vehicle::serveStops).
enum class StopEvent : uint8_t { None, Arrived, Departed };

class Vehicle {
 public:
  Vehicle(const VehicleParams& p, const Route& r, const DriverParams& d);

  // pack: the pack's EMF and resistance at the tick's start, on which the controller's
  // current limit settles; limits false: a vehicle whose pack never limits it (the
  // reference the lost time is measured against).
  VehiclePlan plan(double dt_s, const PackSource& pack, double array_W, bool limits) const;
  // Moves the vehicle over dt with the pack power that flowed (average, W); returns the
  // plan's limit, or PackShortfall when the pack gave less than asked.
  DriveLimit advance(const VehiclePlan& plan, double delivered_W, double dt_s);

  // At the start of the tick at t: the vehicle standing at (or past) its next stop parks
  // there; a parked vehicle whose time is up sets off. Returns what happened.
  StopEvent serveStops(double t_s);
  bool parked() const { return parked_; }
  // The stop the vehicle is at or heads for next (stops().size(): none left).
  size_t nextStop() const { return next_; }

  double speed_m_per_s() const { return v_; }
  double distance_m() const { return s_; }
  bool finished() const { return s_ >= route_.total_m(); }
  const Route& route() const { return route_; }
  const VehicleParams& params() const { return p_; }
  // The constant-energy-per-lap driver's cruise speed for the current lap (0: no such driver).
  double lapSpeed_m_per_s() const { return lapSpeed_; }

 private:
  VehicleParams p_;
  Route route_;
  DriverParams driver_;
  double v_ = 0.0;
  double s_ = 0.0;
  size_t next_ = 0;        // index into route_.stops
  bool parked_ = false;
  double departAt_s_ = 0.0;
  int lap_ = 0;            // completed laps when the lap speed was chosen
  double lapSpeed_ = 0.0;  // the lap's cruise speed (driver_.lap_energy_J)
  void paceLap();
};

}  // namespace packsim
