// What a stack of monitor ICs sees at one instant: the truth at their pins and the
// faults injected into them, in series order (core/sim fills it each tick from the
// plant; MonitorChainPath hands each device its part).
#pragma once
#include <vector>

#include "models/afe/device_faults.hpp"

namespace packsim {

struct MonitorTruth {
  // The cells at the pins, per series position: views of the caller's storage (the
  // plant's signals; a test's own array), read by MonitorChainPath::update and needed
  // only through it. A view, not a copy: the chain's devices copy them into their pins
  // anyway, and a copy here first cost one more pass over every cell each tick.
  const double* cell_V = nullptr;           // nullptr: the pins keep what they had (0 V at first)
  const double* cell_unloaded_V = nullptr;  // the same with every balancing switch open (nullptr: as cell_V)
  std::vector<double> cell_gain_error;   // injected per channel (added to the part's)
  std::vector<double> cell_offset_V;
  // true: those two hold, bit for bit, what they held at the chain's last update (the
  // usual tick: no channel fault comes or goes), so there is nothing to hand on again.
  bool channel_errors_unchanged = false;
  std::vector<double> board_C;           // per device: the board it sits on (its die = this + die_rise_C)
  std::vector<double> therm_C;           // per AFE thermistor channel
  std::vector<ThermistorFault> therm_fault;
  std::vector<MonitorDeviceFault> comm;  // per device
  int broken_link_above = -1;            // >= 0: devices above this index are silent
  double current_A = 0.0;                // positive discharges
  bool host_opens_balancing = false;     // around each conversion it starts (bms.balancing.measure_paused)

  // Sized for `cells` series positions (the cell views: none yet), `devices` devices and
  // `thermistors` AFE channels.
  MonitorTruth(int cells, int devices, int thermistors)
      : cell_gain_error(static_cast<size_t>(cells), 0.0),
        cell_offset_V(static_cast<size_t>(cells), 0.0),
        board_C(static_cast<size_t>(devices), 25.0),
        therm_C(static_cast<size_t>(thermistors), 25.0),
        therm_fault(static_cast<size_t>(thermistors), ThermistorFault::None),
        comm(static_cast<size_t>(devices)) {}
};

}  // namespace packsim
