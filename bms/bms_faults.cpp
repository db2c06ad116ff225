#include "bms_faults.hpp"

namespace bms {

const char* faultName(FaultId id) {
  switch (id) {
    case FaultId::CellOverVoltage: return "cell_overvoltage";
    case FaultId::CellUnderVoltage: return "cell_undervoltage";
    case FaultId::OverCurrentDischarge: return "overcurrent_discharge";
    case FaultId::OverCurrentCharge: return "overcurrent_charge";
    case FaultId::OverTemperature: return "overtemperature";
    case FaultId::OverTemperatureCharge: return "overtemperature_charge";
    case FaultId::UnderTemperatureDischarge: return "undertemperature";
    case FaultId::UnderTemperatureCharge: return "undertemperature_charge";
    case FaultId::BoardOverTemperature: return "board_overtemperature";
    case FaultId::CommLoss: return "comm_loss";
    case FaultId::PlausibilityCellSum: return "cell_sum_plausibility";
    case FaultId::ThermistorFault: return "thermistor_fault";
    case FaultId::CurrentSensorFault: return "current_sensor_fault";
    case FaultId::EStop: return "estop";
    case FaultId::MonitorFault: return "monitor_fault";
    case FaultId::RelayWelded: return "relay_welded";
    case FaultId::PrechargeFailed: return "precharge_failed";
    case FaultId::TemperatureWarning: return "temperature_warning";
    case FaultId::CellImbalance: return "cell_imbalance";
    case FaultId::Count: break;
  }
  return "unknown";
}

}  // namespace bms
