#include "models/hw/mosfet.hpp"

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

}  // namespace packsim
