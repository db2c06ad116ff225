// State-of-charge estimate: coulomb counting between anchors, anchored to the OCV
// table (mean cell voltage) at the first complete measurement and again each time the
// pack has rested (|I| < restCurrent_mA) for rest_ms.
//
//   soc = soc_anchor - (∫ I dt since the anchor) / capacity      (positive I discharges)
//
// The integral is kept as an integer (mA·ms), so a long run does not lose float
// resolution.
//
// Capacity (SOH): between two anchors that were both taken at rest, the charge counted
// over the SOC change the OCV table saw is the capacity:
//   capacity = ∫ I dt / (soc_ocv(first rest) - soc_ocv(second rest))
// accepted only when the SOC change is at least SocConfig::sohMinDeltaSoc.
//
// A rest anchor reads the OCV as the mean cell voltage plus the RC voltage the
// firmware's 1-RC model (EkfConfig's r1_mOhm, tau1_s) still holds from the current
// before the rest: v1 = a·v1 + R1·I·(1 - a) each tick, a = exp(-dt / tau1). After a rest
// of 1.5 tau1 a cell still holds 22 % of its R1·I; read as OCV it moved the anchor (and
// the capacity between two anchors) by that voltage over the OCV slope.
#pragma once
#include <cstdint>

#include "bms_config.hpp"
#include "bms_rc.hpp"
#include "bms_rest.hpp"

namespace bms {

struct SocState {
  bool anchored;
  float anchorSoc;
  int64_t sinceAnchor_mAms;
  uint32_t last_ms;
  RestTimer rest;
  bool restAnchored;  // already re-anchored during this rest
  bool anchorAtRest;  // the current anchor was taken with the pack at rest
  float capacityEstimate_mAh;  // 0 until two rested anchors far enough apart
  float v1_mV;                 // the model's RC voltage of a series group (mV), from the first anchor on
  RcDecay decay;               // its decay over the last tick length
};

void socReset(SocState& s);
// SOC (0..1) from a mean cell voltage by the OCV table (linear, clamped).
float socFromOcv(const SocConfig& c, uint16_t cell_mV);
// One tick. `valid` = a complete cell measurement is available.
void socUpdate(const SocConfig& c, SocState& s, bool valid, uint16_t meanCell_mV, int32_t current_mA, uint32_t now_ms);
float socValue(const SocConfig& c, const SocState& s);
// SOC display (reference system C): 1 + the number of thresholds at or below cell_mV.
uint8_t socDisplayBars(const SocConfig& c, uint16_t cell_mV);

}  // namespace bms
