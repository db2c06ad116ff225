// Faults a script can inject into a monitor device and its thermistor inputs: one type
// each, shared by the fault scheduler (core/sim) and the monitor-IC models.
#pragma once

namespace packsim {

enum class ThermistorFault { None, Open, Short };

// A monitor device's link, as a scripted fault leaves it.
struct MonitorDeviceFault {
  bool silent = false;          // no reply at all (timeout)
  double crc_error_rate = 0.0;  // probability that a reply is corrupted (one bit flipped)
  int stuck_byte = -1;          // -1 healthy; 0x00 or 0xFF: every byte of the reply reads so
  bool operator==(const MonitorDeviceFault& o) const {
    return silent == o.silent && crc_error_rate == o.crc_error_rate && stuck_byte == o.stuck_byte;
  }
  bool operator!=(const MonitorDeviceFault& o) const { return !(*this == o); }
};

// A device no fault was scripted for.
inline const MonitorDeviceFault kHealthyDevice{};

}  // namespace packsim
