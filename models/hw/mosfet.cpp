#include "models/hw/mosfet.hpp"

#include <algorithm>
#include <cmath>

namespace packsim {

bool mosfetConducts(const MosfetConfig& c, bool gateOn, double current_A) {
  if (!c.present || gateOn || current_A == 0.0) return true;
  return c.diode_passes_charge ? current_A < 0.0 : current_A > 0.0;
}

double mosfetLoss_W(const MosfetConfig& c, bool gateOn, double current_A) {
  if (!c.present) return 0.0;
  const double i = std::fabs(current_A);
  if (gateOn) return i * i * c.rds_on_ohm;
  return (c.diode_vf_V + i * c.diode_r_ohm) * i;
}

double fetCurrent_A(FetPaths paths, bool dischargeFet, double pack_A) {
  if (paths == FetPaths::Series) return pack_A;
  return dischargeFet ? std::max(pack_A, 0.0) : std::min(pack_A, 0.0);
}

bool fetPairConducts(FetPaths paths, const MosfetConfig& dsg, bool dsgOn, const MosfetConfig& chg, bool chgOn,
                     double sign) {
  if (paths == FetPaths::Series) return mosfetConducts(dsg, dsgOn, sign) && mosfetConducts(chg, chgOn, sign);
  // Each one-way path: its own FET must be on (its body diode faces the other way, and
  // the path's direction is fixed).
  return sign > 0.0 ? !dsg.present || dsgOn : !chg.present || chgOn;
}

}  // namespace packsim
