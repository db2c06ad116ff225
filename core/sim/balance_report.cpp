#include "core/sim/balance_report.hpp"

#include <algorithm>

namespace packsim {

std::vector<double> groupCharge_Ah(const Plant& plant, const double* x) {
  const Pack& p = plant.pack();
  std::vector<double> q(static_cast<size_t>(p.series), 0.0);
  for (int c = 0; c < p.cellCount(); ++c)
    q[static_cast<size_t>(c / p.parallel)] += plant.cellStates(x, c)[CellLayout::soc] * p.cells[static_cast<size_t>(c)].capacity_Ah;
  return q;
}

double spread(const std::vector<double>& q) {
  const auto [lo, hi] = std::minmax_element(q.begin(), q.end());
  return *hi - *lo;
}

BalanceSummary summarizeBalancing(const Scenario& s, const Plant& plant, const double* x0, const double* xEnd,
                                  const double* quad, const std::vector<Event>& events) {
  BalanceSummary b;
  b.present = s.hardware.balancing.present;
  if (!b.present) return b;
  b.bled_Ah = quad[kQuadBalanceCharge_As] / 3600.0;
  b.heat_Wh = quad[kQuadBalanceHeat_J] / 3600.0;
  for (const Event& e : events) {
    if (e.kind != "balancing") continue;
    if (e.detail == "balancing" && b.started_s < 0.0) b.started_s = e.time_s;
    if (e.detail == "balanced" && b.started_s >= 0.0 && b.balanced_s < 0.0) b.balanced_s = e.time_s;
  }
  b.spread_start_Ah = spread(groupCharge_Ah(plant, x0));
  b.spread_end_Ah = spread(groupCharge_Ah(plant, xEnd));
  return b;
}

}  // namespace packsim
