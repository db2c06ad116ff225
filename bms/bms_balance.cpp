#include "bms_balance.hpp"

#include "bms_measure.hpp"

namespace bms {

void balanceReset(BalanceState& s) {
  s.active = false;
  s.boardPaused = false;
  restReset(s.rest);
  s.decided = false;
  s.lastDecision_ms = 0;
  s.lastArm_ms = 0;
  for (uint8_t w = 0; w < kBalanceWords; ++w) s.mask[w] = 0;
  s.status = BalanceStatus::Disabled;
}

namespace {

void clearMask(uint32_t mask[kBalanceWords]) {
  for (uint8_t w = 0; w < kBalanceWords; ++w) mask[w] = 0;
}

void setBit(uint32_t mask[kBalanceWords], uint16_t cell) { mask[cell / 32] |= 1u << (cell % 32); }

// Board temperature hysteresis; an unreadable board thermistor pauses balancing.
void updateBoard(const BalanceConfig& b, BalanceState& s, const Telemetry& tm) {
  int16_t hottest = INT16_MIN;
  bool invalid = false;
  for (uint8_t k = 0; k < b.boardThermCount; ++k) {
    const int16_t t = tm.temperature_dC[b.boardThermFirst + k];
    if (t == kTempInvalid_dC) invalid = true;
    else if (t > hottest) hottest = t;
  }
  if (b.boardThermCount == 0) {
    s.boardPaused = false;
  } else if (invalid || hottest > b.boardMax_dC) {
    s.boardPaused = true;
  } else if (hottest < b.boardResume_dC) {
    s.boardPaused = false;
  }
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

// Cells above min + stopDelta (and not below minCell), highest first; with noAdjacent a
// neighbour of a chosen cell is skipped. Returns the number chosen.
uint16_t chooseCells(const Config& cfg, const Telemetry& tm, uint32_t mask[kBalanceWords]) {
  const BalanceConfig& b = cfg.balance;
  const uint32_t floor_mV = static_cast<uint32_t>(tm.minCell_mV) + b.stopDelta_mV;
  auto candidate = [&](uint16_t c) {
    const uint16_t v = tm.cellVoltage_mV[c];
    return v > floor_mV && v >= b.minCell_mV;
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
      if (best < 0 || tm.cellVoltage_mV[c] > tm.cellVoltage_mV[best]) best = c;
    }
    if (best < 0) return chosen;
    setBit(mask, static_cast<uint16_t>(best));
    ++chosen;
  }
}

}  // namespace

void balanceStep(const Config& cfg, BalanceState& s, const Telemetry& tm, bool permitted, bool charging,
                 uint32_t now_ms, uint32_t mask[kBalanceWords], uint8_t& armCount) {
  const BalanceConfig& b = cfg.balance;
  restUpdate(s.rest, tm.packCurrent_mA, b.restCurrent_mA, now_ms);
  updateBoard(b, s, tm);

  // Decide at the configured period; hold the mask in between. Losing permission or a
  // hot board stops balancing at once.
  const bool allowed = b.enabled && permitted;
  const bool due = !s.decided || now_ms - s.lastDecision_ms >= b.period_ms;
  if (!allowed || s.boardPaused || due) {
    clearMask(s.mask);
    const uint16_t spread = tm.maxCell_mV > tm.minCell_mV ? static_cast<uint16_t>(tm.maxCell_mV - tm.minCell_mV) : 0;
    if (spread > b.startDelta_mV) s.active = true;
    if (spread < b.stopDelta_mV) s.active = false;
    if (!allowed) {
      s.status = BalanceStatus::Disabled;
    } else if (!conditionHolds(b, s, charging, now_ms)) {
      s.status = BalanceStatus::NotAllowed;
    } else if (s.boardPaused) {
      s.status = BalanceStatus::BoardHot;
    } else if (!s.active) {
      s.status = BalanceStatus::Balanced;
    } else {
      s.status = chooseCells(cfg, tm, s.mask) > 0 ? BalanceStatus::Balancing : BalanceStatus::Balanced;
    }
    if (due) {
      s.decided = true;
      s.lastDecision_ms = now_ms;
    }
    if (!allowed || s.boardPaused) s.decided = false;  // decide afresh once it may resume
  }

  // The minimum holds every tick, not only at a decision: a held cell that now reads
  // below it stops at once.
  for (uint16_t c = 0; c < cfg.cellCount && c < kMaxCells; ++c)
    if (tm.cellVoltage_mV[c] < b.minCell_mV) s.mask[c / 32] &= ~(1u << (c % 32));

  // Re-arm the monitor's timer every half period while anything balances.
  bool any = false;
  for (uint8_t w = 0; w < kBalanceWords; ++w) {
    mask[w] = s.mask[w];
    any = any || s.mask[w] != 0;
  }
  const uint32_t half_ms = static_cast<uint32_t>(cfg.balanceTime_s) * 500u;
  if (any && now_ms - s.lastArm_ms >= half_ms) {
    ++armCount;
    s.lastArm_ms = now_ms;
  }
}

}  // namespace bms
