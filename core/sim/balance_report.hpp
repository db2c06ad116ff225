// Builds the run's BalanceSummary (core/sim/balance_summary.hpp) from the plant's truth,
// its quadratures and the firmware's `balancing` events.
#pragma once
#include <vector>

#include "core/scenario/scenario.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/result.hpp"

namespace packsim {

// The charge (Ah) each series group holds: its cells' SOC (`soc`: one per cell) times capacity.
std::vector<double> groupCharge_Ah(const Pack& p, const std::vector<double>& soc);
// Rest voltage of each series group: the mean OCV of its cells (`soc`: one per cell).
std::vector<double> groupOcv_V(const Pack& p, const std::vector<double>& soc);
// Each series group's capacity: its cells' summed.
std::vector<double> groupCapacity_Ah(const Pack& p);
// Each series group's SOC once its parallel cells share their charge (they rest at one
// voltage): its charge over its capacity.
std::vector<double> groupSoc(const Pack& p, const std::vector<double>& soc);
// The charge (Ah) each series group holds above the lowest group's rest voltage: what
// balancing must take from it for every group to rest at that voltage. Every cell of a
// pack has the same OCV curve, so that is (its SOC - the lowest group's SOC) x its
// capacity, with each group at groupSoc. With alike cells this is the group's charge less
// the lowest group's; with capacities that differ a larger group holds more charge at the
// same voltage, which is no imbalance and which no balancing removes.
std::vector<double> groupExcess_Ah(const Pack& p, const std::vector<double>& soc);
// The pack's imbalance: the most any group holds above the lowest (groupExcess_Ah).
double imbalance_Ah(const Pack& p, const std::vector<double>& soc);
// Every cell's SOC in state x.
std::vector<double> cellSoc(const Plant& plant, const double* x);
// Highest minus lowest of a per-group figure (charge, voltage).
double spread(const std::vector<double>& q);

// x0, xEnd: the plant's state at the start and at the end; quad: the run's quadratures
// (Plant Quadrature order).
BalanceSummary summarizeBalancing(const Scenario& s, const Plant& plant, const double* x0, const double* xEnd,
                                  const double* quad, const std::vector<Event>& events);

}  // namespace packsim
