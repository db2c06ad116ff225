// What a stack of monitor ICs sees at one instant: the truth at their pins and the
// faults injected into them, in series order (core/sim fills it each tick from the
// plant; MonitorChainPath hands each device its part).
#pragma once
#include <vector>

#include "models/afe/device_faults.hpp"

namespace packsim {

struct MonitorTruth {
  std::vector<double> cell_V;            // per series position
  std::vector<double> cell_unloaded_V;   // the same with every balancing switch open (empty: as cell_V)
  std::vector<double> cell_gain_error;   // injected per channel (added to the part's)
  std::vector<double> cell_offset_V;
  std::vector<double> board_C;           // per device: the board it sits on (its die = this + die_rise_C)
  std::vector<double> therm_C;           // per AFE thermistor channel
  std::vector<ThermistorFault> therm_fault;
  std::vector<MonitorDeviceFault> comm;  // per device
  int broken_link_above = -1;            // >= 0: devices above this index are silent
  double current_A = 0.0;                // positive discharges
  bool host_opens_balancing = false;     // around each conversion it starts (bms.balancing.measure_paused)

  // Sized for `cells` series positions, `devices` devices and `thermistors` AFE channels.
  MonitorTruth(int cells, int devices, int thermistors)
      : cell_V(static_cast<size_t>(cells), 0.0),
        cell_gain_error(static_cast<size_t>(cells), 0.0),
        cell_offset_V(static_cast<size_t>(cells), 0.0),
        board_C(static_cast<size_t>(devices), 25.0),
        therm_C(static_cast<size_t>(thermistors), 25.0),
        therm_fault(static_cast<size_t>(thermistors), ThermistorFault::None),
        comm(static_cast<size_t>(devices)) {}
};

}  // namespace packsim
