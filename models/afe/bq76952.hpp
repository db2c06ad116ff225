// BQ76952 monitor and protector as its I2C bus sees it: one device answering
// transactions byte for byte from the register map in bms/afe/bq76952_regs.h
// (direct commands, subcommands through 0x3E/0x3F with the buffer at 0x40, data
// memory written in CONFIG_UPDATE mode), with the optional per-byte CRC-8.
//
//   measurement loop:  every measurement_period_s (0: at every advance) the ADC
//                      converts the pins: cells (part + drawn + injected gain/offset
//                      errors, noise, 1 mV), stack (10 mV), TS1..TS3 through the
//                      thermistor divider (0.1 K), die, CC2 current; FULLSCAN and
//                      ADSCAN set in Alarm Status. Registers hold the last loop.
//                      The loop opens a cell's balancing switch while it converts the
//                      cell or a neighbour (the top cell's also for the stack slot):
//                      cells read without their I_bal·R drop, and a switch held on
//                      conducts for the rest of the loop (balancingDuty).
//   protections:       an alert bit at
//                      once, the status bit after its delay; recovery by hysteresis
//                      (voltage, temperature) or time with the current gone; the
//                      thresholds, delays and enables come from data memory, which
//                      starts from MonitorConfig::bq and which the host may rewrite.
//   FETs:              off in FET test mode (until FET_ENABLE or Mfg Status Init
//                      FET_EN); then CHG / DSG on unless a protection in CHG/DSG FET
//                      Protections A/B or a host off-subcommand blocks them.
//   alarm / ALERT:     Alarm Status latches (SSA, SSBC, FULLSCAN...) until the host
//                      writes 1 to the bit and the condition is gone; the ALERT line
//                      is (Alarm Status & Alarm Enable) != 0.
//   balancing:         CB_ACTIVE_CELLS starts host-controlled balancing; it ends when
//                      the host writes 0, on RESET or CONFIG_UPDATE, or on the device
//                      once Cell Balance Interval (data memory, default 20 s) has passed
//                      since the last CB_ACTIVE_CELLS write.
//                      Autonomous balancing (Balancing Configuration CB_CHG / CB_RLX):
//                      every Cell Balance Interval, while charging or at rest, with the
//                      cell and die temperatures in their limits and no host balancing,
//                      the device balances the highest cells above Min Cell V that sit
//                      Min Delta above the lowest (kept until Stop Delta), at most Max
//                      Cells at once and never two neighbours.
//   coulomb counter:   one conversion per 250 ms (DASTATUS6, RESET_PASSQ).
// Signs: DeviceAnalog::current_A is positive in discharge; the part's CC2 and
// accumulated charge are positive in charge, as on the real device.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <bms/afe/bq76952_regs.h>

#include "models/afe/debounce_timer.hpp"
#include "models/afe/cell_conversion.hpp"
#include "models/afe/monitor_part.hpp"
#include "models/sensors/adc.hpp"

namespace packsim {

class Bq76952Chain : public MonitorChain {
 public:
  Bq76952Chain(const MonitorConfig& cfg, int cellCount, uint64_t seed);

  int deviceCount() const override { return 1; }
  int cellsOf(int d) const override { return d == 0 ? cells_ : 0; }
  DeviceAnalog& analog(int d) override;
  void setCommFault(int d, const MonitorDeviceFault& f) override;
  void setBrokenLinkAbove(int) override {}  // one device per bus: no link sits below it

  void advance(double t) override;
  BusTransfer transfer(double t, const uint8_t* tx, size_t txLen, uint8_t* rx, size_t rxLen) override;

  std::string describe(const uint8_t* tx, size_t txLen, size_t rxLen) const override;
  bool faultLine() const override;
  std::string faultCause() const override;
  // The latched protections among the masked bits of Safety Status A, B, C, by name.
  std::string latchedProtections(uint8_t maskA, uint8_t maskB, uint8_t maskC) const;
  bool balancing(int d, int cell) const override;
  double balancingDuty(int d, int cell, double t0, double t1) const override;
  bool dischargeFetOn() const override;
  bool chargeFetOn() const override;
  bool hasFetDrivers() const override { return true; }
  std::string fetOffCause(bool discharge) const override;

  // Inspection for tests (not part of the bus).
  double channelGain(int cell) const { return errors_.gain(cell); }
  double channelOffset_V(int cell) const { return errors_.offset_V(cell); }
  bool configUpdateMode() const { return cfgUpdate_; }
  uint8_t dataMemory(uint16_t address) const;

  // Transaction time for txLen bytes out and rxLen in at the link clock.
  double transferTime_s(size_t txLen, size_t rxLen) const;

 private:
  // Protection settings decoded from data memory (what the device acts on).
  struct Settings {
    uint8_t enabledA = 0, enabledB = 0, enabledC = 0, chgFetA = 0, chgFetB = 0, dsgFetA = 0, dsgFetB = 0, dsgFetC = 0;
    double cov_V = 0, cov_delay_s = 0, cov_recovery_V = 0, cuv_V = 0, cuv_delay_s = 0, cuv_recovery_V = 0;
    double occ_mV = 0, occ_delay_s = 0, ocd1_mV = 0, ocd1_delay_s = 0, scd_mV = 0;
    double ocd3_A = 0, ocd3_delay_s = 0;  // discharge current (A) read by the coulomb counter
    double current_recovery_s = 0, scd_recovery_s = 0;
    double otc_C = 0, otc_delay_s = 0, otc_recovery_C = 0, otd_C = 0, otd_delay_s = 0, otd_recovery_C = 0;
    double otf_C = 0, otf_delay_s = 0, otf_recovery_C = 0, utc_C = 0, utc_delay_s = 0, utc_recovery_C = 0;
    double utd_C = 0, utd_delay_s = 0, utd_recovery_C = 0;
    double userA_A = 0.001;
    double cb_interval_s = 20.0;
    // autonomous balancing: [0] charging, [1] relax
    uint8_t cbConfig = 0;
    double cbMinCell_C = -20, cbMaxCell_C = 60, cbMaxInt_C = 70;
    int cbMaxCells = 1;
    double cbMinCell_mV[2] = {3900, 3900}, cbStartDelta_mV[2] = {40, 40}, cbStopDelta_mV[2] = {20, 20};
    double chgThreshold_A = 0.05, dsgThreshold_A = 0.1;
  };

  bool replies() const;  // not silent, link intact
  bool receives() const { return replies() && fault_.stuck_byte < 0; }
  void powerOn(double t);
  void initDataMemory();
  void decodeSettings();
  void putDm(uint16_t address, uint8_t v) { dm_[address - BQ952_DM_FIRST] = v; }
  uint16_t dm16(uint16_t address) const;
  int8_t dmI8(uint16_t address) const { return static_cast<int8_t>(dataMemory(address)); }

  void measure(double t);
  void balanceAutonomously(double t);
  void protect(double t);
  uint8_t fetStatus() const;
  uint16_t alarmRaw() const;
  void buildImage(std::array<uint8_t, BQ952_DIRECT_SPACE>& regs) const;

  void writeRegister(double t, uint8_t reg, uint8_t value);
  void subcommandAddressed(double t);  // 0x3F written: run or prepare the subcommand
  void commitTransfer(double t);        // 0x61 written: checksum over the buffer, apply
  void setResponse(const uint8_t* data, int len);

  MonitorConfig cfg_;
  int cells_;
  DeviceAnalog analog_;
  std::vector<double> stackCells_V_;   // what the stack slot sees (only the top cell paused)
  MonitorDeviceFault fault_;
  CellChannelErrors errors_;           // per channel, drawn once from the seed
  Rng noise_;                          // ADC noise, drawn in loop order
  Rng comm_;                           // reply corruption

  // device state
  std::array<uint8_t, BQ952_DM_LAST - BQ952_DM_FIRST + 1> dm_{};
  Settings s_;
  bool cfgUpdate_ = false, fetEnabled_ = false, hostChgOff_ = false, hostDsgOff_ = false, por_ = true;
  uint16_t alarmStatus_ = 0, alarmEnable_ = BQ952_AL_ENABLE_DEFAULT;
  uint8_t alertA_ = 0, alertB_ = 0, alertC_ = 0, statusA_ = 0, statusB_ = 0, statusC_ = 0;
  DebounceTimer cov_, cuv_, occ_, ocd1_, ocd3_, otc_, otd_, otf_, utc_, utd_;
  double currentTrip_s = -1.0;
  // measurement loop: pins held at the last conversion, and the results
  double heldAt_s = -1.0;
  std::array<double, BQ952_MAX_CELLS> heldPin_V{};
  std::array<double, BQ952_MAX_TS> heldTs_C{};
  double heldCurrent_A = 0.0;
  std::array<int16_t, BQ952_MAX_CELLS> cell_mV{};
  uint16_t stack_userV = 0, pack_userV = 0, ld_userV = 0, intTemp_dK = 2982;
  std::array<uint16_t, BQ952_MAX_TS> ts_dK{};
  int16_t cc2_userA = 0;
  // coulomb counter (charge positive in discharge, as the analog input)
  double cc_As = 0.0, ccLast_s = 0.0, ccSince_s = 0.0;
  // host balancing
  uint16_t balanceMask_ = 0;  // host-controlled
  uint16_t autoMask_ = 0;     // chosen by the device
  double autoEval_s = -1.0;
  double balanceArmed_s = 0.0, balanceStarted_s = 0.0;
  double now_s = 0.0;
  // subcommand interface
  double subReady_s = 0.0;
  uint8_t subLo_ = 0, subHi_ = 0, checksum_ = 0, length_ = 0;
  std::array<uint8_t, BQ952_TRANSFER_BUFFER_LEN> buffer_{};
};

// The part's register-level chain (registered by core/parts/bq76952_part.cpp).
std::unique_ptr<MonitorChain> makeBq76952Chain(const MonitorConfig& cfg, int cellCount, uint64_t seed);

}  // namespace packsim
