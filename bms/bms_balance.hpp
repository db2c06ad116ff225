// Passive balancing policy: which cells switch their balancing resistor on.
//
//   allowed   the core permits it (no fatal fault, every monitor answered), the
//             configured condition holds (charging, rest = |I| < restCurrent for rest_ms,
//             either, or always) and the balancing board is not paused
//   board     paused while the hottest board thermistor is above boardMax (or a board
//             thermistor reads at a rail); resumes below boardResume. With boardCount > 1
//             each board's thermistors pause only the cells on that board
//   spread    active from max - min > startDelta until max - min < stopDelta (hysteresis)
//   cells     every cell more than stopDelta above the minimum and not below minCell,
//             highest first; with noAdjacent a cell next to a chosen one is skipped
//   readings  with averageReadings = N > 1 every comparison above uses each cell's mean
//             of its last N readings (a block average, refreshed every N read-outs
//             while balancing is permitted): the minimum of many noisy single readings sits
//             well under the truth, and cells already balanced would bleed
//   timer     the mask is decided every period_ms and held in between; the monitor IC's
//             balancing timer (balanceTime_s) is rewritten (re-armed) when half of it
//             has run, so the device keeps balancing only while the host is alive
//
// Note: a balancing cell reads low by I_bal·R0 (its own resistor loads it); the stop
// threshold absorbs this, as in real firmware that does not pause to measure.
#pragma once
#include <cstdint>

#include "bms_config.hpp"
#include "bms_hal.hpp"
#include "bms_rest.hpp"

namespace bms {

enum class BalanceStatus : uint8_t {
  Disabled = 0,     // not configured, or the core forbids it (fault, init)
  NotAllowed = 1,   // not charging / not at rest, as configured
  BoardHot = 2,     // paused on board temperature
  Balanced = 3,     // spread within the thresholds
  Balancing = 4,    // at least one cell balancing
};

struct BalanceState {
  bool active;            // spread hysteresis
  bool boardPaused;       // every board paused
  bool boardHot[kMaxBoards];
  RestTimer rest;
  bool decided;
  uint32_t lastDecision_ms;
  uint32_t lastArm_ms;
  uint32_t mask[kBalanceWords];
  BalanceStatus status;
  // Block average of the readings (averageReadings > 1).
  uint32_t sum_mV[kMaxCells];
  uint8_t summed;               // readings in sum_mV so far
  bool haveMean;
  uint16_t mean_mV[kMaxCells];
  uint16_t meanMin_mV, meanMax_mV;
};

void balanceReset(BalanceState& s);

// One tick of the policy. `permitted`: the core allows balancing now; `charging`: the
// pack is on the charger (state Charge); `fresh`: the cell readings are a new read-out
// (between read-outs the telemetry holds the last one); `packRange`: {min, max} of the
// other boards' cells in a pack of several (bms_pack.hpp), or null: the spread and the
// floor are the whole pack's, so a board whose cells all sit high bleeds them down to
// the pack's lowest. Writes the mask; `armCount` is incremented when the monitor's
// balancing timer is to be rewritten this tick.
void balanceStep(const Config& cfg, BalanceState& s, const Telemetry& tm, bool permitted, bool charging, bool fresh,
                 uint32_t now_ms, uint32_t mask[kBalanceWords], uint8_t& armCount, const uint16_t* packRange = nullptr);
// The lowest and highest cell the policy compares on this board: the block means when
// averaging (once a block is full), else the readings.
void balanceRange(const Config& cfg, const BalanceState& s, const Telemetry& tm, uint16_t& min_mV, uint16_t& max_mV);

inline bool balanceBit(const uint32_t mask[kBalanceWords], uint16_t cell) {
  return (mask[cell / 32] >> (cell % 32)) & 1u;
}

}  // namespace bms
