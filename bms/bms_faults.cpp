#include "bms_faults.hpp"

namespace bms {

const char* faultName(FaultId id) {
  switch (id) {
    case FaultId::CellOverVoltage: return "cell_overvoltage";
    case FaultId::CellUnderVoltage: return "cell_undervoltage";
    case FaultId::OverCurrentDischarge: return "overcurrent_discharge";
    case FaultId::OverCurrentCharge: return "overcurrent_charge";
    case FaultId::OverTemperature: return "overtemperature";
    case FaultId::Count: break;
  }
  return "unknown";
}

}  // namespace bms
