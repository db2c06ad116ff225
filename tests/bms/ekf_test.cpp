// The EKF per series group against an independent 1-RC cell integrated here in double
// (exact exponential update), with the firmware configured to the same model: it must
// converge from a wrong initial SOC and then track; the OCV table helpers agree with
// the table; the covariance stays positive; R0's temperature factor follows each
// group's measured temperature.
#include <bms/bms_ekf.hpp>
#include <bms/bms_measure.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <math.h>
#include <random>

#include "soc_fixture.hpp"

namespace {

// OCV 3000 mV (empty) .. 4200 mV (full) in 3 points, 2000 mAh, r0 30 mOhm empty and
// 20 mOhm from half full up, r1 10 mOhm, 30 s.
// The map the tests without temperatures pass (never read: no temp_dC).
const bms::ThermistorMap kNoMap{};

bms::SocConfig config() {
  bms::SocConfig c = bms_test::socConfig(3500);
  c.ekf = bms::EkfConfig{{30.0f, 20.0f, 20.0f}, 10.0f, 30.0f, 5.0f, 1.7e-4f, 1.0f, -1.0f, 0.05f, 0.0f, 25.0f};
  return c;
}

double ocvTrue_mV(double soc) {  // the same piecewise-linear curves, in double
  return soc < 0.5 ? 3000.0 + soc * 1000.0 : 3500.0 + (soc - 0.5) * 1400.0;
}
double r0True_ohm(double soc) { return soc < 0.5 ? 0.030 - soc * 0.020 : 0.020; }

TEST(Ekf, OcvTableValueAndSlope) {
  const bms::SocConfig c = config();
  EXPECT_NEAR(bms::ocvAt_mV(c, 0.25f), 3250.0f, 1e-3f);
  EXPECT_NEAR(bms::ocvAt_mV(c, 0.75f), 3850.0f, 1e-3f);
  EXPECT_NEAR(bms::ocvSlope_mV(c, 0.25f), 1000.0f, 1e-3f);
  EXPECT_NEAR(bms::ocvSlope_mV(c, 0.75f), 1400.0f, 1e-3f);
  EXPECT_NEAR(bms::ocvAt_mV(c, 1.2f), 4200.0f, 1e-3f);  // clamped
  EXPECT_NEAR(bms::r0At_mOhm(c, 0.25f), 25.0f, 1e-4f);
  EXPECT_NEAR(bms::r0Slope_mOhm(c, 0.25f), -20.0f, 1e-4f);
  EXPECT_NEAR(bms::r0Slope_mOhm(c, 0.75f), 0.0f, 1e-4f);
}

// A pulsed discharge of a 1-RC cell from 0.9 to about 0.35 (into the rising R0); the
// EKF starts at 0.5 although the cell is at 0.9.
TEST(Ekf, ConvergesFromAWrongInitialSocAndTracks) {
  bms::SocConfig c = config();
  c.ekf.initialSoc = 0.5f;
  c.ekf.initialSocSd = 0.3f;
  bms::EkfState s;
  bms::ekfReset(s);
  double soc = 0.9, v1_mV = 0.0;
  const double cap_As = 2.0 * 3600.0, r1 = 0.010, tau = 30.0, dt = 0.1;
  uint32_t t_ms = 0;
  double worstAfter60s = 0.0;
  for (int k = 0; k <= 36000; ++k, t_ms += 100) {  // one hour at 100 ms
    const double i_A = (k / 300) % 2 == 0 ? 2.0 : 0.2;  // 30 s at 1C, 30 s at 0.1C
    const uint16_t v = static_cast<uint16_t>(std::lround(ocvTrue_mV(soc) - v1_mV - r0True_ohm(soc) * i_A * 1e3));
    const int32_t i_mA = static_cast<int32_t>(std::lround(i_A * 1e3));
    bms::ekfUpdate(c, kNoMap, s, 1, true, &v, i_mA, nullptr, t_ms);
    if (k == 0) EXPECT_EQ(s.soc[0], 0.5f);  // started where it was told
    if (t_ms >= 60000) worstAfter60s = std::fmax(worstAfter60s, std::fabs(s.soc[0] - soc));
    EXPECT_GE(s.p00[0], 0.0f);
    EXPECT_GE(s.p00[0] * s.p11[0] - s.p01[0] * s.p01[0], -1e-3f);
    // The plant: exact update over the tick with the current held.
    const double a = std::exp(-dt / tau);
    v1_mV = a * v1_mV + r1 * i_A * 1e3 * (1.0 - a);
    soc -= i_A * dt / cap_As;
  }
  EXPECT_LT(worstAfter60s, 0.01);
  EXPECT_NEAR(bms::ekfPackSoc(s, 1), soc, 0.005);
}

// Without a complete reading it only predicts: coulomb counting at the model's capacity.
TEST(Ekf, PredictsByChargeWithoutReadings) {
  bms::SocConfig c = config();
  bms::EkfState s;
  bms::ekfReset(s);
  const uint16_t v[2] = {3500, 3500};
  bms::ekfUpdate(c, kNoMap, s, 2, true, v, 0, nullptr, 0);  // starts from the OCV: 0.5
  EXPECT_NEAR(bms::ekfPackSoc(s, 2), 0.5f, 1e-4f);
  for (uint32_t t = 100; t <= 360000; t += 100) bms::ekfUpdate(c, kNoMap, s, 2, false, v, 1000, nullptr, t);
  // 1 A for 360 s from 2000 mAh: -0.05.
  EXPECT_NEAR(bms::ekfPackSoc(s, 2), 0.45f, 1e-4f);
}

// A pack resting at 0.8 whose EKF is told it starts at 0.3 with the default 5 % sigma
// and the default noise (10 mV reading, 2 mV/sqrt(s) v1 walk), on a table as flat above
// half full as the LiPo's (700 mV per unit SOC): the first readings move the SOC to 0.6
// and leave the rest of the error (130 mV) in v1. At rest nothing drives the RC branch:
// whatever voltage it holds decays as exp(-t / tau1), so after 5 tau1 at most e^-5
// (0.7 %) of even the whole start error (0.5 SOC: 0.35 % SOC) can still sit there, and
// the SOC must be within 1 % of the truth from then on (measured: 0.15 % at 5 tau1). A
// v1 walk of constant size at rest held the error in v1 instead: 8.4 % off at 5 tau1,
// still 2.4 % after ten minutes.
TEST(Ekf, AtRestConvergesToTheOcvsSoc) {
  bms::SocConfig c = config();
  c.ekf.voltageSd_mV = 10.0f;
  c.ekf.v1SdPerSqrtS_mV = 2.0f;
  c.ekf.initialSoc = 0.3f;
  c.ekf.initialSocSd = 0.05f;
  c.ocv_mV[1] = 3850;  // 3850 mV at 0.5, 4200 mV full: 700 mV per unit SOC above half
  const double soc = 0.8;
  const uint16_t v = 3850 + 210;  // at rest: the OCV at 0.8
  bms::EkfState s;
  bms::ekfReset(s);
  const uint32_t settled_ms = static_cast<uint32_t>(5.0f * c.ekf.tau1_s * 1000.0f);
  double worstSettled = 0.0;
  for (uint32_t t_ms = 0; t_ms <= 600000; t_ms += 100) {  // ten minutes at 100 ms
    bms::ekfUpdate(c, kNoMap, s, 1, true, &v, 0, nullptr, t_ms);
    if (t_ms >= settled_ms) worstSettled = std::fmax(worstSettled, std::fabs(s.soc[0] - soc));
  }
  EXPECT_LT(worstSettled, 0.01);
  EXPECT_NEAR(s.v1_mV[0], 0.0f, 1.0f);  // the RC branch of a resting cell holds nothing
}

// A part measuring in a loop of its own (every 60 ms here, at 10 ms ticks) hands the
// firmware the cells of its last loop, taken before the tick: the loop that ran just
// before a 1C step from rest holds the rest voltage, read at the tick the current is
// already 2 A. Paired with the current of their own loop (readingCurrent_mA) the cells
// are consistent and the EKF stays on the plant's SOC; paired with the tick's current
// the missing I·R drop reads as charge.
double worstErrorAcrossAStepFromRest(bool paired) {
  bms::SocConfig c = config();
  bms::EkfState s;
  bms::ekfReset(s);
  double soc = 0.7, v1_mV = 0.0, i_A = 0.0;  // i_A: the current flowing before the tick
  const double cap_As = 2.0 * 3600.0, r1 = 0.010, tau = 30.0, dt = 0.01;
  uint16_t held_mV = 0;  // the part's registers: its last loop
  int32_t held_mA = 0;
  double worst = 0.0;
  for (int k = 0; k <= 1000; ++k) {  // 10 s
    const bool loop = k % 6 == 0;    // the loop ran just before this tick's read-out
    if (loop) {
      held_mV = static_cast<uint16_t>(std::lround(ocvTrue_mV(soc) - v1_mV - r0True_ohm(soc) * i_A * 1e3));
      held_mA = static_cast<int32_t>(std::lround(i_A * 1e3));
    }
    i_A = k >= 102 ? 2.0 : 0.0;  // the step, right after the loop of tick 102
    const int32_t i_mA = static_cast<int32_t>(std::lround(i_A * 1e3));
    const uint32_t t_ms = static_cast<uint32_t>(k) * 10u;
    bms::ekfUpdate(c, kNoMap, s, 1, loop, &held_mV, i_mA, nullptr, t_ms, false, paired ? &held_mA : nullptr);
    if (s.started) worst = std::fmax(worst, std::fabs(s.soc[0] - soc));
    const double a = std::exp(-dt / tau);
    v1_mV = a * v1_mV + r1 * i_A * 1e3 * (1.0 - a);
    soc -= i_A * dt / cap_As;
  }
  return worst;
}

TEST(Ekf, PairsAReadingWithTheCurrentItsCellsWereMeasuredUnder) {
  // Paired: within a 1 mV reading over the table's 1.4 V per unit SOC (0.07 %), which
  // the filter averages over its readings (measured: 0.006 %).
  EXPECT_LT(worstErrorAcrossAStepFromRest(true), 0.0005);
  // The contrast: the one loop read under the tick's current misses R0·I = 40 mV and
  // moves the SOC by ten times that (measured: 0.19 %).
  EXPECT_GT(worstErrorAcrossAStepFromRest(false), 0.001);
}

// R0's Arrhenius factor, computed here in double: exp(K·(1/T_K − 1/T_ref_K)).
double arrhenius(double k_K, double temp_C, double ref_C) {
  return std::exp(k_K * (1.0 / (temp_C + 273.15) - 1.0 / (ref_C + 273.15)));
}

// Two groups, each nearest its own cell thermistor (channels 0 and 1); channel 2 is a
// board thermistor outside the cell range that must never be read.
bms::SocConfig thermalConfig() {
  bms::SocConfig c = config();
  c.ekf.r0ArrheniusK = 2000.0f;
  c.ekf.r0RefTemp_C = 25.0f;
  return c;
}

bms::ThermistorMap thermalMap() {
  bms::ThermistorMap m{};
  m.cell = 0b011;
  m.board = 0b100;
  m.perBoard = 1;
  for (uint8_t& ch : m.nearest) ch = bms::kMaxThermistors;
  m.nearest[0] = 0;
  m.nearest[1] = 1;
  return m;
}

TEST(Ekf, R0FollowsEachGroupsMeasuredTemperature) {
  const bms::SocConfig c = thermalConfig();
  const bms::ThermistorMap map = thermalMap();
  bms::EkfState s;
  bms::ekfReset(s);
  const uint16_t v[2] = {3500, 3500};
  int16_t t_dC[3] = {0, 450, 900};  // group 0 at 0 °C, group 1 at 45 °C, board at 90 °C
  bms::ekfUpdate(c, map, s, 2, true, v, 1000, t_dC, 0);
  EXPECT_NEAR(s.r0Scale[0], arrhenius(2000.0, 0.0, 25.0), 1e-4);   // 1.85
  EXPECT_NEAR(s.r0Scale[1], arrhenius(2000.0, 45.0, 25.0), 1e-4);  // 0.66
  EXPECT_NEAR(bms::ekfR0Factor(c.ekf, 25.0f), 1.0f, 1e-6f);
  // Group 0's thermistor opens: it takes the mean of the valid cell thermistors (45 °C
  // alone, never the board's 90 °C).
  t_dC[0] = bms::kTempInvalid_dC;
  bms::ekfUpdate(c, map, s, 2, true, v, 1000, t_dC, 100);
  EXPECT_NEAR(s.r0Scale[0], arrhenius(2000.0, 45.0, 25.0), 1e-4);
  // Both valid again, group 0 at 10 °C: the mean fallback is not used.
  t_dC[0] = 100;
  bms::ekfUpdate(c, map, s, 2, true, v, 1000, t_dC, 200);
  EXPECT_NEAR(s.r0Scale[0], arrhenius(2000.0, 10.0, 25.0), 1e-4);
  // No valid cell thermistor: the reference (the flashed table as it is).
  t_dC[0] = t_dC[1] = bms::kTempInvalid_dC;
  bms::ekfUpdate(c, map, s, 2, true, v, 1000, t_dC, 300);
  EXPECT_EQ(s.r0Scale[0], 1.0f);
  EXPECT_EQ(s.r0Scale[1], 1.0f);
  // Without a factor (K = 0) the temperature is not read at all.
  bms::SocConfig flat = c;
  flat.ekf.r0ArrheniusK = 0.0f;
  t_dC[0] = -200;
  bms::ekfUpdate(flat, map, s, 2, true, v, 1000, t_dC, 400);
  EXPECT_EQ(s.r0Scale[0], 1.0f);
}

// The mean fallback is the factor of the mean temperature (10 °C and 40 °C: 25 °C, 1.0).
TEST(Ekf, R0FallbackIsTheFactorOfTheMeanCellTemperature) {
  bms::SocConfig c = thermalConfig();
  bms::ThermistorMap map = thermalMap();
  map.nearest[0] = 7;  // a channel that is no cell thermistor
  bms::EkfState s;
  bms::ekfReset(s);
  const uint16_t v[2] = {3500, 3500};
  const int16_t t_dC[2] = {100, 400};
  bms::ekfUpdate(c, map, s, 2, true, v, 0, t_dC, 0);
  EXPECT_NEAR(s.r0Scale[0], 1.0f, 1e-5f);
  EXPECT_NEAR(s.r0Scale[1], arrhenius(2000.0, 40.0, 25.0), 1e-4);
}

// A cell at 0 °C whose R0 is the table × its Arrhenius factor (1.85): with the
// thermistor reading 0 °C the EKF tracks it as well as at the reference; told 25 °C
// (the old, temperature-blind firmware) it misreads the larger drop as a lower SOC.
double worstErrorOnAColdCell(int16_t measured_dC) {
  bms::SocConfig c = thermalConfig();
  c.ekf.initialSoc = 0.9f;
  bms::EkfState s;
  bms::ekfReset(s);
  const double factor = arrhenius(2000.0, 0.0, 25.0);
  double soc = 0.9, v1_mV = 0.0, worst = 0.0;
  const double cap_As = 2.0 * 3600.0, r1 = 0.010, tau = 30.0, dt = 0.1;
  uint32_t t_ms = 0;
  const int16_t t_dC[2] = {measured_dC, measured_dC};
  for (int k = 0; k <= 18000; ++k, t_ms += 100) {  // half an hour at 100 ms
    const double i_A = (k / 300) % 2 == 0 ? 2.0 : 0.2;
    const uint16_t v = static_cast<uint16_t>(
        std::lround(ocvTrue_mV(soc) - v1_mV - r0True_ohm(soc) * factor * i_A * 1e3));
    bms::ekfUpdate(c, thermalMap(), s, 1, true, &v, static_cast<int32_t>(std::lround(i_A * 1e3)), t_dC, t_ms);
    worst = std::fmax(worst, std::fabs(s.soc[0] - soc));
    const double a = std::exp(-dt / tau);
    v1_mV = a * v1_mV + r1 * i_A * 1e3 * (1.0 - a);
    soc -= i_A * dt / cap_As;
  }
  return worst;
}

TEST(Ekf, TracksAColdCellWithItsMeasuredTemperature) {
  const double right = worstErrorOnAColdCell(0), blind = worstErrorOnAColdCell(250);
  EXPECT_LT(right, 0.01);
  EXPECT_GT(blind, 2.0 * right);
  EXPECT_GT(blind, 0.01);
}

// ekfUpdate bit for bit against the straightforward form it replaced (every channel up
// to the highest cell channel walked, the mean's factor always computed, the update's
// segment through the clamping lookup, one group at a time with a branch where the
// innovation variance is not positive), over random maps, temperatures with invalid
// readings, currents and ticks with and without a fresh reading, and group counts that
// leave 0 to 3 groups after the blocks of four the firmware updates in SIMD lanes; the
// firmware told whenever the temperatures read as at its previous call (R0's factors
// kept), the reference recomputing them at every fresh reading.
namespace reference {

float clamp01(float v) { return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v); }

void setR0Scales(const bms::EkfConfig& k, const bms::ThermistorMap& therm, bms::EkfState& s, uint16_t groups,
                 const int16_t temp_dC[]) {
  if (k.r0ArrheniusK == 0.0f || temp_dC == nullptr) {
    for (uint16_t g = 0; g < groups; ++g) s.r0Scale[g] = 1.0f;
    return;
  }
  uint16_t channels = 0;
  while (channels < bms::kMaxThermistors && (therm.cell >> channels) != 0) ++channels;
  float factor[bms::kMaxThermistors];
  int32_t sum_dC = 0;
  uint16_t valid = 0;
  for (uint16_t ch = 0; ch < channels; ++ch) {
    factor[ch] = 0.0f;
    if (!bms::thermOn(therm.cell, static_cast<uint8_t>(ch)) || temp_dC[ch] == bms::kTempInvalid_dC) continue;
    factor[ch] = bms::ekfR0Factor(k, static_cast<float>(temp_dC[ch]) * 0.1f);
    sum_dC += temp_dC[ch];
    ++valid;
  }
  const float mean =
      valid > 0 ? bms::ekfR0Factor(k, static_cast<float>(sum_dC) * 0.1f / static_cast<float>(valid)) : 1.0f;
  for (uint16_t g = 0; g < groups; ++g) {
    const uint16_t ch = therm.nearest[g];
    s.r0Scale[g] = ch < channels && factor[ch] > 0.0f ? factor[ch] : mean;
  }
}

void update(const bms::SocConfig& c, const bms::ThermistorMap& therm, bms::EkfState& s, uint16_t groups, bool valid,
            const uint16_t cell_mV[], int32_t current_mA, const int16_t temp_dC[], uint32_t now_ms) {
  const uint32_t dt_ms = now_ms - s.last_ms;
  s.last_ms = now_ms;
  if (valid) setR0Scales(c.ekf, therm, s, groups, temp_dC);
  const bms::EkfConfig& k = c.ekf;
  const float dt_s = static_cast<float>(dt_ms) * 1e-3f;
  const float i_mA = static_cast<float>(current_mA);
  const float a = k.tau1_s > 0.0f ? expf(-dt_s / k.tau1_s) : 0.0f;
  const float dSoc = i_mA * static_cast<float>(dt_ms) / (c.capacity_mAh * 3.6e6f);
  const float v1Drive_mV = k.r1_mOhm * i_mA * 1e-3f * (1.0f - a);
  const float qSoc = k.socSdPerSqrtS * k.socSdPerSqrtS * dt_s;
  // v1's walk: full under load, fading by a² a tick at rest (below 1e-6: none).
  const bool rest = current_mA > -c.restCurrent_mA && current_mA < c.restCurrent_mA;
  s.v1Walk = rest ? s.v1Walk * a * a : 1.0f;
  if (s.v1Walk < 1e-6f) s.v1Walk = 0.0f;
  const float qV1 = k.v1SdPerSqrtS_mV * k.v1SdPerSqrtS_mV * dt_s * s.v1Walk;
  const float r = k.voltageSd_mV * k.voltageSd_mV;
  const float perUnitSoc = static_cast<float>(c.ocvPoints - 1);
  for (uint16_t g = 0; g < groups; ++g) {
    struct {
      float &soc, &v1_mV, &p00, &p01, &p11, &r0Scale;
    } e{s.soc[g], s.v1_mV[g], s.p00[g], s.p01[g], s.p11[g], s.r0Scale[g]};
    e.soc = clamp01(e.soc - dSoc);
    e.v1_mV = a * e.v1_mV + v1Drive_mV;
    e.p00 += qSoc;
    e.p01 *= a;
    e.p11 = a * a * e.p11 + qV1;
    if (!valid) continue;
    const float pos = clamp01(e.soc) * static_cast<float>(c.ocvPoints - 1);
    uint8_t i = static_cast<uint8_t>(pos);
    if (i >= c.ocvPoints - 1) i = static_cast<uint8_t>(c.ocvPoints - 2);
    const float frac = pos - static_cast<float>(i);
    const float ocvLo = static_cast<float>(c.ocv_mV[i]), ocvHi = static_cast<float>(c.ocv_mV[i + 1]);
    const float r0Lo = k.r0_mOhm[i] * e.r0Scale, r0Hi = k.r0_mOhm[i + 1] * e.r0Scale;
    const float i_A = i_mA * 1e-3f;
    const float h0 = ((ocvHi - ocvLo) - (r0Hi - r0Lo) * i_A) * perUnitSoc;
    const float v_pred = ocvLo + frac * (ocvHi - ocvLo) - e.v1_mV - (r0Lo + frac * (r0Hi - r0Lo)) * i_A;
    const float innovation = static_cast<float>(cell_mV[g]) - v_pred;
    const float ph0 = e.p00 * h0 - e.p01;
    const float ph1 = e.p01 * h0 - e.p11;
    const float sInn = h0 * ph0 - ph1 + r;
    if (!(sInn > 0.0f)) continue;
    const float k0 = ph0 / sInn, k1 = ph1 / sInn;
    e.soc = clamp01(e.soc + k0 * innovation);
    e.v1_mV += k1 * innovation;
    e.p00 -= k0 * ph0;
    e.p01 -= k0 * ph1;
    e.p11 -= k1 * ph1;
    if (e.p00 < 0.0f) e.p00 = 0.0f;
    if (e.p11 < 0.0f) e.p11 = 0.0f;
  }
}

}  // namespace reference

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(Ekf, MatchesTheStraightforwardFormBitForBit) {
  std::mt19937 rng(5);
  auto pick = [&](uint32_t n) { return rng() % n; };
  constexpr uint16_t kMaxGroups = 24;
  for (int run = 0; run < 60; ++run) {
    const uint16_t kGroups = static_cast<uint16_t>(kMaxGroups - run % 4 - (run % 7 == 0 ? 20 : 0));
    bms::SocConfig c = thermalConfig();
    c.ekf.r0ArrheniusK = run % 5 == 0 ? 0.0f : 500.0f + static_cast<float>(pick(4000));
    if (run % 3 == 1) {  // no measurement or v1 noise, a flat lower half: a group there has
      c.ekf.voltageSd_mV = c.ekf.v1SdPerSqrtS_mV = 0.0f;  // no innovation variance (kept
      c.ocv_mV[1] = c.ocv_mV[0];                          // predicted), one above has some
      c.ekf.r0_mOhm[0] = c.ekf.r0_mOhm[1];
    }
    bms::ThermistorMap m{};
    m.cell = (uint64_t{rng()} << 32 | rng()) & ((uint64_t{1} << bms::kMaxThermistors) - 1) & (run % 2 ? ~0ull : 0xFFull);
    for (uint8_t& ch : m.nearest) ch = bms::kMaxThermistors;
    for (uint16_t g = 0; g < kGroups; ++g)  // mostly a channel, now and then none or a non-cell one
      m.nearest[g] = static_cast<uint8_t>(pick(8) == 0 ? bms::kMaxThermistors : pick(bms::kMaxThermistors));
    static bms::EkfState mine, ref;
    bms::ekfReset(mine);
    bms::ekfReset(ref);
    uint16_t cell_mV[kMaxGroups];
    int16_t temp_dC[bms::kMaxThermistors], last_dC[bms::kMaxThermistors];
    uint32_t now = 4294960000u + static_cast<uint32_t>(pick(5000));  // across the millisecond wrap
    for (int tick = 0; tick < 300; ++tick) {
      now += 1 + pick(30);
      for (uint16_t g = 0; g < kGroups; ++g) cell_mV[g] = static_cast<uint16_t>(2900 + pick(1400));
      // New temperatures every tick in some runs, now and then in the others (held in
      // between: the firmware keeps R0's factors while told they read as before).
      if (tick == 0 || run % 3 == 0 || pick(4) == 0) {
        for (int16_t& t : temp_dC) t = pick(10) == 0 ? bms::kTempInvalid_dC : static_cast<int16_t>(pick(1800)) - 600;
        for (uint8_t ch = 1; ch < bms::kMaxThermistors; ++ch)  // neighbours reading the same, now and then
          if (pick(3) == 0) temp_dC[ch] = temp_dC[ch - 1];
      }
      const bool asBefore = tick > 0 && std::memcmp(temp_dC, last_dC, sizeof temp_dC) == 0;
      std::memcpy(last_dC, temp_dC, sizeof temp_dC);
      // Now and then a tick at rest (|I| below the rest current: v1's walk fades).
      const bool small = pick(5) == 0;
      const int32_t current_mA = small ? static_cast<int32_t>(pick(400)) - 200 : static_cast<int32_t>(pick(20000)) - 10000;
      const bool valid = pick(4) != 0;
      bms::ekfUpdate(c, m, mine, kGroups, valid, cell_mV, current_mA, temp_dC, now, asBefore);
      if (!ref.started) {  // the start is unchanged: take it from the firmware
        if (mine.started) ref = mine;
        else ref.last_ms = now;
        continue;
      }
      reference::update(c, m, ref, kGroups, valid, cell_mV, current_mA, temp_dC, now);
      for (uint16_t g = 0; g < kGroups; ++g) {
        ASSERT_TRUE(sameBits(mine.soc[g], ref.soc[g]) && sameBits(mine.v1_mV[g], ref.v1_mV[g]) &&
                    sameBits(mine.p00[g], ref.p00[g]) && sameBits(mine.p01[g], ref.p01[g]) &&
                    sameBits(mine.p11[g], ref.p11[g]) && sameBits(mine.r0Scale[g], ref.r0Scale[g]))
            << "run " << run << " tick " << tick << " group " << g;
      }
    }
  }
}

}  // namespace
