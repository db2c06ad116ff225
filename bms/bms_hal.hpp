// The boundary between the BMS core and the board. Plain fixed-size structs: what the
// microcontroller reads from its own ADC and GPIO each control tick, and what it drives
// back. The monitor ICs' readings reach the core through its acquisition
// (bms_measure.hpp), filled by the read-out task over the bus (bms_firmware.hpp).
// Nothing here points into simulator memory.
#pragma once
#include <cstdint>

#include "bms_afe.hpp"
#include "bms_faults.hpp"
#include "bms_limits.hpp"

namespace bms {

struct Inputs {
  uint32_t now_ms;                           // millisecond tick counter (wraps after 49 days)
  uint16_t mcuThermistorCode[kMaxThermistors];  // thermistors on the MCU's own ADC (after the AFE ones)
  int32_t currentCode;                       // current-sense ADC code (shunt + amplifier)
  uint16_t busVoltageCode;                   // ADC code of the load-bus divider (precharge)
  bool eSwitchInternal;                      // latching E-switch inside the vehicle (GPIO, true = pulled)
  bool eSwitchExternal;                      // latching E-switch outside the vehicle
  bool relayAux;                             // main relay auxiliary contact: true = closed
  bool monitorFaultPin;                      // FAULT / ALERT line of the monitor stack, asserted
  bool chargerPresent;                       // charger connected (GPIO)
  bool runRequest;                           // key / drive-enable input
  bool resetRequest;                         // operator reset of latched faults
};

// Old states keep their numbers (result files); precharge and charge were added.
enum class State : uint8_t { Init = 0, Standby = 1, Normal = 2, Error = 3, Precharge = 4, Charge = 5 };

enum class PrechargePhase : uint8_t { Idle = 0, Charging = 1, Closing = 2, Pause = 3, Done = 4, Failed = 5 };

struct Telemetry {
  uint16_t cellVoltage_mV[kMaxCells];
  int16_t temperature_dC[kMaxThermistors];
  int32_t packCurrent_mA;
  uint32_t packVoltage_mV;   // sum of the cells
  uint32_t busVoltage_mV;
  uint16_t minCell_mV;
  uint16_t maxCell_mV;
  int16_t maxTemp_dC;
  int16_t minTemp_dC;
  int16_t maxDie_dC;
  int16_t maxFet_dC;         // hottest FET thermistor (INT16_MIN: none)
  uint16_t soc_permille;     // state-of-charge estimate, 0..1000
  uint8_t commBad[kMaxDevices];  // consecutive bad reads per device (saturating)
  uint8_t lastResult[kMaxDevices];  // FrameResult of the last read of each device
  uint64_t devicesLost;      // bit per device (first 64): comm-loss count reached
  uint8_t prechargePhase;    // PrechargePhase
  uint8_t prechargeAttempts;
  bool monitorFault;         // any device reports its own protection latched, or the FAULT line
  // State estimation: both estimators run every tick; soc_permille is the selected one.
  float socCoulomb;          // coulomb counting, 0..1 (valid once anchored)
  float socEkf;              // EKF, mean over the series groups, 0..1 (valid once started)
  bool socCoulombValid;
  bool socEkfValid;
  uint16_t socGroup_permille[kMaxCells];  // EKF per series group
  float capacityEstimate_mAh;  // SOH: capacity between two rested OCV points (0: none yet)
  uint8_t socDisplayBars;    // SOC display from the mean cell voltage, 1..kDisplayBars
};

struct Outputs {
  bool relayClose;          // normally-open main relay: true = energise (close)
  bool prechargeClose;      // precharge path (relay or FET)
  bool dischargeFetOn;
  bool chargeFetOn;
  bool afeClearFaults;      // clear every monitor IC's latched fault/alert flags (on the bus this tick)
  uint32_t balanceMask[kBalanceWords];  // bit per cell: balancing switch on
  uint16_t balanceTime_s;   // balancing timer to write with the mask (device enforces it)
  uint8_t balanceArmCount;  // +1 each time the host rewrites the balancing timer (re-arm)
  uint8_t balanceStatus;    // BalanceStatus (bms_balance.hpp): why cells do or do not balance
  bool chargerEnable;       // charger output allowed
  int32_t chargerCurrentRequest_mA;  // charger current limit requested (0 while disabled)
  State state;
  uint32_t faultActive;     // bit per FaultId: condition present and debounced
  uint32_t faultLatched;    // bit per FaultId: latched until operator reset
  Telemetry telemetry;
};

}  // namespace bms
