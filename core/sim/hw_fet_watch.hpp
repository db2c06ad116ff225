// Why a FET never conducted in a run although the firmware asked for it. Over the run it
// keeps, per FET, how long the MCU's pin, the monitor part's own driver and the gate
// were on (each level held from one actuation to the next), and why the part's driver
// was off the last time the pin was on without it (MonitorChain::fetOffCause).
//
// A FET whose gate was never on while the pin or the part's driver was at some time
// gives one summary line: which side stayed off, for how long the other was on, and the
// board's wiring (hardware.fet_control) that needs them both, or only one.
#pragma once
#include <string>
#include <vector>

#include "core/sim/hw_switchgear.hpp"

namespace packsim {

class FetWatch {
 public:
  // The levels in force from t on; `dsgCause` / `chgCause`: why the part's driver is off
  // now ("" when on, or not known).
  void hold(double t, const SwitchDrive& d, const SwitchState& s, const std::string& dsgCause,
            const std::string& chgCause);
  // The lines for a run that ended at end_s; none when each FET conducted at some time
  // or was never asked for. `part`: the monitor part's name (hardware.afe.model).
  std::vector<std::string> notes(double end_s, FetControl control, const std::string& part, bool chargeFet) const;
  // Both gates were on at some time: no note can come any more and hold() keeps nothing
  // (its caller need not find the part's reasons).
  bool settled() const { return dsg_.gateEver && chg_.gateEver; }

 private:
  struct Levels {
    bool pin = false, driver = false, gate = false;
    double pin_s = 0.0, driver_s = 0.0, gate_s = 0.0;  // time on so far
    bool pinEver = false, driverEver = false, gateEver = false;
    std::string cause;  // the driver's reason to be off, the last time the pin was on without it
  };
  static void advance(Levels& l, double dt);
  static void set(Levels& l, bool pin, bool driver, bool gate, const std::string& cause);
  static std::string note(const Levels& l, bool discharge, FetControl control, const std::string& part);

  Levels dsg_, chg_;
  double since_s_ = 0.0;
};

}  // namespace packsim
