// What passive balancing did in a run (hardware.balancing): the charge the resistors bled
// and the heat they made (the plant's quadratures), when the firmware started balancing
// and when it declared the pack balanced (its `balancing` events), and the series groups'
// imbalance and charge spread at the start and at the end (the plant's truth). The summary's
// `balancing` line and the /summary attributes balance_* (core/sim/summary_fields.cpp).
#pragma once

namespace packsim {

struct BalanceSummary {
  bool present = false;          // the scenario has passive balancing hardware
  double bled_Ah = 0.0;          // through the balancing resistors, every group summed
  double heat_Wh = 0.0;          // in the resistors and their FETs
  double started_s = -1.0;       // the firmware's first `balancing` status (-1: never)
  double balanced_s = -1.0;      // its first `balanced` after that (-1: never)
  double spread_start_Ah = 0.0;  // highest minus lowest series group's charge
  double spread_end_Ah = 0.0;
  // The most charge a series group holds above the lowest group's rest voltage: what
  // balancing has to bleed (core/sim/balance_report.hpp groupExcess_Ah). The spread
  // above also counts the capacities' differences; alike cells give both the same.
  double imbalance_start_Ah = 0.0;
  double imbalance_end_Ah = 0.0;
};

}  // namespace packsim
