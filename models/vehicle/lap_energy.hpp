// The constant-energy-per-lap driver (docs/vehicle.md, "A target energy per lap"): at
// the start of each lap it picks the one cruise speed u it can hold for the lap's
// energy budget, from the road-load equation at steady speed:
//
//   E(u) = ½·m·(u₁² − v₀²)/η                       getting from the lap's start speed v₀
//        + Σ_k  L_k·F_k/η_k          (F_k > 0)      to u₁ = min(u, v_1), then per segment
//        + Σ_k  max(L_k·F_k·η_k, −P_regen·L_k/u_k)  (F_k ≤ 0: regeneration, the rest braked)
//        + P_aux · Σ_k L_k/u_k                       [J]
//
// with u_k = min(u, the segment's target speed), F_k = F_res(u_k, G_k, w_k) and η_k the
// drivetrain efficiency there. E has one minimum u* (the auxiliaries cost more the
// slower the lap; the road load more the faster), and rises from there: the driver
// takes the fastest u ≤ u_max with E(u) ≤ the budget (bisection on [u*, u_max]);
// u_max itself when the budget allows it, u* when not even u* fits.
#pragma once
#include "models/vehicle/road_load.hpp"
#include "models/vehicle/route.hpp"

namespace packsim {

// E(u) for one lap of the route from start speed v0 [J].
double lapEnergy_J(const VehicleParams& p, const Route& r, double cruise_m_per_s, double start_m_per_s);
// The cruise speed for a lap budget of target_J, at most max_m_per_s (the route's
// fastest target, or the driver's cap).
double lapSpeedFor(const VehicleParams& p, const Route& r, double target_J, double start_m_per_s, double max_m_per_s);

}  // namespace packsim
