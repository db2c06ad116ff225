#include "bms_names.hpp"

namespace bms {

const char* stateName(State st) {
  switch (st) {
    case State::Init: return "init";
    case State::Standby: return "standby";
    case State::Normal: return "normal";
    case State::Error: return "error";
    case State::Precharge: return "precharge";
    case State::Charge: return "charge";
  }
  return "unknown";
}

const char* prechargePhaseName(PrechargePhase phase) {
  switch (phase) {
    case PrechargePhase::Idle: return "idle";
    case PrechargePhase::Charging: return "charging";
    case PrechargePhase::Closing: return "closing";
    case PrechargePhase::Pause: return "pause";
    case PrechargePhase::Done: return "done";
    case PrechargePhase::Failed: return "failed";
  }
  return "unknown";
}

const char* balanceStatusName(BalanceStatus status) {
  switch (status) {
    case BalanceStatus::Disabled: return "disabled";
    case BalanceStatus::NotAllowed: return "not_allowed";
    case BalanceStatus::BoardHot: return "board_hot";
    case BalanceStatus::Balanced: return "balanced";
    case BalanceStatus::Balancing: return "balancing";
  }
  return "unknown";
}

}  // namespace bms
