// Power MOSFET with its body / parallel Schottky diode (reference system A: the
// discharge FET's diode carries the charge current). With the gate on it conducts
// both ways through Rds_on; off, only the diode conducts, in its forward direction.
//
//   on:  v = I·Rds_on,  p = I²·Rds_on
//   off: I in the diode's direction: v = Vf + I·R_diode, p = v·|I|;  otherwise blocks
#pragma once
#include <algorithm>
#include <cmath>
#include <string>

namespace packsim {

struct MosfetConfig {
  bool present = true;
  double rds_on_ohm = 0.002;
  double diode_vf_V = 0.3;        // low-Vf Schottky
  double diode_r_ohm = 0.01;
  bool diode_passes_charge = true;  // diode forward direction = charge (negative) current
  std::string thermal_node;         // thermal node its dissipation heats ("" = not modelled)
};

// Can current of this sign flow (positive = discharge)?
bool mosfetConducts(const MosfetConfig& c, bool gateOn, double current_A);
// Dissipation at a current that does flow. Inline, as fetCurrent_A: asked for twice a
// tick (the switchgear's report) and at every plant evaluation, for a few operations.
inline double mosfetLoss_W(const MosfetConfig& c, bool gateOn, double current_A) {
  if (!c.present) return 0.0;
  const double i = std::fabs(current_A);
  if (gateOn) return i * i * c.rds_on_ohm;
  return (c.diode_vf_V + i * c.diode_r_ohm) * i;
}

// How the discharge and charge FETs sit between the pack and the outside world:
//   Series    back to back in one path: both carry the pack current both ways
//   Separate  two one-way paths (reference system E): the load draws through the
//             discharge FET alone, the charger feeds through the charge FET alone
enum class FetPaths { Series, Separate };

// Who switches the FET gates (hardware.fet_control):
//   Mcu        the MCU's FET pins alone (a monitor part without FET drivers of its own)
//   Afe        the monitor part's own CHG / DSG drivers alone (a BQ76952 board as built:
//              the part drives the gates; the MCU reaches them over the bus)
//   AfeAndMcu  the part's drivers with the MCU's pins on its DFETOFF / CFETOFF inputs: a
//              gate is on while the driver is on and the pin is high
enum class FetControl { Mcu, Afe, AfeAndMcu };
// The gate of one FET from the MCU's pin and the part's driver.
inline bool fetGateOn(FetControl c, bool mcuPin, bool partDriver) {
  return c == FetControl::Mcu ? mcuPin : c == FetControl::Afe ? partDriver : mcuPin && partDriver;
}

// The current through one FET of the pair for a pack current (positive = discharge).
inline double fetCurrent_A(FetPaths paths, bool dischargeFet, double pack_A) {
  if (paths == FetPaths::Series) return pack_A;
  return dischargeFet ? std::max(pack_A, 0.0) : std::min(pack_A, 0.0);
}
// Can pack current of this sign flow through the pair?
bool fetPairConducts(FetPaths paths, const MosfetConfig& dsg, bool dsgOn, const MosfetConfig& chg, bool chgOn,
                     double sign);

}  // namespace packsim
