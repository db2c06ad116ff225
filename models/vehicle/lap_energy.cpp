#include "models/vehicle/lap_energy.hpp"

#include <algorithm>
#include <cmath>

namespace packsim {

double lapEnergy_J(const VehicleParams& p, const Route& r, double u, double v0) {
  double e = 0.0;
  for (const RouteSegment& g : r.segments) {
    const double uk = std::min(u, g.speed_m_per_s);
    const double f = resistanceForce_N(p, uk, g.grade, g.headwind_m_per_s);
    const double eta = drivetrainEfficiency(p, uk, f);
    e += f > 0.0 ? g.length_m * f / eta : std::max(g.length_m * f * eta, -p.max_regen_power_W * g.length_m / uk);
    e += p.aux_power_W * g.length_m / uk;
  }
  const double u1 = std::min(u, r.segments.front().speed_m_per_s);
  e += 0.5 * p.mass_kg * (u1 * u1 - v0 * v0) / drivetrainEfficiency(p, u1, 0.0);
  return e;
}

double lapSpeedFor(const VehicleParams& p, const Route& r, double target_J, double v0, double umax) {
  if (lapEnergy_J(p, r, umax, v0) <= target_J) return umax;
  // The minimum u* on a grid of 200 speeds (E is smooth and has one minimum), then
  // bisection on [u*, u_max], where E rises.
  constexpr int kGrid = 200;
  double lo = umax / kGrid, eLo = lapEnergy_J(p, r, lo, v0);
  for (int k = 2; k <= kGrid; ++k) {
    const double u = umax * k / kGrid, e = lapEnergy_J(p, r, u, v0);
    if (e < eLo) {
      lo = u;
      eLo = e;
    }
  }
  if (eLo >= target_J) return lo;  // not even the most economical speed fits: drive at it
  double hi = umax;
  for (int it = 0; it < 60 && hi - lo > 1e-9 * umax; ++it) {
    const double mid = 0.5 * (lo + hi);
    (lapEnergy_J(p, r, mid, v0) <= target_J ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace packsim
