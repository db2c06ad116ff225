// Names of the BMS's enumerations, one function each: the events the simulator logs,
// the `names` attributes of the result file and the docs all read them from here, so a
// state, a precharge phase or a balancing status is spelled the same everywhere
// (snake_case, no spaces). Each returns "unknown" for a value outside the enumeration.
#pragma once
#include <cstdint>

#include "bms_balance.hpp"
#include "bms_hal.hpp"

namespace bms {

// How many values each enumeration has (its values are 0 .. count-1).
constexpr uint8_t kStateCount = 6;
constexpr uint8_t kPrechargePhaseCount = 6;
constexpr uint8_t kBalanceStatusCount = 5;

const char* stateName(State st);
const char* prechargePhaseName(PrechargePhase phase);
const char* balanceStatusName(BalanceStatus status);

}  // namespace bms
