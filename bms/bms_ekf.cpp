#include "bms_ekf.hpp"

#include <math.h>

#include "bms_measure.hpp"
#include "bms_soc.hpp"

namespace bms {

namespace {

float clamp01(float v) { return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v); }

// Segment of the table holding soc and the position inside it.
void segment(const SocConfig& c, float soc, uint8_t& i, float& frac) {
  const float pos = clamp01(soc) * static_cast<float>(c.ocvPoints - 1);
  uint8_t k = static_cast<uint8_t>(pos);
  if (k >= c.ocvPoints - 1) k = static_cast<uint8_t>(c.ocvPoints - 2);
  i = k;
  frac = pos - static_cast<float>(k);
}

// Linear in the table holding soc: value and slope per unit SOC.
float tableAt(const SocConfig& c, const float* y, float soc) {
  uint8_t i;
  float frac;
  segment(c, soc, i, frac);
  return y[i] + frac * (y[i + 1] - y[i]);
}
float tableSlope(const SocConfig& c, const float* y, float soc) {
  uint8_t i;
  float frac;
  segment(c, soc, i, frac);
  return (y[i + 1] - y[i]) * static_cast<float>(c.ocvPoints - 1);
}

// The index of the lowest set bit of m (m != 0); 32-bit count instructions only (a
// Cortex-M4 has no 64-bit one).
uint8_t lowestBit(uint64_t m) {
  const uint32_t lo = static_cast<uint32_t>(m);
  return static_cast<uint8_t>(lo != 0 ? __builtin_ctz(lo) : 32 + __builtin_ctz(static_cast<uint32_t>(m >> 32)));
}

// exp(K·(1/T - 1/T_ref)) with 1/T_ref given (the same quotient ekfR0Factor forms).
float r0Factor(const EkfConfig& k, float invRef, float temp_C) {
  const float t_C = temp_C < -55.0f ? -55.0f : (temp_C > 125.0f ? 125.0f : temp_C);
  return expf(k.r0ArrheniusK * (1.0f / (t_C + 273.15f) - invRef));
}

// Each group's R0 factor from this tick's thermistor readings: its own channel when
// valid, else the mean of the valid cell thermistors, else the reference (1).
void setR0Scales(const EkfConfig& k, const ThermistorMap& therm, EkfState& s, uint16_t groups, const int16_t temp_dC[]) {
  if (k.r0ArrheniusK == 0.0f || temp_dC == nullptr) {
    for (uint16_t g = 0; g < groups; ++g) s.group[g].r0Scale = 1.0f;
    return;
  }
  const float invRef = 1.0f / (k.r0RefTemp_C + 273.15f);
  // One pass per cell channel. factor[ch] is set for the cell channels with a valid
  // reading only (the group pass below reads no other).
  float factor[kMaxThermistors];
  uint64_t usable = 0;  // bit ch: a cell channel with a valid reading and a factor above 0
  int32_t sum_dC = 0;
  uint16_t valid = 0;
  int16_t last_dC = kTempInvalid_dC;  // the previous valid channel's reading and factor:
  float lastFactor = 0.0f;            // neighbours often read the same tenth of a degree
  for (uint64_t left = therm.cell; left != 0; left &= left - 1) {
    const uint8_t ch = lowestBit(left);
    if (ch >= kMaxThermistors) break;
    if (temp_dC[ch] == kTempInvalid_dC) continue;
    if (temp_dC[ch] != last_dC) {
      last_dC = temp_dC[ch];
      lastFactor = r0Factor(k, invRef, static_cast<float>(last_dC) * 0.1f);
    }
    factor[ch] = lastFactor;
    if (factor[ch] > 0.0f) usable |= uint64_t{1} << ch;
    sum_dC += temp_dC[ch];
    ++valid;
  }
  // The mean's factor only when a group has no usable channel of its own (an expf).
  float mean = 0.0f;
  bool meanKnown = false;
  for (uint16_t g = 0; g < groups; ++g) {
    const uint8_t ch = therm.nearest[g];
    if (ch < kMaxThermistors && thermOn(usable, ch)) {
      s.group[g].r0Scale = factor[ch];
      continue;
    }
    if (!meanKnown) {
      mean = valid > 0 ? r0Factor(k, invRef, static_cast<float>(sum_dC) * 0.1f / static_cast<float>(valid)) : 1.0f;
      meanKnown = true;
    }
    s.group[g].r0Scale = mean;
  }
}

void start(const SocConfig& c, EkfState& s, uint16_t groups, const uint16_t cell_mV[], int32_t current_mA) {
  const EkfConfig& k = c.ekf;
  for (uint16_t g = 0; g < groups; ++g) {
    EkfGroup& e = s.group[g];
    // The reading plus the R0 drop at the SOC the reading itself suggests.
    const float loaded = socFromOcv(c, cell_mV[g]);
    const float drop_mV = r0At_mOhm(c, loaded) * e.r0Scale * static_cast<float>(current_mA) * 1e-3f;
    const float ocv_mV = static_cast<float>(cell_mV[g]) + drop_mV;
    const uint16_t ocv = static_cast<uint16_t>(ocv_mV < 0.0f ? 0.0f : (ocv_mV > 65535.0f ? 65535.0f : ocv_mV));
    e.soc = k.initialSoc >= 0.0f ? k.initialSoc : socFromOcv(c, ocv);
    e.v1_mV = 0.0f;
    e.p00 = k.initialSocSd * k.initialSocSd;
    e.p01 = 0.0f;
    e.p11 = k.voltageSd_mV * k.voltageSd_mV;
  }
  s.started = true;
}

// What one tick's prediction and update share across the groups.
struct TickTerms {
  float a;           // the RC branch's decay over the tick
  float dSoc;        // SOC the current moves in the tick
  float v1Drive_mV;  // the RC voltage the current drives in the tick
  float qSoc, qV1;   // process noise over the tick
  float r;           // the reading's variance
  float i_A;
  float perUnitSoc;  // table segments per unit SOC
  int lastSegment;   // the same as an int: the segment index stays below it
};

void predict(const TickTerms& t, EkfGroup& e) {
  e.soc = clamp01(e.soc - t.dSoc);
  e.v1_mV = t.a * e.v1_mV + t.v1Drive_mV;
  e.p00 += t.qSoc;
  e.p01 *= t.a;
  e.p11 = t.a * t.a * e.p11 + t.qV1;
}

// The update with the group's reading. OCV and R0 (value and slope, at the group's
// temperature) from the one table segment holding soc; e.soc was clamped by predict,
// so the segment is taken without segment()'s clamp (the same bits).
void correct(const SocConfig& c, const TickTerms& t, uint16_t reading_mV, EkfGroup& e) {
  const EkfConfig& k = c.ekf;
  const float pos = e.soc * t.perUnitSoc;
  uint8_t i = static_cast<uint8_t>(pos);
  if (i >= t.lastSegment) i = static_cast<uint8_t>(t.lastSegment - 1);
  const float frac = pos - static_cast<float>(i);
  const float ocvLo = static_cast<float>(c.ocv_mV[i]), ocvHi = static_cast<float>(c.ocv_mV[i + 1]);
  const float r0Lo = k.r0_mOhm[i] * e.r0Scale, r0Hi = k.r0_mOhm[i + 1] * e.r0Scale;
  const float h0 = ((ocvHi - ocvLo) - (r0Hi - r0Lo) * t.i_A) * t.perUnitSoc;
  const float v_pred = ocvLo + frac * (ocvHi - ocvLo) - e.v1_mV - (r0Lo + frac * (r0Hi - r0Lo)) * t.i_A;
  const float innovation = static_cast<float>(reading_mV) - v_pred;
  const float ph0 = e.p00 * h0 - e.p01;  // (P·H')[0]
  const float ph1 = e.p01 * h0 - e.p11;  // (P·H')[1]
  const float sInn = h0 * ph0 - ph1 + t.r;
  if (!(sInn > 0.0f)) return;
  const float k0 = ph0 / sInn, k1 = ph1 / sInn;
  e.soc = clamp01(e.soc + k0 * innovation);
  e.v1_mV += k1 * innovation;
  // P -= K·(H·P) with H·P = (P·H')' (P symmetric).
  e.p00 -= k0 * ph0;
  e.p01 -= k0 * ph1;
  e.p11 -= k1 * ph1;
  if (e.p00 < 0.0f) e.p00 = 0.0f;
  if (e.p11 < 0.0f) e.p11 = 0.0f;
}

}  // namespace

void ekfReset(EkfState& s) {
  s.started = false;
  s.last_ms = 0;
  for (uint16_t g = 0; g < kMaxCells; ++g) s.group[g] = EkfGroup{0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f};
}

float ekfR0Factor(const EkfConfig& k, float temp_C) {
  if (k.r0ArrheniusK == 0.0f) return 1.0f;
  return r0Factor(k, 1.0f / (k.r0RefTemp_C + 273.15f), temp_C);
}

float ocvAt_mV(const SocConfig& c, float soc) {
  if (c.ocvPoints < 2) return 0.0f;
  uint8_t i;
  float frac;
  segment(c, soc, i, frac);
  const float lo = static_cast<float>(c.ocv_mV[i]), hi = static_cast<float>(c.ocv_mV[i + 1]);
  return lo + frac * (hi - lo);
}

float ocvSlope_mV(const SocConfig& c, float soc) {
  if (c.ocvPoints < 2) return 0.0f;
  uint8_t i;
  float frac;
  segment(c, soc, i, frac);
  return (static_cast<float>(c.ocv_mV[i + 1]) - static_cast<float>(c.ocv_mV[i])) * static_cast<float>(c.ocvPoints - 1);
}

float r0At_mOhm(const SocConfig& c, float soc) {
  return c.ocvPoints < 2 ? 0.0f : tableAt(c, c.ekf.r0_mOhm, soc);
}

float r0Slope_mOhm(const SocConfig& c, float soc) {
  return c.ocvPoints < 2 ? 0.0f : tableSlope(c, c.ekf.r0_mOhm, soc);
}

float ekfPackSoc(const EkfState& s, uint16_t groups, uint16_t groupPermille[]) {
  float sum = 0.0f;
  for (uint16_t g = 0; g < groups; ++g) {
    const float soc = s.group[g].soc;
    sum += soc;
    if (groupPermille != nullptr) groupPermille[g] = static_cast<uint16_t>(soc * 1000.0f + 0.5f);
  }
  if (!s.started || groups == 0) return 0.0f;
  return clamp01(sum / static_cast<float>(groups));
}

void ekfUpdate(const SocConfig& c, const ThermistorMap& therm, EkfState& s, uint16_t groups, bool valid, const uint16_t cell_mV[],
               int32_t current_mA, const int16_t temp_dC[], uint32_t now_ms) {
  const uint32_t dt_ms = now_ms - s.last_ms;
  s.last_ms = now_ms;
  if (c.ocvPoints < 2) return;  // no table, no model
  if (valid) setR0Scales(c.ekf, therm, s, groups, temp_dC);
  if (!s.started) {
    if (valid) start(c, s, groups, cell_mV, current_mA);
    return;
  }
  const EkfConfig& k = c.ekf;
  const float dt_s = static_cast<float>(dt_ms) * 1e-3f;
  const float i_mA = static_cast<float>(current_mA);
  const float a = k.tau1_s > 0.0f ? expf(-dt_s / k.tau1_s) : 0.0f;
  const float dSoc = i_mA * static_cast<float>(dt_ms) / (c.capacity_mAh * 3.6e6f);
  const float v1Drive_mV = k.r1_mOhm * i_mA * 1e-3f * (1.0f - a);
  const float qSoc = k.socSdPerSqrtS * k.socSdPerSqrtS * dt_s;
  const float qV1 = k.v1SdPerSqrtS_mV * k.v1SdPerSqrtS_mV * dt_s;
  const float r = k.voltageSd_mV * k.voltageSd_mV;
  const int lastSegment = c.ocvPoints - 1;  // table segments; segment() keeps i below this
  const float perUnitSoc = static_cast<float>(lastSegment);  // table segments per unit SOC
  const float i_A = i_mA * 1e-3f;
  const TickTerms t{a, dSoc, v1Drive_mV, qSoc, qV1, r, i_A, perUnitSoc, lastSegment};
  for (uint16_t g = 0; g < groups; ++g) {
    // The group in registers for the tick: a store into the state could alias the
    // configuration's float tables, so the compiler would store and reload between steps.
    EkfGroup e = s.group[g];
    predict(t, e);
    if (valid) correct(c, t, cell_mV[g], e);  // a fresh complete reading; else prediction only
    s.group[g] = e;
  }
}

}  // namespace bms
