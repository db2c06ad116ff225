// A minimal board for monitor-IC tests: the firmware contract's services over one
// MonitorChain and a simulated clock. Each bus transfer advances the clock by the
// time the chain says the transaction took; delay_us advances it by the delay. The
// chain is advanced to the clock before every transfer.
#pragma once
#include <bms/packsim_fw.h>

#include <cstdint>

#include "models/afe/monitor_part.hpp"

namespace packsim::test {

class ChainTestBoard {
 public:
  explicit ChainTestBoard(MonitorChain& chain) : chain_(chain) {
    api_.abi_version = PSFW_ABI_VERSION;
    api_.now_ms = [](psfw_board* b) { return static_cast<uint32_t>(self(b).t_s * 1e3); };
    api_.now_us = [](psfw_board* b) { return static_cast<uint32_t>(self(b).t_s * 1e6); };
    api_.delay_us = [](psfw_board* b, uint32_t us) { self(b).t_s += us * 1e-6; };
    api_.bus_transfer = [](psfw_board* b, uint8_t bus, const uint8_t* tx, uint16_t txLen, uint8_t* rx,
                           uint16_t rxLen) -> int32_t {
      ChainTestBoard& s = self(b);
      if (bus != 0) return PSFW_BUS_ERROR;
      s.chain_.advance(s.t_s);
      const BusTransfer r = s.chain_.transfer(s.t_s, tx, txLen, rx, rxLen);
      s.t_s += r.duration_s;
      ++s.transfers;
      return r.received < 0 ? PSFW_BUS_TIMEOUT : r.received;
    };
  }
  const psfw_board_api* api() const { return &api_; }
  psfw_board* board() { return reinterpret_cast<psfw_board*>(this); }
  // Lets time pass without bus traffic (the chain's timers run).
  void wait(double dt_s) {
    t_s += dt_s;
    chain_.advance(t_s);
  }

  double t_s = 0.0;
  int transfers = 0;

 private:
  static ChainTestBoard& self(psfw_board* b) { return *reinterpret_cast<ChainTestBoard*>(b); }
  MonitorChain& chain_;
  psfw_board_api api_{};
};

}  // namespace packsim::test
