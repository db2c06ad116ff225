// State-of-charge estimate by an extended Kalman filter per series group, on the
// firmware's own 1-RC model (EkfConfig, the OCV table and capacity of SocConfig).
//
//   state  x = [soc, v1_mV]                    (positive I discharges)
//   predict soc -= I·dt / capacity;   v1 = a·v1 + r1·I·(1 - a),   a = exp(-dt / tau1)
//           P = F·P·F' + Q·dt,        F = diag(1, a)
//   update  v_pred = OCV(soc) - v1 - R0(soc,T)·I,   H = [dOCV/dsoc - I·dR0/dsoc, -1]
//           K = P·H' / (H·P·H' + R);  x += K·(v_meas - v_pred);  P = (I - K·H)·P
//   R0      R0(soc,T) = r0_mOhm(soc) · exp(r0ArrheniusK · (1/T_K - 1/T_ref_K)),
//           T_K = T + 273.15, T_ref = r0RefTemp_C, T the group's *measured* temperature:
//           its nearest cell thermistor (ThermistorMap::nearest) if that reads valid, else
//           the mean of the valid cell thermistors, else T_ref (factor 1); T is held
//           within -55…125 °C. Recomputed on every complete reading.
//
//   Q       Q = diag(socWalk², v1Walk² · w)·dt, w = 1 while |I| >= SocConfig::restCurrent_mA,
//           w → w·a² each tick at rest: nothing drives v1 at rest, so its model error fades
//           with the branch's own relaxation (bms_ekf.cpp, v1WalkShare).
//
// Started at the first complete reading from the OCV of the reading plus its R0·I drop
// (or from EkfConfig::initialSoc); R0(soc) is linear in the table like the OCV. Fixed arrays, float, no allocation:
// 24 bytes per series group (6.1 KiB for kMaxCells = 256), one array per quantity so that
// the groups' update runs in SIMD lanes where the CPU has them (bms_ekf.cpp). Per tick
// with a temperature factor: one expf per valid cell thermistor plus one for their mean.
#pragma once
#include <cstdint>

#include "bms_config.hpp"
#include "bms_limits.hpp"
#include "bms_rc.hpp"

namespace bms {

// Each series group's filter state at index g of every array (structure of arrays).
struct EkfState {
  bool started;
  bool r0Held;          // r0Scale holds the factors of the temperatures as they read now
  uint32_t last_ms;
  RcDecay decay;        // the RC branch's decay over the last tick length (bms_rc.hpp)
  float v1Walk;         // the share of v1's process noise the tick gets: 1 under load, fading
                        // as exp(-2t / tau1) over a rest (bms_ekf.cpp, v1WalkShare)
  float soc[kMaxCells];
  float v1_mV[kMaxCells];
  float p00[kMaxCells], p01[kMaxCells], p11[kMaxCells];  // covariance [soc², soc·mV, mV²]
  float r0Scale[kMaxCells];  // R0's temperature factor at the last complete reading (1 = T_ref)
};

// The configuration an EkfState runs with is the one it had since its reset.
void ekfReset(EkfState& s);
// One tick over `groups` series groups. `valid` = a complete cell measurement.
// `temp_dC` = this tick's thermistor readings (kTempInvalid_dC where invalid; nullptr:
// none, R0 at r0RefTemp_C), `therm` where each channel sits. tempsAsBefore: the caller
// knows temp_dC reads as at the previous call (the same array, every value the same),
// so R0's factors computed since then still hold (bms_core passes measure()'s answer);
// false recomputes them at every complete reading. current_mA is the tick's (the
// prediction moves with it); readingCurrent_mA, where given, is the current the cells
// of cell_mV were measured under, which the update and the start pair with them (a
// part measuring in a loop of its own reads its cells up to a loop before the tick:
// across a load step the tick's current is not theirs). nullptr: the tick's.
void ekfUpdate(const SocConfig& c, const ThermistorMap& therm, EkfState& s, uint16_t groups, bool valid, const uint16_t cell_mV[],
               int32_t current_mA, const int16_t temp_dC[], uint32_t now_ms, bool tempsAsBefore = false,
               const int32_t* readingCurrent_mA = nullptr);
// R0's temperature factor exp(r0ArrheniusK · (1/T_K - 1/T_ref_K)) at temp_C (held within
// -55…125 °C); exactly 1 when r0ArrheniusK = 0.
float ekfR0Factor(const EkfConfig& k, float temp_C);
// Mean SOC over the groups (0..1); 0 before the first reading. With groupPermille, each
// group's SOC in permille (rounded) into it as well, in the same pass.
float ekfPackSoc(const EkfState& s, uint16_t groups, uint16_t groupPermille[] = nullptr);
// Slope of the OCV table at soc, mV per unit SOC (the segment's; 0 for a flat table).
float ocvSlope_mV(const SocConfig& c, float soc);
// OCV table at soc (linear, clamped), mV.
float ocvAt_mV(const SocConfig& c, float soc);
// The EKF's R0 table at soc and its slope per unit SOC, mOhm (at r0RefTemp_C).
float r0At_mOhm(const SocConfig& c, float soc);
float r0Slope_mOhm(const SocConfig& c, float soc);

}  // namespace bms
