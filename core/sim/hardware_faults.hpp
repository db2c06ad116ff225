// Runtime fault state: what scripted injections (core/faults, issue 4) have switched on
// at the current tick. The fault scheduler writes it; the sensor, monitor-IC, switching
// hardware and load models read it every tick. All fields default to "healthy".
#pragma once
#include <cstdint>
#include <vector>

#include "models/afe/device_faults.hpp"

namespace packsim {

struct ChannelError {
  double gain_error = 0.0;  // relative, added to the configured part error (0.055 = +5.5 %)
  double offset_V = 0.0;
};

struct HardwareFaults {
  std::vector<ChannelError> cell_channel;    // per series position (monitor input)
  std::vector<ThermistorFault> thermistor;   // per thermistor channel
  std::vector<MonitorDeviceFault> device;    // per monitor IC, 0 = bottom of the stack
  int broken_link_above = -1;                // >= 0: every device above this index (on its board) is cut off
  int broken_link_byte = -1;                 // ... silent (-1), or reading this byte (a floating line)
  bool relay_welded = false;
  bool estop_internal_pulled = false;
  bool estop_external_pulled = false;
  double current_sensor_offset_A = 0.0;
  double current_sensor_drift_A_per_s = 0.0;  // offset at t: offset_A + drift · t (start folded into offset_A)
  double extra_load_A = 0.0;                 // over-current load step, added to the profile
  double charger_overvoltage_V = 0.0;        // charger output above its setpoint
  bool host_dead = false;                    // the (pack host) MCU hung: no BMS step, outputs frozen
  uint32_t dead_boards = 0;                  // bit b: monitor board b's MCU hung (b >= 1)
  bool reset_requested = false;              // operator reset GPIO asserted
  bool key_off = false;                      // the run request released (bms.run_request overridden)
  double supply_V = -1.0;                    // the BMS board's 12 V rail during a supply_brownout (-1: nominal)
  std::vector<double> cell_heat_W;           // extra heat per cell (hot cell)
  std::vector<double> cell_leak_ohm;         // internal short per cell; 0 = none
};

}  // namespace packsim
