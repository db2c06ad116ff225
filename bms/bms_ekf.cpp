#include "bms_ekf.hpp"

#include <math.h>
#include <stddef.h>

#include "bms_measure.hpp"
#include "bms_soc.hpp"

namespace bms {

namespace {

// Two selects one after the other, each of two values (the same result as the chain
// v < 0 ? 0 : (v > 1 ? 1 : v), NaN and -0 included): GCC if-converts these in a loop.
float atLeast0(float v) { return v < 0.0f ? 0.0f : v; }
float clamp01(float v) {
  const float low = atLeast0(v);
  return low > 1.0f ? 1.0f : low;
}

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
    for (uint16_t g = 0; g < groups; ++g) s.r0Scale[g] = 1.0f;
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
      s.r0Scale[g] = factor[ch];
      continue;
    }
    if (!meanKnown) {
      mean = valid > 0 ? r0Factor(k, invRef, static_cast<float>(sum_dC) * 0.1f / static_cast<float>(valid)) : 1.0f;
      meanKnown = true;
    }
    s.r0Scale[g] = mean;
  }
}

void start(const SocConfig& c, EkfState& s, uint16_t groups, const uint16_t cell_mV[], int32_t current_mA) {
  const EkfConfig& k = c.ekf;
  for (uint16_t g = 0; g < groups; ++g) {
    // The reading plus the R0 drop at the SOC the reading itself suggests.
    const float loaded = socFromOcv(c, cell_mV[g]);
    const float drop_mV = r0At_mOhm(c, loaded) * s.r0Scale[g] * static_cast<float>(current_mA) * 1e-3f;
    const float ocv_mV = static_cast<float>(cell_mV[g]) + drop_mV;
    const uint16_t ocv = static_cast<uint16_t>(ocv_mV < 0.0f ? 0.0f : (ocv_mV > 65535.0f ? 65535.0f : ocv_mV));
    s.soc[g] = k.initialSoc >= 0.0f ? k.initialSoc : socFromOcv(c, ocv);
    s.v1_mV[g] = 0.0f;
    s.p00[g] = k.initialSocSd * k.initialSocSd;
    s.p01[g] = 0.0f;
    s.p11[g] = k.voltageSd_mV * k.voltageSd_mV;
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
  float i_A;         // the current the reading was measured under
  float perUnitSoc;  // table segments per unit SOC
  int lastSegment;   // the same as an int: the segment index stays below it
};

// The groups go through a tick in blocks of kLanes: each step is a loop of a fixed
// count over the block, which GCC vectorises even at -O2 (its very-cheap cost model takes
// only a loop whose count is a multiple of the lanes); the groups left over go through
// the same steps one at a time (N = 1). SIMD lanes do each group's IEEE operations in the
// same order as the scalar code, so every group's result is the same bits either way.
// Four floats fill an SSE or NEON register (a Cortex-M4 has none: there the loops stay
// scalar, the same work as one group at a time). On a host this saves about 45 of the
// update's instructions a group (of about 130) in the blocks; a group left over costs
// what it did.
constexpr size_t kLanes = 4;

// The prediction of N groups from g0.
template <size_t N>
void predict(const TickTerms& t, EkfState& s, size_t g0) {
  for (size_t g = g0; g < g0 + N; ++g) {
    s.soc[g] = clamp01(s.soc[g] - t.dSoc);
    s.v1_mV[g] = t.a * s.v1_mV[g] + t.v1Drive_mV;
    s.p00[g] += t.qSoc;
    s.p01[g] *= t.a;
    s.p11[g] = t.a * t.a * s.p11[g] + t.qV1;
  }
}

// The update of N groups from g0 with their readings, in loops the vectoriser takes but
// for the table lookups:
//   1. where each group's SOC sits in the table (soc was clamped by predict, so the
//      segment is taken without segment()'s clamp: the same bits);
//   2. the rows at the segment's ends and the reading, a lookup per group;
//   3. the update's arithmetic, every group's candidate state;
//   4. the choice, written back: a group whose innovation variance is not positive
//      keeps its prediction.
// Every step goes into local arrays of one value each, and the arithmetic is done for
// every group before the choice: an operation or a store into the state on one side of
// a branch keeps GCC from if-converting a loop (FP operations may trap; a store of the
// state's own value is dropped, leaving the other one conditional), an array of structs
// is an interleaved access it does not take, and a uint16_t value in a loop of floats
// halves the lanes (the millivolts go through step 2 as int32_t).
template <size_t N>
void correct(const SocConfig& c, const TickTerms& t, const uint16_t cell_mV[], EkfState& s, size_t g0) {
  int32_t seg[N];
  float frac[N];
  for (size_t j = 0; j < N; ++j) {
    const float pos = s.soc[g0 + j] * t.perUnitSoc;
    // The segment as static_cast<uint8_t>(pos) is (the low byte of the 32-bit
    // conversion), kept below the last row.
    int32_t i = static_cast<int32_t>(pos) & 0xFF;
    i = i >= t.lastSegment ? t.lastSegment - 1 : i;
    seg[j] = i;
    frac[j] = pos - static_cast<float>(i);
  }
  // The millivolts as int32_t: converted to float in the lanes of step 3 (the same value).
  int32_t ocvLoMv[N], ocvHiMv[N], readingMv[N];
  float r0LoRef[N], r0HiRef[N];
  for (size_t j = 0; j < N; ++j) {
    const int32_t i = seg[j];
    ocvLoMv[j] = c.ocv_mV[i], ocvHiMv[j] = c.ocv_mV[i + 1];
    r0LoRef[j] = c.ekf.r0_mOhm[i], r0HiRef[j] = c.ekf.r0_mOhm[i + 1];  // at the reference temperature
    readingMv[j] = cell_mV[g0 + j];
  }
  float soc[N], v1[N], p00[N], p01[N], p11[N], sInn[N];  // the update
  float socP[N], v1P[N], p00P[N], p01P[N], p11P[N];      // the prediction
  for (size_t j = 0; j < N; ++j) {
    const size_t g = g0 + j;
    socP[j] = s.soc[g], v1P[j] = s.v1_mV[g], p00P[j] = s.p00[g], p01P[j] = s.p01[g], p11P[j] = s.p11[g];
    const float ocvLo = static_cast<float>(ocvLoMv[j]), ocvHi = static_cast<float>(ocvHiMv[j]);
    const float r0Lo = r0LoRef[j] * s.r0Scale[g], r0Hi = r0HiRef[j] * s.r0Scale[g];  // at the group's temperature
    const float h0 = ((ocvHi - ocvLo) - (r0Hi - r0Lo) * t.i_A) * t.perUnitSoc;
    const float v_pred = ocvLo + frac[j] * (ocvHi - ocvLo) - v1P[j] - (r0Lo + frac[j] * (r0Hi - r0Lo)) * t.i_A;
    const float innovation = static_cast<float>(readingMv[j]) - v_pred;
    const float ph0 = p00P[j] * h0 - p01P[j];  // (P·H')[0]
    const float ph1 = p01P[j] * h0 - p11P[j];  // (P·H')[1]
    sInn[j] = h0 * ph0 - ph1 + t.r;
    const float k0 = ph0 / sInn[j], k1 = ph1 / sInn[j];
    soc[j] = clamp01(socP[j] + k0 * innovation);
    v1[j] = v1P[j] + k1 * innovation;
    // P -= K·(H·P) with H·P = (P·H')' (P symmetric).
    p00[j] = atLeast0(p00P[j] - k0 * ph0);
    p01[j] = p01P[j] - k0 * ph1;
    p11[j] = atLeast0(p11P[j] - k1 * ph1);
  }
  for (size_t j = 0; j < N; ++j) {
    const size_t g = g0 + j;
    const bool take = sInn[j] > 0.0f;
    s.soc[g] = take ? soc[j] : socP[j];
    s.v1_mV[g] = take ? v1[j] : v1P[j];
    s.p00[g] = take ? p00[j] : p00P[j];
    s.p01[g] = take ? p01[j] : p01P[j];
    s.p11[g] = take ? p11[j] : p11P[j];
  }
}

// One tick of N groups from g0: the prediction, then the update when a fresh complete
// reading came (else prediction only).
template <size_t N>
void tick(const SocConfig& c, const TickTerms& t, bool valid, const uint16_t cell_mV[], EkfState& s, size_t g0) {
  predict<N>(t, s, g0);
  if (valid) correct<N>(c, t, cell_mV, s, g0);
}

// The share of v1's random walk this tick gets. The walk stands for the RC branch's
// model error: a flashed R1 or tau1 that is not the cell's, a relaxation pair the 1-RC
// model lacks. Every one of them is driven by the current (dv1/dt = (R1·I - v1)/tau1)
// and, once the current stops, dies away with the branch's relaxation: a cell resting
// several tau1 has no RC voltage left, and at zero current nothing drives v1. A walk of
// constant size at rest lets v1 hold any OCV error instead: started at 0.3 on a pack
// resting at 0.8, v1 took the error the first readings left (~75 mV, 11 % SOC on the
// LiPo's 700 mV per unit SOC) and the SOC crept back at a percent a minute (3.5 % off
// after two minutes, 0.7 % after ten). So the walk keeps its full size while the current
// is at least the rest current (the coulomb counter's rest too), and at rest its
// variance fades by a² a tick, exp(-2t / tau1): the decay of the variance of a voltage
// relaxing with tau1. Right after a load it still lets v1 follow a relaxation the model
// gets wrong; after a few tau1 v1 is held to the model's decay towards 0 and the
// readings go to the SOC (1 % within 5 tau1: Ekf.AtRestConvergesToTheOcvsSoc).
// Below 1e-6 the share is 0 (no subnormal floats on a long rest).
float v1WalkShare(const SocConfig& c, EkfState& s, int32_t current_mA, float a) {
  const bool rest = current_mA > -c.restCurrent_mA && current_mA < c.restCurrent_mA;
  const float w = rest ? s.v1Walk * a * a : 1.0f;
  s.v1Walk = w < 1e-6f ? 0.0f : w;
  return s.v1Walk;
}

}  // namespace

void ekfReset(EkfState& s) {
  s.started = false;
  s.r0Held = false;
  s.last_ms = 0;
  rcDecayReset(s.decay);
  s.v1Walk = 1.0f;  // a start may follow a load the firmware did not see
  for (uint16_t g = 0; g < kMaxCells; ++g) {
    s.soc[g] = s.v1_mV[g] = 0.0f;
    s.p00[g] = s.p01[g] = s.p11[g] = 0.0f;
    s.r0Scale[g] = 1.0f;
  }
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

// (The buffer tested once, not per group, and two groups a pass, the sum still added in
// group order: about 3 instructions a group a tick less on a host.)
float ekfPackSoc(const EkfState& s, uint16_t groups, uint16_t groupPermille[]) {
  float sum = 0.0f;
  if (groupPermille == nullptr) {
    for (uint16_t g = 0; g < groups; ++g) sum += s.soc[g];
  } else {
#pragma GCC unroll 2
    for (uint16_t g = 0; g < groups; ++g) {
      const float soc = s.soc[g];
      sum += soc;
      groupPermille[g] = static_cast<uint16_t>(soc * 1000.0f + 0.5f);
    }
  }
  if (!s.started || groups == 0) return 0.0f;
  return clamp01(sum / static_cast<float>(groups));
}

void ekfUpdate(const SocConfig& c, const ThermistorMap& therm, EkfState& s, uint16_t groups, bool valid, const uint16_t cell_mV[],
               int32_t current_mA, const int16_t temp_dC[], uint32_t now_ms, bool tempsAsBefore,
               const int32_t* readingCurrent_mA) {
  const int32_t reading_mA = readingCurrent_mA != nullptr ? *readingCurrent_mA : current_mA;
  const uint32_t dt_ms = now_ms - s.last_ms;
  s.last_ms = now_ms;
  if (c.ocvPoints < 2) return;  // no table, no model
  // R0's factors are a function of the readings alone (the map, the groups and the
  // configuration are the reset's): while no temperature moves they are kept (the
  // usual tick: a thermistor moves slowly), saving an expf per distinct reading and the
  // passes over the channels and groups.
  if (!tempsAsBefore) s.r0Held = false;
  if (valid && !s.r0Held) {
    setR0Scales(c.ekf, therm, s, groups, temp_dC);
    s.r0Held = true;
  }
  if (!s.started) {
    if (valid) start(c, s, groups, cell_mV, reading_mA);
    return;
  }
  const EkfConfig& k = c.ekf;
  const float dt_s = static_cast<float>(dt_ms) * 1e-3f;
  const float i_mA = static_cast<float>(current_mA);
  const float a = rcDecay(k.tau1_s, s.decay, dt_ms);
  const float dSoc = i_mA * static_cast<float>(dt_ms) / (c.capacity_mAh * 3.6e6f);
  const float v1Drive_mV = k.r1_mOhm * i_mA * 1e-3f * (1.0f - a);
  const float qSoc = k.socSdPerSqrtS * k.socSdPerSqrtS * dt_s;
  const float qV1 = k.v1SdPerSqrtS_mV * k.v1SdPerSqrtS_mV * dt_s * v1WalkShare(c, s, current_mA, a);
  const float r = k.voltageSd_mV * k.voltageSd_mV;
  const int lastSegment = c.ocvPoints - 1;  // table segments; segment() keeps i below this
  const float perUnitSoc = static_cast<float>(lastSegment);  // table segments per unit SOC
  const float i_A = static_cast<float>(reading_mA) * 1e-3f;
  const TickTerms t{a, dSoc, v1Drive_mV, qSoc, qV1, r, i_A, perUnitSoc, lastSegment};
  size_t g = 0;
  for (; g + kLanes <= groups; g += kLanes) tick<kLanes>(c, t, valid, cell_mV, s, g);
  for (; g < groups; ++g) tick<1>(c, t, valid, cell_mV, s, g);
}

}  // namespace bms
