// Closed-form time to balance one series group through its resistor (no simulation):
//
//   constant current   t = ΔQ / I,  I = V_cell / (R + Rds_on)
//                      assumes the cell stays at V_cell the whole time and the branch
//                      is always on (no pause, no decision period, no noise)
//   with OCV droop     t = (R + Rds_on) · ∫ dQ / OCV(Q)   from the low cell's charge to
//                      the high cell's: the bleed current falls with the cell's rest
//                      voltage as charge leaves it (the cell's R0 and RC drops under the
//                      ~0.1 A bleed current are neglected: I·R0 / V ≈ 1e-5)
//
// Q in Ah and R in ohm give hours. Both assume the low cells are never bled.
#pragma once
#include "models/cell/ecm.hpp"

namespace packsim {

// SOC at which the cell's OCV equals v (bisection on the increasing OCV curve).
double socAtOcv(const CellParams& cell, double v);

double constantCurrentHours(double delta_Ah, double cell_V, double branch_ohm);

// (R + Rds_on)·∫ dQ/OCV(Q) for a group of `group_Ah` capacity from soc_low to soc_high.
double ocvDroopHours(const CellParams& cell, double group_Ah, double soc_low, double soc_high, double branch_ohm);

}  // namespace packsim
