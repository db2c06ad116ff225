// Builds the run's BalanceSummary (core/sim/balance_summary.hpp) from the plant's truth,
// its quadratures and the firmware's `balancing` events.
#pragma once
#include <vector>

#include "core/scenario/scenario.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/result.hpp"

namespace packsim {

// The charge (Ah) each series group holds in state x: its cells' SOC times capacity.
std::vector<double> groupCharge_Ah(const Plant& plant, const double* x);
// Highest minus lowest of a per-group figure (charge, voltage).
double spread(const std::vector<double>& q);

// x0, xEnd: the plant's state at the start and at the end; quad: the run's quadratures
// (Plant Quadrature order).
BalanceSummary summarizeBalancing(const Scenario& s, const Plant& plant, const double* x0, const double* xEnd,
                                  const double* quad, const std::vector<Event>& events);

}  // namespace packsim
