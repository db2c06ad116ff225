#include "bms_soc.hpp"

namespace bms {

void socReset(SocState& s) {
  s.anchored = false;
  s.anchorSoc = 0.0f;
  s.sinceAnchor_mAms = 0;
  s.last_ms = 0;
  restReset(s.rest);
  s.restAnchored = false;
  s.anchorAtRest = false;
  s.capacityEstimate_mAh = 0.0f;
  s.v1_mV = 0.0f;
  rcDecayReset(s.decay);
}

// Unrolled (a fixed count): a compare and an add a threshold, every tick (41 -> 17
// instructions on a host).
uint8_t socDisplayBars(const SocConfig& c, uint16_t cell_mV) {
  uint8_t bars = 1;
#pragma GCC unroll 16
  for (uint8_t i = 0; i + 1 < kDisplayBars; ++i)
    if (cell_mV >= c.displayBars_mV[i]) ++bars;
  return bars;
}

float socFromOcv(const SocConfig& c, uint16_t mv) {
  const uint8_t n = c.ocvPoints;
  if (n < 2) return 0.0f;
  if (mv <= c.ocv_mV[0]) return 0.0f;
  if (mv >= c.ocv_mV[n - 1]) return 1.0f;
  for (uint8_t i = 1; i < n; ++i) {
    if (mv <= c.ocv_mV[i]) {
      const float lo = static_cast<float>(c.ocv_mV[i - 1]);
      const float hi = static_cast<float>(c.ocv_mV[i]);
      const float frac = hi > lo ? (static_cast<float>(mv) - lo) / (hi - lo) : 0.0f;
      return (static_cast<float>(i - 1) + frac) / static_cast<float>(n - 1);
    }
  }
  return 1.0f;
}

float socValue(const SocConfig& c, const SocState& s) {
  if (!s.anchored) return 0.0f;
  const float used = static_cast<float>(s.sinceAnchor_mAms) / (c.capacity_mAh * 3.6e6f);
  const float soc = s.anchorSoc - used;
  return soc < 0.0f ? 0.0f : (soc > 1.0f ? 1.0f : soc);
}

namespace {

void anchor(const SocConfig& c, SocState& s, uint16_t meanCell_mV, bool atRest) {
  const float soc = socFromOcv(c, meanCell_mV);
  if (atRest && s.anchored && s.anchorAtRest) {
    const float delta = s.anchorSoc - soc;
    const float size = delta < 0.0f ? -delta : delta;
    if (size >= c.sohMinDeltaSoc && size > 0.0f) {
      const float counted_mAh = static_cast<float>(s.sinceAnchor_mAms) / 3.6e6f;
      const float capacity_mAh = counted_mAh / delta;
      if (capacity_mAh > 0.0f) s.capacityEstimate_mAh = capacity_mAh;
    }
  }
  s.anchored = true;
  s.anchorAtRest = atRest;
  s.anchorSoc = soc;
  s.sinceAnchor_mAms = 0;
}

// The OCV a rested reading stands for: the reading plus the RC voltage the model still
// holds (rounded to the reading's mV, within a uint16_t).
uint16_t restedOcv_mV(uint16_t meanCell_mV, float v1_mV) {
  const float ocv = static_cast<float>(meanCell_mV) + v1_mV + 0.5f;
  return static_cast<uint16_t>(ocv < 0.0f ? 0.0f : (ocv > 65535.0f ? 65535.0f : ocv));
}

}  // namespace

void socUpdate(const SocConfig& c, SocState& s, bool valid, uint16_t meanCell_mV, int32_t current_mA, uint32_t now_ms) {
  const uint32_t dt_ms = now_ms - s.last_ms;
  s.last_ms = now_ms;
  if (!s.anchored) {
    if (valid) anchor(c, s, meanCell_mV, magnitude(current_mA) < c.restCurrent_mA);
    return;
  }
  // Rectangle rule with this tick's current over the elapsed interval.
  s.sinceAnchor_mAms += static_cast<int64_t>(current_mA) * static_cast<int64_t>(dt_ms);
  const float a = rcDecay(c.ekf.tau1_s, s.decay, dt_ms);
  s.v1_mV = a * s.v1_mV + c.ekf.r1_mOhm * static_cast<float>(current_mA) * 1e-3f * (1.0f - a);

  restUpdate(s.rest, current_mA, c.restCurrent_mA, now_ms);
  if (!s.rest.resting) {
    s.restAnchored = false;
    return;
  }
  if (valid && !s.restAnchored && restedFor(s.rest, now_ms, c.rest_ms)) {
    anchor(c, s, restedOcv_mV(meanCell_mV, s.v1_mV), true);
    s.restAnchored = true;
  }
}

}  // namespace bms
