#include "core/sim/stranded_energy.hpp"

#include <algorithm>

namespace packsim {

double cellEnergy_Wh(const CellParams& p, double soc) {
  // Composite Simpson over [0, soc]; the OCV curves are smooth or piecewise linear.
  const double s = std::clamp(soc, 0.0, 1.0);
  if (s <= 0.0) return 0.0;
  const int n = 400;
  const double h = s / n;
  double sum = ecm::ocv(p, 0.0) + ecm::ocv(p, s);
  for (int k = 1; k < n; ++k) sum += (k % 2 ? 4.0 : 2.0) * ecm::ocv(p, k * h);
  return p.capacity_Ah * sum * h / 3.0;
}

StrandedEnergy strandedEnergy(const Pack& pack, const std::vector<double>& soc, int limitCell) {
  StrandedEnergy e;
  const double socW = soc[static_cast<size_t>(limitCell)];
  for (int c = 0; c < pack.cellCount(); ++c) {
    const CellParams& p = pack.cells[static_cast<size_t>(c)];
    const double ei = cellEnergy_Wh(p, soc[static_cast<size_t>(c)]);
    e.left_Wh += ei;
    e.stranded_Wh += std::max(0.0, ei - cellEnergy_Wh(p, socW));
  }
  return e;
}

}  // namespace packsim
