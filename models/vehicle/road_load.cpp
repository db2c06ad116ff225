#include "models/vehicle/road_load.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace packsim {

double resistanceForce_N(const VehicleParams& p, double v, double grade, double wind) {
  const double c = 1.0 / std::sqrt(1.0 + grade * grade);  // cos θ
  const double s = grade * c;                             // sin θ
  const double weight_N = p.mass_kg * kGravity_m_per_s2;
  const double air = v + wind;  // the air's speed past the vehicle (v >= 0: without wind exactly v·v below)
  return weight_N * p.rolling_coefficient * c + 0.5 * p.air_density_kg_per_m3 * p.drag_area_m2 * air * std::fabs(air) +
         weight_N * s;
}

double wheelPower_W(const VehicleParams& p, double v, double grade, double a, double dt, double wind) {
  return (resistanceForce_N(p, v, grade, wind) + p.mass_kg * a) * (v + 0.5 * a * dt);
}

double accelerationFor(const VehicleParams& p, double v, double grade, double wheel_W, double dt, double wind) {
  // (m·dt/2)·a² + (m·v + F·dt/2)·a + (F·v - P) = 0; the root that is continuous in P.
  const double f = resistanceForce_N(p, v, grade, wind);
  const double qa = 0.5 * p.mass_kg * dt;
  const double qb = p.mass_kg * v + 0.5 * f * dt;
  const double qc = f * v - wheel_W;
  const double disc = std::max(0.0, qb * qb - 4.0 * qa * qc);  // >= 0 for P >= 0 (docs/vehicle.md)
  const double root = std::sqrt(disc);
  if (qb >= 0.0) return -2.0 * qc / (qb + root);
  return (-qb + root) / (2.0 * qa);
}

double drivetrainEfficiency(const VehicleParams& p, double v, double force_N) {
  if (p.efficiency_map.empty()) return p.drivetrain_efficiency;
  return p.efficiency_map.at(v, std::fabs(force_N) * p.efficiency_map.wheel_radius_m);
}

double allowedCurrent_A(const VehicleParams& p, double pack_V) {
  double i = p.max_current_A > 0.0 ? p.max_current_A : std::numeric_limits<double>::infinity();
  if (p.cutoff_start_V > p.cutoff_end_V) {
    const double f = std::clamp((pack_V - p.cutoff_end_V) / (p.cutoff_start_V - p.cutoff_end_V), 0.0, 1.0);
    i *= f;  // the loader requires max_current_A with a fold-back
  }
  return i;
}

double allowedCurrentOn_A(const VehicleParams& p, const PackSource& pack) {
  const double most = allowedCurrent_A(p, std::numeric_limits<double>::infinity());
  if (!(p.cutoff_start_V > p.cutoff_end_V)) return most;  // no fold-back: the limit alone
  // I = I_max·(E - R·I - V_end)/ΔV solved for I; beyond [0, I_max] the clamp of
  // allowedCurrent_A holds (E - R·I_max >= V_start: I_max; E <= V_end: nothing).
  const double dv = p.cutoff_start_V - p.cutoff_end_V;
  return std::clamp(most * (pack.e_V - p.cutoff_end_V) / (dv + most * pack.r_ohm), 0.0, most);
}

}  // namespace packsim
