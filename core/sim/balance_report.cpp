#include "core/sim/balance_report.hpp"

#include <algorithm>

namespace packsim {

std::vector<double> groupCharge_Ah(const Pack& p, const std::vector<double>& soc) {
  std::vector<double> q(static_cast<size_t>(p.series), 0.0);
  for (size_t c = 0; c < soc.size(); ++c) q[c / static_cast<size_t>(p.parallel)] += soc[c] * p.cells[c].capacity_Ah;
  return q;
}

std::vector<double> cellSoc(const Plant& plant, const double* x) {
  std::vector<double> soc(static_cast<size_t>(plant.pack().cellCount()));
  for (size_t c = 0; c < soc.size(); ++c) soc[c] = plant.cellStates(x, static_cast<int>(c))[CellLayout::soc];
  return soc;
}

std::vector<double> groupOcv_V(const Pack& p, const std::vector<double>& soc) {
  std::vector<double> v(static_cast<size_t>(p.series), 0.0);
  for (size_t c = 0; c < soc.size(); ++c)
    v[c / static_cast<size_t>(p.parallel)] += ecm::ocv(p.cells[c], soc[c]) / p.parallel;
  return v;
}

std::vector<double> groupCapacity_Ah(const Pack& p) {
  std::vector<double> capacity(static_cast<size_t>(p.series), 0.0);
  for (size_t c = 0; c < p.cells.size(); ++c) capacity[c / static_cast<size_t>(p.parallel)] += p.cells[c].capacity_Ah;
  return capacity;
}

std::vector<double> groupSoc(const Pack& p, const std::vector<double>& soc) {
  std::vector<double> q = groupCharge_Ah(p, soc);
  const std::vector<double> capacity = groupCapacity_Ah(p);
  for (size_t g = 0; g < q.size(); ++g) q[g] /= capacity[g];
  return q;
}

std::vector<double> groupExcess_Ah(const Pack& p, const std::vector<double>& soc) {
  const std::vector<double> s = groupSoc(p, soc), capacity = groupCapacity_Ah(p);
  const double lowest = *std::min_element(s.begin(), s.end());
  std::vector<double> excess(s.size());
  for (size_t g = 0; g < s.size(); ++g) excess[g] = (s[g] - lowest) * capacity[g];
  return excess;
}

double imbalance_Ah(const Pack& p, const std::vector<double>& soc) {
  const std::vector<double> excess = groupExcess_Ah(p, soc);
  return *std::max_element(excess.begin(), excess.end());
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
  const std::vector<double> socStart = cellSoc(plant, x0), socEnd = cellSoc(plant, xEnd);
  b.spread_start_Ah = spread(groupCharge_Ah(plant.pack(), socStart));
  b.spread_end_Ah = spread(groupCharge_Ah(plant.pack(), socEnd));
  b.imbalance_start_Ah = imbalance_Ah(plant.pack(), socStart);
  b.imbalance_end_Ah = imbalance_Ah(plant.pack(), socEnd);
  return b;
}

}  // namespace packsim
