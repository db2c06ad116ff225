#include "core/batch/drawn_inputs.hpp"

#include <algorithm>
#include <cmath>

#include "core/sim/scenario_cells.hpp"

namespace packsim {

namespace {

// Population sd / mean: exactly 0 when every value is the same (the summed mean of equal
// values can miss them by an ulp, which gave a spread of 3e-16 to a pack without one).
double relativeSd(const std::vector<double>& v) {
  if (v.empty() || std::all_of(v.begin(), v.end(), [&v](double x) { return x == v.front(); })) return 0.0;
  double mean = 0.0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return mean > 0.0 ? std::sqrt(ss / static_cast<double>(v.size())) / mean : 0.0;
}

}  // namespace

DrawnInputs drawnInputs(const Scenario& s) {
  const PackCells cells = scenarioCells(s);
  DrawnInputs d;
  d.series = s.pack.series;
  d.parallel = s.pack.parallel;
  for (size_t c = 0; c < cells.params.size(); ++c) {
    d.capacity_Ah.push_back(cells.params[c].capacity_Ah);
    d.r0_scale.push_back(cells.params[c].r0_scale);
    d.initial_soc.push_back(cells.initial_soc[c]);
    d.self_discharge_A.push_back(cells.params[c].self_discharge_A);
  }
  return d;
}

const std::vector<std::string>& drawnInputNames() {
  static const std::vector<std::string> names = {
      "drawn_capacity_min_Ah", "drawn_capacity_max_Ah", "drawn_capacity_rel_sd", "drawn_r0_scale_max",
      "drawn_r0_scale_rel_sd", "drawn_initial_soc_min", "drawn_initial_soc_max", "drawn_charge_min_Ah",
      "drawn_headroom_min_Ah", "drawn_self_discharge_max_A", "drawn_weakest_group"};
  return names;
}

std::vector<std::pair<std::string, double>> drawnInputFigures(const DrawnInputs& d) {
  const size_t groups = static_cast<size_t>(d.series), p = static_cast<size_t>(d.parallel);
  std::vector<double> capacity(groups, 0.0), charge(groups, 0.0), headroom(groups, 0.0), conductance(groups, 0.0),
      leak(groups, 0.0), soc(groups, 0.0), r0(groups, 0.0);
  for (size_t g = 0; g < groups; ++g) {
    for (size_t k = 0; k < p; ++k) {
      const size_t c = g * p + k;
      capacity[g] += d.capacity_Ah[c];
      charge[g] += d.initial_soc[c] * d.capacity_Ah[c];
      headroom[g] += (1.0 - d.initial_soc[c]) * d.capacity_Ah[c];
      conductance[g] += 1.0 / d.r0_scale[c];
      leak[g] += d.self_discharge_A[c];
    }
    soc[g] = charge[g] / capacity[g];
    r0[g] = static_cast<double>(p) / conductance[g];
  }
  const auto weakest = std::min_element(charge.begin(), charge.end()) - charge.begin();
  const double values[] = {*std::min_element(capacity.begin(), capacity.end()),
                           *std::max_element(capacity.begin(), capacity.end()),
                           relativeSd(capacity),
                           *std::max_element(r0.begin(), r0.end()),
                           relativeSd(r0),
                           *std::min_element(soc.begin(), soc.end()),
                           *std::max_element(soc.begin(), soc.end()),
                           charge[static_cast<size_t>(weakest)],
                           *std::min_element(headroom.begin(), headroom.end()),
                           *std::max_element(leak.begin(), leak.end()),
                           static_cast<double>(weakest + 1)};
  std::vector<std::pair<std::string, double>> out;
  for (size_t k = 0; k < drawnInputNames().size(); ++k) out.emplace_back(drawnInputNames()[k], values[k]);
  return out;
}

}  // namespace packsim
