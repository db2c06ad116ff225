// The table `packsim balance-time` prints and `str(packsim.balance_time(...))` returns:
// one line per resistor, the firmware's notes, per-board peaks, the V/R-vs-simulated
// choice and a legend naming what every column counts (docs/balancing.md).
#pragma once
#include <string>

#include "core/balance/balance_time.hpp"

namespace packsim {

std::string balanceTimeTable(const BalanceTimeResult& r);

}  // namespace packsim
