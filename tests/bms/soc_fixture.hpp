// The SOC configuration the SOC and EKF tests share: a 3-point OCV table from 3000 mV
// (empty) through `half_mV` (half full) to 4200 mV (full), 2000 mAh, rest 10 s below 100 mA.
#pragma once
#include <bms/bms_soc.hpp>

#include <cstdint>

namespace bms_test {

inline bms::SocConfig socConfig(uint16_t half_mV) {
  bms::SocConfig c{};
  c.capacity_mAh = 2000.0f;
  c.ocvPoints = 3;
  c.ocv_mV[0] = 3000;
  c.ocv_mV[1] = half_mV;
  c.ocv_mV[2] = 4200;
  c.restCurrent_mA = 100;
  c.rest_ms = 10000;
  return c;
}

}  // namespace bms_test
