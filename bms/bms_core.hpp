// The BMS control core: one pure step per tick over fixed-size structs.
//
//   step(cfg, state, in, out):
//     1. measure: the held monitor readings (the read-out task's, bms_measure) and
//        the MCU's own codes -> mV / mA / deci-degC; min/max quantities. In a pack
//        of several boards (bms_pack.hpp) the pack host merges the members'
//        statuses in; a member takes the pack current and balancing permission from
//        the pack host and acts on nothing else (it has no relay)
//     2. estimate: SOC by coulomb counting, re-anchored to OCV after rest (and the
//        capacity between rested anchors), and by an EKF per series group; the
//        configured one is reported
//     3. protections: debounce every rule of the table, latch fatal ones
//     4. state machine: one function per state decides the next state
//        init -> standby -> precharge -> normal | charge;  any fatal fault -> error
//     5. actuators: relay, precharge and FET commands follow the state and the table;
//        the relay never closes while a fatal fault is present or latched
//     6. balancing and charger: the balancing policy (bms_balance) picks the cells; the
//        charger is enabled (with its current request) only in Charge with no fault
//        acting on the charge side (relay or charge FET)
//
// No heap, no exceptions, no I/O, no globals: the same sources run on the
// microcontroller and in the simulator. Commands take effect from the next tick.
#pragma once
#include <cstdint>

#include "bms_balance.hpp"
#include "bms_config.hpp"
#include "bms_ekf.hpp"
#include "bms_hal.hpp"
#include "bms_measure.hpp"
#include "bms_names.hpp"
#include "bms_pack.hpp"
#include "bms_protect.hpp"
#include "bms_soc.hpp"

namespace bms {

struct PrechargeState {
  PrechargePhase phase;
  uint32_t phaseSince_ms;
  uint8_t attempts;   // attempts started (1 = the first)
  bool failed;        // every attempt timed out; cleared by an operator reset
};

struct CoreState {
  State state;
  bool firstTick;
  ProtectionState protection;
  int32_t quantity[kQuantityCount];
  AcquisitionState acq;
  SocState soc;
  EkfState ekf;
  PrechargeState precharge;
  BalanceState balance;
  PackState pack;          // the other boards' hosts, in a pack of several (bms_pack.hpp)
  bool balancePermitted;   // this tick's balancing permission (shared with the members)
  bool chargeComplete;  // a cell reached chargeFullCell_mV on this charger connection
  // Commands of the previous tick (what the hardware is doing now).
  bool relayCmd;
  bool prechargeCmd;
  bool dischargeFetCmd;
  bool chargeFetCmd;
  uint32_t relayOpenSince_ms;
};

void init(CoreState& s);
void step(const Config& cfg, CoreState& s, const Inputs& in, Outputs& out);

}  // namespace bms
