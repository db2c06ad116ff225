#include "models/pack/cell_spread.hpp"

#include <algorithm>
#include <cmath>

#include "models/random/random.hpp"

namespace packsim {

PackCells drawCells(const CellParams& nominal, double nominal_soc, int count, int parallel, const CellSpread& spread,
                    const std::vector<CellOverride>& overrides, uint64_t seed) {
  Rng rng(deriveSeed(seed, RngStream::CellSpread));
  auto z = [&rng] { return std::clamp(standardNormal(rng), -3.0, 3.0); };
  PackCells pc;
  pc.params.assign(static_cast<size_t>(count), nominal);
  pc.initial_soc.assign(static_cast<size_t>(count), nominal_soc);
  double z1 = 0.0, z2 = 0.0, z3 = 0.0, z4 = 0.0;
  for (int c = 0; c < count; ++c) {
    CellParams& p = pc.params[static_cast<size_t>(c)];
    // Always draw all four so one cell's values do not depend on which spreads are on.
    if (!spread.per_group || c % parallel == 0) {
      z1 = z();
      z2 = z();
      z3 = z();
      z4 = z();
    }
    p.capacity_Ah = nominal.capacity_Ah * (1.0 + spread.capacity_rel_sd * z1);
    p.r0_scale = 1.0 + spread.r0_rel_sd * z2;
    pc.initial_soc[static_cast<size_t>(c)] = std::clamp(nominal_soc + spread.initial_soc_sd * z3, 0.0, 1.0);
    p.self_discharge_A = nominal.self_discharge_A + std::fabs(spread.self_discharge_A_sd * z4);
  }
  for (const CellOverride& o : overrides) {
    CellParams& p = pc.params[static_cast<size_t>(o.cell)];
    if (o.capacity_Ah) p.capacity_Ah = *o.capacity_Ah;
    if (o.r0_scale) p.r0_scale = *o.r0_scale;
    if (o.initial_soc) pc.initial_soc[static_cast<size_t>(o.cell)] = *o.initial_soc;
    if (o.self_discharge_A) p.self_discharge_A = *o.self_discharge_A;
  }
  return pc;
}

}  // namespace packsim
