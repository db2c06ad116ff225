#include "bms_balance.hpp"

#include <cstring>

#include "bms_measure.hpp"

namespace bms {

void balanceReset(BalanceState& s) {
  s.active = false;
  s.boardPaused = false;
  for (uint8_t k = 0; k < kMaxBoards; ++k) s.boardHot[k] = false;
  restReset(s.rest);
  s.decided = false;
  s.lastDecision_ms = 0;
  s.lastArm_ms = 0;
  for (uint8_t w = 0; w < kBalanceWords; ++w) s.mask[w] = 0;
  s.status = BalanceStatus::Disabled;
  for (uint16_t c = 0; c < kMaxCells; ++c) s.sum_mV[c] = 0, s.mean_mV[c] = 0;
  s.summed = 0;
  s.haveMean = false;
  s.meanMin_mV = s.meanMax_mV = 0;
}

namespace {

void clearMask(uint32_t mask[kBalanceWords]) {
  for (uint8_t w = 0; w < kBalanceWords; ++w) mask[w] = 0;
}

void setBit(uint32_t mask[kBalanceWords], uint16_t cell) { mask[cell / 32] |= 1u << (cell % 32); }

// Boards in use (1 unless boardCount > 1; never more than the state holds).
uint8_t boards(const BalanceConfig& b) {
  return b.boardCount <= 1 ? 1 : (b.boardCount < kMaxBoards ? b.boardCount : kMaxBoards);
}

uint8_t boardOf(const BalanceConfig& b, uint16_t cell) {
  if (boards(b) == 1 || b.cellsPerBoard == 0) return 0;
  const uint16_t k = static_cast<uint16_t>(cell / b.cellsPerBoard);
  return static_cast<uint8_t>(k < boards(b) ? k : boards(b) - 1);
}

// Board temperature hysteresis per board; an unreadable board thermistor pauses its board.
void updateBoard(const Config& cfg, BalanceState& s, const Telemetry& tm) {
  const BalanceConfig& b = cfg.balance;
  const uint8_t n = boards(b);
  const uint8_t perBoard = cfg.therm.perBoard;
  bool all = true;
  uint8_t ch = 0;  // the board channels in order: perBoard for each board
  for (uint8_t k = 0; k < n; ++k) {
    int16_t hottest = INT16_MIN;
    bool invalid = false;
    for (uint8_t i = 0; i < perBoard; ++i, ++ch) {
      while (ch < kMaxThermistors && !thermOn(cfg.therm.board, ch)) ++ch;
      if (ch >= kMaxThermistors) break;
      const int16_t t = tm.temperature_dC[ch];
      if (t == kTempInvalid_dC) invalid = true;
      else if (t > hottest) hottest = t;
    }
    if (perBoard == 0) {
      s.boardHot[k] = false;
    } else if (invalid || hottest > b.boardMax_dC) {
      s.boardHot[k] = true;
    } else if (hottest < b.boardResume_dC) {
      s.boardHot[k] = false;
    }
    all = all && s.boardHot[k];
  }
  s.boardPaused = all;
}

bool conditionHolds(const BalanceConfig& b, const BalanceState& s, bool charging, uint32_t now_ms) {
  const bool rest = restedFor(s.rest, now_ms, b.rest_ms);
  switch (b.when) {
    case BalanceWhen::Charging: return charging;
    case BalanceWhen::Rest: return rest;
    case BalanceWhen::ChargingOrRest: return charging || rest;
    case BalanceWhen::Always: return true;
  }
  return false;
}

// The cell voltages the policy compares: each reading, or each cell's block mean.
struct Readings {
  const uint16_t* cell_mV;
  uint16_t min_mV, max_mV;
};

// Adds a new read-out's readings to the block; a full block replaces the means.
// Restarts while balancing is not permitted (a silent device reads 0).
void accumulate(const Config& cfg, BalanceState& s, const Telemetry& tm, bool permitted, bool fresh) {
  const uint8_t n = cfg.balance.averageReadings;
  if (n <= 1) return;
  if (!permitted) {
    for (uint16_t c = 0; c < cfg.cellCount; ++c) s.sum_mV[c] = 0;
    s.summed = 0;
    s.haveMean = false;
    return;
  }
  if (!fresh) return;  // the same reading again is no new sample
  for (uint16_t c = 0; c < cfg.cellCount; ++c) s.sum_mV[c] += tm.cellVoltage_mV[c];
  if (++s.summed < n) return;
  uint16_t lo = UINT16_MAX, hi = 0;
  for (uint16_t c = 0; c < cfg.cellCount; ++c) {
    const uint16_t m = static_cast<uint16_t>((s.sum_mV[c] + n / 2u) / n);
    s.mean_mV[c] = m;
    s.sum_mV[c] = 0;
    lo = m < lo ? m : lo;
    hi = m > hi ? m : hi;
  }
  s.summed = 0;
  s.haveMean = true;
  s.meanMin_mV = lo;
  s.meanMax_mV = hi;
}

// Cells above min + stopDelta (and not below minCell), highest first; with noAdjacent a
// neighbour of a chosen cell is skipped. Returns the number chosen.
uint16_t chooseCells(const Config& cfg, const BalanceState& s, const Readings& tm, uint32_t mask[kBalanceWords]) {
  const BalanceConfig& b = cfg.balance;
  const uint32_t floor_mV = static_cast<uint32_t>(tm.min_mV) + b.stopDelta_mV;
  auto candidate = [&](uint16_t c) {
    const uint16_t v = tm.cell_mV[c];
    return v > floor_mV && v >= b.minCell_mV && !s.boardHot[boardOf(b, c)];
  };
  uint16_t chosen = 0;
  if (!b.noAdjacent) {
    for (uint16_t c = 0; c < cfg.cellCount; ++c)
      if (candidate(c)) setBit(mask, c), ++chosen;
    return chosen;
  }
  for (;;) {
    int32_t best = -1;
    for (uint16_t c = 0; c < cfg.cellCount; ++c) {
      if (!candidate(c) || balanceBit(mask, c)) continue;
      if (c > 0 && balanceBit(mask, static_cast<uint16_t>(c - 1))) continue;
      if (c + 1 < cfg.cellCount && balanceBit(mask, static_cast<uint16_t>(c + 1))) continue;
      if (best < 0 || tm.cell_mV[c] > tm.cell_mV[best]) best = c;
    }
    if (best < 0) return chosen;
    setBit(mask, static_cast<uint16_t>(best));
    ++chosen;
  }
}

}  // namespace

void balanceRange(const Config& cfg, const BalanceState& s, const Telemetry& tm, uint16_t& min_mV, uint16_t& max_mV) {
  const bool averaging = cfg.balance.averageReadings > 1;
  min_mV = averaging ? s.meanMin_mV : tm.minCell_mV;
  max_mV = averaging ? s.meanMax_mV : tm.maxCell_mV;
}

namespace {

// The spread's hysteresis at a decision. At or below the stop delta no cell is above
// min + stopDelta (chooseCells' floor): stopping there too keeps the two in step.
// Stopping only below it left the policy active with nothing to choose at spread ==
// stopDelta, reported "balanced", and started again at the next millivolt, far below
// the start delta.
void spreadHysteresis(const BalanceConfig& b, BalanceState& s, const Readings& r) {
  const uint16_t spread = r.max_mV > r.min_mV ? static_cast<uint16_t>(r.max_mV - r.min_mV) : 0;
  if (spread > b.startDelta_mV) s.active = true;
  if (spread <= b.stopDelta_mV) s.active = false;
}

// A tick on which balancing is not allowed (not configured, or the core forbids it):
// what the general path below does then, without its passes over a mask it has just
// cleared (the usual tick of a pack that does not balance: some 30 instructions on a
// host). The mask and the output are cleared, the spread's hysteresis and the decision
// timer move as they would, the status is Disabled.
void balanceStopped(const BalanceConfig& b, BalanceState& s, const Readings& r, bool due, uint32_t now_ms,
                    uint32_t mask[kBalanceWords]) {
  clearMask(s.mask);
  clearMask(mask);
  spreadHysteresis(b, s, r);
  s.status = BalanceStatus::Disabled;
  if (due) s.lastDecision_ms = now_ms;
  s.decided = false;  // decide afresh once it may resume
}

}  // namespace

void balanceStep(const Config& cfg, BalanceState& s, const Telemetry& tm, bool permitted, bool charging, bool fresh,
                 uint32_t now_ms, uint32_t mask[kBalanceWords], uint8_t& armCount, const uint16_t* packRange) {
  const BalanceConfig& b = cfg.balance;
  restUpdate(s.rest, tm.packCurrent_mA, b.restCurrent_mA, now_ms);
  updateBoard(cfg, s, tm);

  // Decide at the configured period (once a first block mean exists when averaging);
  // hold the mask in between. Losing permission or a hot board stops balancing at once.
  const bool allowed = b.enabled && permitted;
  accumulate(cfg, s, tm, allowed, fresh);
  const bool averaging = b.averageReadings > 1;
  Readings r = averaging ? Readings{s.mean_mV, s.meanMin_mV, s.meanMax_mV}
                         : Readings{tm.cellVoltage_mV, tm.minCell_mV, tm.maxCell_mV};
  if (packRange) {  // the other boards' cells count for the spread and the floor
    r.min_mV = packRange[0] < r.min_mV ? packRange[0] : r.min_mV;
    r.max_mV = packRange[1] > r.max_mV ? packRange[1] : r.max_mV;
  }
  const bool due = (!averaging || s.haveMean) && (!s.decided || now_ms - s.lastDecision_ms >= b.period_ms);
  if (!allowed) return balanceStopped(b, s, r, due, now_ms, mask);
  if (s.boardPaused || due) {
    clearMask(s.mask);
    spreadHysteresis(b, s, r);
    if (!conditionHolds(b, s, charging, now_ms)) {
      s.status = BalanceStatus::NotAllowed;
    } else if (s.boardPaused) {
      s.status = BalanceStatus::BoardHot;
    } else if (!s.active) {
      s.status = BalanceStatus::Balanced;
    } else {
      bool anyHot = false;
      for (uint8_t k = 0; k < boards(b); ++k) anyHot = anyHot || s.boardHot[k];
      s.status = chooseCells(cfg, s, r, s.mask) > 0 ? BalanceStatus::Balancing
                 : anyHot                           ? BalanceStatus::BoardHot
                                                    : BalanceStatus::Balanced;
    }
    if (due) {
      s.decided = true;
      s.lastDecision_ms = now_ms;
    }
    if (s.boardPaused) s.decided = false;  // decide afresh once it may resume
  }

  // A board that turned hot stops its own cells at once (the others keep their decision).
  // The minimum holds every tick, not only at a decision: a held cell that now reads
  // below it stops at once. Both only clear bits: one pass per cell in the mask (none
  // while nothing balances).
  const bool severalBoards = boards(b) > 1;
  const uint8_t cellWords = static_cast<uint8_t>(cfg.cellCount >= kMaxCells ? kBalanceWords : (cfg.cellCount + 31u) / 32u);
  for (uint8_t w = 0; w < cellWords; ++w) {
    for (uint32_t left = s.mask[w]; left != 0; left &= left - 1) {
      const uint8_t bit = static_cast<uint8_t>(__builtin_ctz(left));
      const uint16_t c = static_cast<uint16_t>(w * 32u + bit);
      if (c >= cfg.cellCount) break;  // bits ascend; the later words hold higher cells still
      if ((severalBoards && s.boardHot[boardOf(b, c)]) || tm.cellVoltage_mV[c] < b.minCell_mV)
        s.mask[w] &= ~(1u << bit);
    }
  }

  // Re-arm the monitor's timer every half period while anything balances. The output
  // mask is every word of the state's, copied whole (a copy the compiler need not check
  // for overlap, then one pass over the state's words: 49 -> 14 instructions on a host).
  std::memcpy(mask, s.mask, sizeof s.mask);
  uint32_t anyBit = 0;
  for (uint8_t w = 0; w < kBalanceWords; ++w) anyBit |= s.mask[w];
  const bool any = anyBit != 0;
  const uint32_t half_ms = static_cast<uint32_t>(cfg.balanceTime_s) * 500u;
  if (any && now_ms - s.lastArm_ms >= half_ms) {
    ++armCount;
    s.lastArm_ms = now_ms;
  }
}

}  // namespace bms
