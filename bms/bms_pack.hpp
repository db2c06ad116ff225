// A pack of several monitor boards, each with its own host MCU running this core, on one
// CAN bus (reference system D: boards of 6 stacked devices; longer stacks failed). Board
// 0's host is the pack host: it has the current sense, the relay and the E-switches,
// and judges the whole pack; the other boards' hosts (members) read and balance their
// own cells.
//
//   pack host  every control tick broadcasts PackShare (pack current, the lowest and
//              highest cell the boards' balancing compares, balancing permission,
//              charging) and merges the members' last
//              BoardStatus into its protection quantities and telemetry: pack min / max
//              cell and temperature, the worst comm count (a member whose status stops
//              arriving counts one bad read per read-out period missed), plausibility,
//              thermistor faults, monitor faults, pack voltage
//   member     after each read-out sends its BoardStatus; takes the pack current and the
//              balancing permission from the last PackShare (no share yet: no
//              balancing); its own protection table does not act (it has no relay)
//
// CAN frames (11-bit ids, little-endian):
//   0x080 share    [current mA i32][balancing min mV u16][balancing max mV u16]
//   0x081 flags    [bit0 balancing permitted, bit1 charging][state u8]
//   0x100 + b      [min mV u16][max mV u16][max temp dC i16][min temp dC i16]   (board b)
//   0x180 + b      [worst bad u8][invalid therms u8][bit0 monitor fault][cell-sum error mV u8]
//                  [sum of cells 10 mV u16][max die dC i16]
//   0x200 + b      [balancing min mV u16][balancing max mV u16]: what board b's balancing
//                  compares (its block means when it averages)
#pragma once
#include <cstdint>

#include "bms_config.hpp"
#include "bms_hal.hpp"
#include "packsim_fw.h"

namespace bms {

constexpr uint32_t kCanShare = 0x080, kCanShareFlags = 0x081, kCanStatus = 0x100, kCanHealth = 0x180,
                   kCanBalance = 0x200;
constexpr uint8_t kPackCan = 0;  // the CAN bus the boards share

struct BoardStatus {
  bool seen;            // a status arrived since power-up
  uint32_t rx_ms;       // when the last one arrived
  uint16_t min_mV, max_mV;
  int16_t maxTemp_dC, minTemp_dC;  // INT16_MIN / INT16_MAX: no valid reading
  uint8_t worstBad, invalidTherm;
  bool monitorFault;
  uint8_t cellSumError_mV;
  uint32_t sum_mV;
  int16_t maxDie_dC;
  bool balanceSeen;
  uint16_t balanceMin_mV, balanceMax_mV;
};

struct PackShare {
  bool seen;
  uint32_t rx_ms;
  int32_t current_mA;
  uint16_t min_mV, max_mV;
  bool balancePermitted, charging;
};

struct PackState {
  BoardStatus board[kMaxBoards];  // pack host: what each member last said
  PackShare share;                // member: what the pack host last said
  uint32_t lastStatus_ms;         // member: when it last sent its status
};

void packReset(PackState& p);
inline bool packHost(const Config& c) { return c.pack.board == 0; }
inline bool packMember(const Config& c) { return c.pack.boards > 1 && c.pack.board > 0; }

// Frames waiting on the bus into the state (either role); call before step().
void packReceive(const Config& c, PackState& p, uint32_t now_ms, psfw_board* b, const psfw_board_api* api);
// Pack host: the members' statuses into this tick's quantities and telemetry (after measure).
void packMerge(const Config& c, const PackState& p, uint32_t now_ms, Telemetry& tm, int32_t quantity[kQuantityCount]);
// Member: the pack current from the share into telemetry and quantities.
void packApplyShare(const PackState& p, Telemetry& tm, int32_t quantity[kQuantityCount]);
// The other boards' balancing range {min, max}: a member's from the share, the pack
// host's from the members' frames; false when there is none yet.
bool packBalanceRange(const Config& c, const PackState& p, uint16_t range[2]);
// After step(): the pack host's share, a member's status after each read-out (readOut:
// one ran since the last tick, whether its devices answered or not).
// balanceRange: this board's own {min, max} as its balancing compares them.
void packSend(const Config& c, PackState& p, const Outputs& out, bool balancePermitted, bool charging, bool readOut,
              const int32_t quantity[kQuantityCount], const uint16_t balanceRange[2], psfw_board* b,
              const psfw_board_api* api);

}  // namespace bms
