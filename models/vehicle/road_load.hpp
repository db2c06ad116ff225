// The road-load equation: the force at the wheels that moves a vehicle of mass m at
// speed v up a grade G (rise over run) while it accelerates at a (docs/vehicle.md).
//
//   F_wheel = m·g·C_rr·cos θ + ½·ρ·CdA·(v+w)·|v+w| + m·g·sin θ + m·a      θ = atan(G)   [N]
//
// with w the headwind: the wind's component against the direction of travel (negative:
// a tailwind), so the air moves past the vehicle at v + w.
//
// Over one tick of length dt at a constant force the vehicle covers
// ds = v·dt + ½·a·dt², so the wheel power that does that work is F·ds/dt [W]. The
// drivetrain (motor, controller, gearing) turns pack power into wheel power at a
// efficiency η, constant or from a map over speed and torque: P_wheel = η·P_drive when
// driving, P_drive = η·P_wheel when braking regeneratively.
#pragma once
#include "models/vehicle/drivetrain_map.hpp"

namespace packsim {

constexpr double kGravity_m_per_s2 = 9.80665;

struct VehicleParams {
  double mass_kg = 0.0;                 // vehicle and driver
  double rolling_coefficient = 0.0;     // C_rr
  double drag_area_m2 = 0.0;            // C_d·A
  double air_density_kg_per_m3 = 1.2;
  double drivetrain_efficiency = 1.0;   // pack terminals <-> wheel, both ways (without a map)
  DrivetrainMap efficiency_map;         // empty: the constant drivetrain_efficiency
  double max_drive_power_W = 0.0;       // most the drive draws from the pack bus
  double max_regen_power_W = 0.0;       // most regeneration returns to the pack bus (0: none)
  double aux_power_W = 0.0;             // lights, electronics, telemetry: drawn always
  // The motor controller's battery-current limit and its low-voltage fold-back: the
  // current it allows falls linearly from max_current_A at cutoff_start_V to 0 at
  // cutoff_end_V (0: no such limit).
  double max_current_A = 0.0;
  double cutoff_start_V = 0.0;
  double cutoff_end_V = 0.0;
};

// Resistance at speed v on grade G against headwind w: rolling + aerodynamic + climbing [N].
double resistanceForce_N(const VehicleParams& p, double speed_m_per_s, double grade, double headwind_m_per_s = 0.0);
// Wheel power over one tick of dt at speed v and constant acceleration a [W]:
// (resistance at v + m·a) · (v + a·dt/2).
double wheelPower_W(const VehicleParams& p, double speed_m_per_s, double grade, double accel_m_per_s2, double dt_s,
                    double headwind_m_per_s = 0.0);
// The acceleration that wheel power P gives over dt (the inverse of wheelPower_W at
// the same v, grade and wind): the root of m·a·(v + a·dt/2) + F_res·(v + a·dt/2) = P.
double accelerationFor(const VehicleParams& p, double speed_m_per_s, double grade, double wheel_W, double dt_s,
                       double headwind_m_per_s = 0.0);
// The drivetrain efficiency at speed v with force F at the wheels: the constant, or the
// map at torque |F|·r_wheel.
double drivetrainEfficiency(const VehicleParams& p, double speed_m_per_s, double wheelForce_N);
// The pack current the controller allows at pack voltage V (infinite without a limit).
double allowedCurrent_A(const VehicleParams& p, double pack_V);

// The pack as the controller sees it over a tick: its EMF E behind its resistance R,
// so the terminals give V = E - R·I (the plant's Thevenin equivalent at the tick's start).
struct PackSource {
  double e_V = 0.0;
  double r_ohm = 0.0;
};
// The current where the controller's limit and the pack meet, I = I_allowed(E - R·I)
// (infinite without a limit). The controller regulates its battery current far faster
// than a BMS tick, so within a tick it sits at this point: with the fold-back between
// V_end and V_start (ΔV) that is I = I_max·(E - V_end)/(ΔV + I_max·R), within [0, I_max].
// With R = 0 it is allowedCurrent_A at V = E.
double allowedCurrentOn_A(const VehicleParams& p, const PackSource& pack);

}  // namespace packsim
