// CC-CV charger at the pack terminals, enabled and current-limited by the BMS.
//
//   limit      I_lim = min(current_A, BMS request)        (0 while disabled or done)
//   current    I_chg = clamp((V_set - E)/R, 0, I_lim)     into the pack, where the pack
//              seen from its terminals is V = E - R·I (I positive discharging): constant
//              current until the terminal voltage reaches V_set, then constant voltage
//              with the current tapering
//   end        in CV (terminal voltage at the setpoint), a current below end_current_A
//              ends the charge (latched until the charger is disabled and enabled again)
// Units: A, V. Sign: I_chg >= 0 flows into the pack (pack current = -I_chg).
#pragma once

namespace packsim {

struct ChargerConfig {
  bool present = false;
  double current_A = 1.0;       // constant-current limit
  double voltage_V = 4.2;       // constant-voltage setpoint at the pack terminals
  double end_current_A = 0.05;  // taper end
  bool stop_run_when_done = true;
};

struct ChargerState {
  bool enabled = false;  // BMS enable, as last applied
  bool cv = false;       // in the constant-voltage phase
  bool done = false;     // taper ended
};

// Charging current (A, >= 0) for the pack Thevenin (e_V, r_ohm).
double chargerCurrent_A(double limit_A, double setpoint_V, double e_V, double r_ohm);

// Once per tick: the enable and request of the BMS, the charging current and the pack
// terminal voltage now, and the setpoint in force. Returns the limit for the next tick.
double chargerStep(const ChargerConfig& c, ChargerState& s, bool enable, double request_A, double charge_A,
                   double pack_V, double setpoint_V);

}  // namespace packsim
