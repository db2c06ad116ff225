#include "models/hw/mosfet.hpp"

#include <algorithm>
#include <cmath>

namespace packsim {

bool mosfetConducts(const MosfetConfig& c, bool gateOn, double current_A) {
  if (!c.present || gateOn || current_A == 0.0) return true;
  return c.diode_passes_charge ? current_A < 0.0 : current_A > 0.0;
}

bool fetPairConducts(FetPaths paths, const MosfetConfig& dsg, bool dsgOn, const MosfetConfig& chg, bool chgOn,
                     double sign) {
  if (paths == FetPaths::Series) return mosfetConducts(dsg, dsgOn, sign) && mosfetConducts(chg, chgOn, sign);
  // Each one-way path: its own FET must be on (its body diode faces the other way, and
  // the path's direction is fixed).
  return sign > 0.0 ? !dsg.present || dsgOn : !chg.present || chgOn;
}

}  // namespace packsim
