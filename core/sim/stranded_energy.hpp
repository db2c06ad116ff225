// Energy left in the pack when the first cell reached its limit, and how much of it is
// stranded by imbalance.
//
//   E_i(soc)  = Q_i · ∫_0^soc OCV_i(s) ds                      (Wh, down to SOC 0)
//   left      = Σ_i E_i(soc_i)
//   stranded  = Σ_i [E_i(soc_i) - E_i(soc_w)]                   w = the limiting cell
//
// i.e. the energy the other cells still held above the level of the cell that stopped
// the pack: with perfectly balanced cells it is zero.
#pragma once
#include <vector>

#include "models/pack/pack.hpp"

namespace packsim {

double cellEnergy_Wh(const CellParams& p, double soc);

struct StrandedEnergy {
  double left_Wh = 0.0;
  double stranded_Wh = 0.0;
};

StrandedEnergy strandedEnergy(const Pack& pack, const std::vector<double>& soc, int limitCell);

}  // namespace packsim
