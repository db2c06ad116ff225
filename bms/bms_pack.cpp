#include "bms_pack.hpp"

#include <climits>

namespace bms {

namespace {

void put16(uint8_t* p, uint32_t v) {
  p[0] = static_cast<uint8_t>(v & 0xFFu);
  p[1] = static_cast<uint8_t>((v >> 8) & 0xFFu);
}
void put32(uint8_t* p, uint32_t v) {
  put16(p, v & 0xFFFFu);
  put16(p + 2, v >> 16);
}
uint16_t get16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t get32(const uint8_t* p) { return get16(p) | (static_cast<uint32_t>(get16(p + 2)) << 16); }
uint8_t sat8(int32_t v) { return static_cast<uint8_t>(v < 0 ? 0 : v > 255 ? 255 : v); }
uint16_t sat16(int32_t v) { return static_cast<uint16_t>(v < 0 ? 0 : v > 65535 ? 65535 : v); }
int16_t clamp16(int32_t v) { return static_cast<int16_t>(v < INT16_MIN ? INT16_MIN : v > INT16_MAX ? INT16_MAX : v); }

int32_t q(const int32_t quantity[kQuantityCount], Quantity which) { return quantity[static_cast<uint8_t>(which)]; }
void setQ(int32_t quantity[kQuantityCount], Quantity which, int32_t v) { quantity[static_cast<uint8_t>(which)] = v; }

void onFrame(const Config& c, PackState& p, uint32_t id, const uint8_t* d, int32_t len, uint32_t now_ms) {
  if (packMember(c)) {
    if (id == kCanShare && len == 8) {
      p.share.current_mA = static_cast<int32_t>(get32(d));
      p.share.min_mV = get16(d + 4);
      p.share.max_mV = get16(d + 6);
      p.share.seen = true;
      p.share.rx_ms = now_ms;
    } else if (id == kCanShareFlags && len == 2) {
      p.share.balancePermitted = (d[0] & 1u) != 0;
      p.share.charging = (d[0] & 2u) != 0;
    }
    return;
  }
  const uint32_t base = id >= kCanBalance ? kCanBalance : id >= kCanHealth ? kCanHealth : kCanStatus;
  const uint32_t b = id - base;
  if (id < kCanStatus || b == 0 || b >= c.pack.boards || b >= kMaxBoards) return;
  BoardStatus& s = p.board[b];
  if (base == kCanBalance) {
    if (len != 4) return;
    s.balanceMin_mV = get16(d);
    s.balanceMax_mV = get16(d + 2);
    s.balanceSeen = true;
    return;
  }
  if (len != 8) return;
  if (base == kCanStatus) {
    s.min_mV = get16(d);
    s.max_mV = get16(d + 2);
    s.maxTemp_dC = static_cast<int16_t>(get16(d + 4));
    s.minTemp_dC = static_cast<int16_t>(get16(d + 6));
    s.seen = true;
    s.rx_ms = now_ms;
  } else {
    s.worstBad = d[0];
    s.invalidTherm = d[1];
    s.monitorFault = (d[2] & 1u) != 0;
    s.cellSumError_mV = d[3];
    s.sum_mV = static_cast<uint32_t>(get16(d + 4)) * 10u;
    s.maxDie_dC = static_cast<int16_t>(get16(d + 6));
  }
}

}  // namespace

void packReset(PackState& p) {
  for (uint8_t b = 0; b < kMaxBoards; ++b) {
    BoardStatus& s = p.board[b];
    s.seen = false;
    s.rx_ms = 0;
    s.min_mV = s.max_mV = 0;
    s.maxTemp_dC = INT16_MIN;
    s.minTemp_dC = INT16_MAX;
    s.worstBad = s.invalidTherm = s.cellSumError_mV = 0;
    s.monitorFault = false;
    s.sum_mV = 0;
    s.maxDie_dC = INT16_MIN;
    s.balanceSeen = false;
    s.balanceMin_mV = s.balanceMax_mV = 0;
  }
  p.share = PackShare{false, 0, 0, 0, 0, false, false};
  p.lastStatus_ms = 0;
}

void packReceive(const Config& c, PackState& p, uint32_t now_ms, psfw_board* b, const psfw_board_api* api) {
  if (c.pack.boards <= 1) return;
  uint32_t id = 0;
  uint8_t data[8];
  for (int32_t len; (len = api->can_receive(b, kPackCan, &id, data)) >= 0;) onFrame(c, p, id, data, len, now_ms);
}

void packMerge(const Config& c, const PackState& p, uint32_t now_ms, Telemetry& tm, int32_t quantity[kQuantityCount]) {
  const uint32_t period = c.readout.period_ms > 0 ? c.readout.period_ms : 1;
  int32_t maxCell = q(quantity, Quantity::MaxCell_mV), minCell = q(quantity, Quantity::MinCell_mV);
  int32_t maxT = tm.maxTemp_dC, minT = tm.minTemp_dC, die = q(quantity, Quantity::MaxDie_dC);
  int32_t worst = q(quantity, Quantity::CommBadFrames), sumErr = q(quantity, Quantity::CellSumError_mV);
  int32_t invalid = q(quantity, Quantity::InvalidThermistors);
  bool monitorFault = q(quantity, Quantity::MonitorFaultLine) != 0;
  uint32_t pack_mV = tm.packVoltage_mV;
  for (uint8_t b = 1; b < c.pack.boards && b < kMaxBoards; ++b) {
    const BoardStatus& s = p.board[b];
    // A member's status comes after each of its read-outs: each read-out period without
    // one counts as one bad read of that board.
    const uint32_t since = now_ms - (s.seen ? s.rx_ms : 0u);
    const int32_t missed = static_cast<int32_t>(since / period);
    if (missed > worst) worst = missed;
    if (!s.seen) continue;  // no cell values yet: comm loss covers the board
    if (s.max_mV > maxCell) maxCell = s.max_mV;
    if (s.min_mV < minCell) minCell = s.min_mV;
    if (s.maxTemp_dC > maxT) maxT = s.maxTemp_dC;
    if (s.minTemp_dC < minT) minT = s.minTemp_dC;
    if (s.maxDie_dC > die) die = s.maxDie_dC;
    if (s.worstBad > worst) worst = s.worstBad;
    if (s.cellSumError_mV > sumErr) sumErr = s.cellSumError_mV;
    invalid += s.invalidTherm;
    monitorFault = monitorFault || s.monitorFault;
    pack_mV += s.sum_mV;
  }
  setQ(quantity, Quantity::MaxCell_mV, maxCell);
  setQ(quantity, Quantity::MinCell_mV, minCell);
  setQ(quantity, Quantity::MaxTemp_dC, maxT);
  setQ(quantity, Quantity::MinTemp_dC, minT);
  const bool charging = q(quantity, Quantity::MaxTempCharging_dC) != INT32_MIN;
  setQ(quantity, Quantity::MaxTempCharging_dC, charging ? maxT : INT32_MIN);
  setQ(quantity, Quantity::MinTempCharging_dC, charging ? minT : INT32_MAX);
  setQ(quantity, Quantity::MaxDie_dC, die);
  setQ(quantity, Quantity::CommBadFrames, worst);
  setQ(quantity, Quantity::CellSumError_mV, sumErr);
  setQ(quantity, Quantity::InvalidThermistors, invalid);
  setQ(quantity, Quantity::MonitorFaultLine, monitorFault ? 1 : 0);
  if (maxCell > 0 && minCell != INT32_MAX) setQ(quantity, Quantity::CellSpread_mV, maxCell - minCell);
  tm.maxCell_mV = sat16(maxCell);
  tm.minCell_mV = minCell == INT32_MAX ? 0 : sat16(minCell);
  tm.maxTemp_dC = clamp16(maxT);
  tm.minTemp_dC = clamp16(minT);
  tm.maxDie_dC = clamp16(die);
  tm.packVoltage_mV = pack_mV;
  tm.monitorFault = monitorFault;
}

void packApplyShare(const PackState& p, Telemetry& tm, int32_t quantity[kQuantityCount]) {
  const int32_t i = p.share.seen ? p.share.current_mA : 0;
  tm.packCurrent_mA = i;
  setQ(quantity, Quantity::DischargeCurrent_mA, i);
  setQ(quantity, Quantity::ChargeCurrent_mA, -i);
  setQ(quantity, Quantity::CurrentCodeAtRail, 0);  // the current sense is the pack host's
}

bool packBalanceRange(const Config& c, const PackState& p, uint16_t range[2]) {
  if (packMember(c)) {
    range[0] = p.share.min_mV;
    range[1] = p.share.max_mV;
    return p.share.seen && p.share.min_mV > 0;
  }
  bool any = false;
  for (uint8_t b = 1; b < c.pack.boards && b < kMaxBoards; ++b) {
    const BoardStatus& s = p.board[b];
    if (!s.balanceSeen || s.balanceMin_mV == 0) continue;
    range[0] = !any || s.balanceMin_mV < range[0] ? s.balanceMin_mV : range[0];
    range[1] = !any || s.balanceMax_mV > range[1] ? s.balanceMax_mV : range[1];
    any = true;
  }
  return any;
}

void packSend(const Config& c, PackState& p, const Outputs& out, bool balancePermitted, bool charging, bool readOut,
              const int32_t quantity[kQuantityCount], const uint16_t balanceRange[2], psfw_board* b,
              const psfw_board_api* api) {
  if (c.pack.boards <= 1) return;
  uint8_t d[8];
  const Telemetry& tm = out.telemetry;
  if (packHost(c)) {
    uint16_t range[2] = {balanceRange[0], balanceRange[1]};
    uint16_t others[2];
    if (packBalanceRange(c, p, others)) {
      if (range[0] == 0 || others[0] < range[0]) range[0] = others[0];
      if (others[1] > range[1]) range[1] = others[1];
    }
    put32(d, static_cast<uint32_t>(tm.packCurrent_mA));
    put16(d + 4, range[0]);
    put16(d + 6, range[1]);
    api->can_send(b, kPackCan, kCanShare, d, 8);
    d[0] = static_cast<uint8_t>((balancePermitted ? 1u : 0u) | (charging ? 2u : 0u));
    d[1] = static_cast<uint8_t>(out.state);
    api->can_send(b, kPackCan, kCanShareFlags, d, 2);
    return;
  }
  if (!readOut) return;
  const int32_t maxT = q(quantity, Quantity::MaxTemp_dC), minT = q(quantity, Quantity::MinTemp_dC);
  put16(d, sat16(q(quantity, Quantity::MinCell_mV)));
  put16(d + 2, sat16(q(quantity, Quantity::MaxCell_mV)));
  put16(d + 4, static_cast<uint16_t>(clamp16(maxT)));
  put16(d + 6, static_cast<uint16_t>(clamp16(minT)));
  api->can_send(b, kPackCan, kCanStatus + c.pack.board, d, 8);
  d[0] = sat8(q(quantity, Quantity::CommBadFrames));
  d[1] = sat8(q(quantity, Quantity::InvalidThermistors));
  d[2] = q(quantity, Quantity::MonitorFaultLine) != 0 ? 1u : 0u;
  d[3] = sat8(q(quantity, Quantity::CellSumError_mV));
  put16(d + 4, sat16(static_cast<int32_t>(tm.packVoltage_mV / 10u)));
  put16(d + 6, static_cast<uint16_t>(clamp16(q(quantity, Quantity::MaxDie_dC))));
  api->can_send(b, kPackCan, kCanHealth + c.pack.board, d, 8);
  put16(d, balanceRange[0]);
  put16(d + 2, balanceRange[1]);
  api->can_send(b, kPackCan, kCanBalance + c.pack.board, d, 4);
  p.lastStatus_ms = api->now_ms(b);
}

}  // namespace bms
