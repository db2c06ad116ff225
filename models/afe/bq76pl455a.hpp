// A BQ76PL455A daisy chain as the MCU's UART sees it: up to 16 devices of up to 16
// cells each, answering command frames byte for byte from the register map in
// bms/afe/bq76pl455a_regs.h (frame format and CRC there).
//
//   per device:  registers (reset from an EEPROM image built from MonitorConfig),
//                address state (unaddressed after power-up / reset until the
//                auto-address broadcast sequence), held sample results and a pending
//                conversion, comparator debounce timers, balancing expiry
//   advance(t):  a conversion whose time has passed becomes the held result (STATUS
//                data-ready, ADC UV/OV checks against CELL_UV/CELL_OV latch FAULT_UV/OV);
//                comparators compare the true pin voltages with COMP_UV/COMP_OV and
//                the AUX inputs' noiseless code with AUXn_UV (below = NTC hot), each
//                latching after its MonitorConfig::secondary delay (the EEPROM's AUX
//                threshold is the exact code of secondary.ot_C: the comparator
//                trips exactly above ot_C); CBENBL clears when
//                the CBCONFIG balance time has run out
//   transfer:    command frames in (a frame with a wrong CRC is dropped and flagged in
//                FAULT_COM), response frames out: top device first for broadcasts; a
//                sample reply waits for its conversion (channels x oversamples x
//                conversion_s_per_channel); every byte takes 10 bits at MonitorConfig::baud
//   outputs:     FAULT line = any device's FAULT_SUM & FO_CTRL; CBENBL bits
//
// Faults are latched until the host writes 1 to their FAULT_SUM bit (or detail bit)
// and the condition is gone. Per-channel gain/offset errors are drawn once from the
// seed (cell_conversion.hpp, the same for every part); conversion noise and CRC
// corruption draw from two more seed streams in a fixed order, so the same seed and
// the same transactions give the same bytes.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <bms/afe/bq76pl455a_regs.h>
#include <bms/bms_crc.hpp>

#include "models/afe/debounce_timer.hpp"
#include "models/afe/balance_pause.hpp"
#include "models/afe/cell_conversion.hpp"
#include "models/afe/frame_crc_memo.hpp"
#include "models/afe/monitor_part.hpp"
#include "models/afe/reply_slots.hpp"
#include "models/sensors/adc.hpp"
#include "models/sensors/round_even.hpp"

namespace packsim {

class Bq76pl455aChain final : public MonitorChain {
 public:
  Bq76pl455aChain(const MonitorConfig& cfg, int cellCount, uint64_t seed);

  int deviceCount() const override { return cfg_.devices; }
  int cellsOf(int d) const override;
  DeviceAnalog& analog(int d) override {  // the caller fills it: the comparators look again
    Device& dv = dev_[static_cast<size_t>(d)];
    dv.compared = false;
    calm_ = false;
    return dv.analog;
  }
  void setCommFault(int d, const MonitorDeviceFault& f) override { dev_[static_cast<size_t>(d)].comm = f; }
  void setBrokenLinkAbove(int d) override { brokenAbove_ = d; }
  void advance(double t) override;
  BusTransfer transfer(double t, const uint8_t* tx, size_t txLen, uint8_t* rx, size_t rxLen) override;
  bool faultLine() const override;
  std::string faultCause() const override;
  bool balancing(int d, int cell) const override;
  uint32_t balancingMask(int d) const override;
  double balancingDuty(int d, int cell, double t0, double t1) const override {
    return dev_[static_cast<size_t>(d)].pauses.conductingShare(cell, t0, t1);
  }
  std::string describe(const uint8_t* tx, size_t txLen, size_t rxLen) const override;

  // The part's own channel errors drawn from the seed (tests use them).
  double channelGain(int cell) const { return errors_.gain(cell); }
  double channelOffset_V(int cell) const { return errors_.offset_V(cell); }

  // Seconds a device waits after the last byte it expected before the MCU gives up.
  static constexpr double kResponseTimeout_s = 1e-3;

 private:
  static constexpr int kResultSlots = 32;  // one per CHANNELS bit
  struct Device {
    std::array<uint8_t, 256> reg{};
    std::array<uint8_t, 256> eeprom{};
    bool addressed = false, autoAddress = false;
    DebounceTimer cov, cuv, hot[PL455_AUX_INPUTS];
    // AUX over-temperature threshold in (unrounded) code units: the EEPROM's exact
    // value until the host writes AUXn_UV, then the written code.
    double hotCode[PL455_AUX_INPUTS] = {}, eepromHotCode[PL455_AUX_INPUTS] = {};
    ThermistorCodeCache thermCode[PL455_AUX_INPUTS];  // each AUX input's noiseless code
    // The comparators' conditions (bit c: cell c over / under, bit k: AUX k hot) for the
    // pins and thresholds as they are; compared = false once either may have changed.
    uint16_t over = 0, under = 0, hotMask = 0;
    bool compared = false;
    // No condition present and every debounce timer at rest: a pass changes nothing
    // (DebounceTimer::held with a false condition), so none is made until one appears.
    bool quiet = false;
    double balanceUntil_s = 0.0;
    BalancePauses pauses;  // the host's, around its conversions
    double heard_s = 0.0;  // the last valid frame it heard (the link supervision's clock)
    // sample results: held (readable) and pending (converting until ready_s)
    std::array<uint16_t, kResultSlots> held{}, pending{};
    uint32_t heldChannels = 0, pendingChannels = 0;
    uint32_t channelsRead = 0;  // every slot a reply has carried so far (MonitorChain::noteRead on a new one)
    ReplySlots replySlots;      // the order a sample reply sends its channels in
    double ready_s = -1.0;  // < 0: no conversion pending
    DeviceAnalog analog;
    MonitorDeviceFault comm;
    // Its replies' CRC: the STATUS + FAULT_SUM reply answers the same bytes tick after tick.
    FrameCrcMemo<uint16_t, bms::crcCrc16> replyCrc;
  };
  // One device's response frame: header, data, CRC (a register read of up to 128 bytes).
  struct Reply {
    std::array<uint8_t, 1 + 128 + 2> bytes;
    size_t size = 0;
    void push(uint8_t b) { bytes[size++] = b; }
  };
  struct Frame {  // one command frame as received
    uint8_t req = 0, address = 0, size = 0;
    uint16_t reg = 0;
    const uint8_t* data = nullptr;
  };

  void powerUp(Device& dv);
  // The chain advances at every frame (several per tick), and on most calls a device has
  // nothing to do: the checks sit here, inline, the work out of line.
  // A conversion whose time has come becomes the held result (settleDue).
  void settle(Device& dv, double t) {
    if (!(dv.ready_s < 0.0 || t < dv.ready_s - 1e-12)) settleDue(dv);
  }
  void settleDue(Device& dv);
  void compare(Device& dv, int d);
  // The comparators, when enabled: no pass while their conditions are known (compared)
  // and none is present with the timers at rest (quiet): it would change nothing.
  void runComparators(Device& dv, int d, double t) {
    if ((dv.reg[PL455_REG_DEVCONFIG] & PL455_DEVCONFIG_COMP_ENA) != 0 && !(dv.compared && dv.quiet))
      runComparatorsPass(dv, d, t);
  }
  void runComparatorsPass(Device& dv, int d, double t);
  // runComparators(dv, ...) would make no pass.
  static bool comparatorsAtRest(const Device& dv) {
    return (dv.reg[PL455_REG_DEVCONFIG] & PL455_DEVCONFIG_COMP_ENA) == 0 || (dv.compared && dv.quiet);
  }
  void superviseLink(Device& dv, double t);
  // A time before which none of advance()'s timed work acts on dv: no result lands
  // (settle), the link supervision does not trip (superviseLink: its heard_s + timeout,
  // less a margin far above the rounding of t - heard_s) and the balancing timer does not
  // expire; +inf when none can come.
  static double dueOf(const Device& dv);
  // Every device's timed work at t, and dueAt_s_ the earliest dueOf() from then on.
  void settleAll(double t);
  // Every device's comparators at t, and calm_ whether all are at rest from then on.
  void runAllComparators(double t);
  // After a write to dv: its due time and comparators as they may now be (a sample
  // started, a timer or threshold written, a reset).
  void noteWritten(const Device& dv) {
    dueAt_s_ = std::min(dueAt_s_, dueOf(dv));
    calm_ = calm_ && comparatorsAtRest(dv);
  }
  // After a reply from dv: a reply writes no register the timed work or the comparators
  // read (only STATUS, FAULT_SUM), but may start a sample (its results due at ready_s).
  void noteReplied(const Device& dv) {
    if (!(dv.ready_s < 0.0)) dueAt_s_ = std::min(dueAt_s_, dv.ready_s - 1e-12);
  }
  bool hears(int d) const {  // on an intact link and not silent
    return !(brokenAbove_ >= 0 && d > brokenAbove_) && !dev_[static_cast<size_t>(d)].comm.silent;
  }
  bool acceptsWrites(int d) const { return hears(d) && dev_[static_cast<size_t>(d)].comm.stuck_byte < 0; }
  // Inline: asked for every device and frame (a call for a switch of a few instructions).
  bool addressedBy(const Frame& f, int d) const {
    const Device& dv = dev_[static_cast<size_t>(d)];
    switch (f.req & ~0x10u) {  // with or without response alike
      case PL455_REQ_SINGLE_R: return dv.addressed && dv.reg[PL455_REG_ADDR] == f.address;
      case PL455_REQ_GROUP_R: return dv.addressed && dv.reg[PL455_REG_GROUP_ID] == f.address;
      case PL455_REQ_BROADCAST_R: return true;
      default: return false;
    }
  }
  void write(Device& dv, int d, const Frame& f, double t, bool takesAddress);
  void clearWritten(Device& dv, uint8_t addr, uint8_t bits);
  // Two builds of one body (startSampleWith): the SSE4.1 one, its rounding one instruction
  // (round_even.hpp), where the CPU has it (nativeRounding), else the plain one.
  void startSample(Device& dv, int d, double t) {
    if (nativeRounding()) startSampleNative(dv, d, t);
    else startSampleWith<RoundHalfEven>(dv, d, t);
  }
  void startSampleNative(Device& dv, int d, double t);
  template <class Round>
  void startSampleWith(Device& dv, int d, double t);
  uint16_t faultSummary(const Device& dv) const;
  // One device's reply to f (data read or sample) into out (size 0: no reply); ready_s:
  // when it can start sending.
  void reply(Device& dv, int d, const Frame& f, double t, double& ready_s, Reply& out);
  void corrupt(const Device& dv, Reply& out);

  MonitorConfig cfg_;
  int cells_;
  int brokenAbove_ = -1;
  std::vector<Device> dev_;
  CellChannelErrors errors_;  // per channel, drawn once from the seed
  Rng noise_, comm_;
  // The chain advances at every transfer and tick (four times a tick or more), and on
  // most calls no device has anything to do: dueAt_s_ is at most the earliest dueOf()
  // of any device (lowered by every frame that acts on one, made exact by settleAll),
  // calm_ true only while every device's comparators are at rest. Before t reaches
  // dueAt_s_ and while calm_, advance() makes no pass over the devices.
  double dueAt_s_ = -std::numeric_limits<double>::infinity();
  bool calm_ = false;
};

// The CTO fault timer code of a link-supervision time (0 s: off), or -1 when the part has
// no such setting.
int pl455CommTimeoutCode(double timeout_s);

// The part's register-level chain (registered by core/parts/bq76pl455a_part.cpp).
std::unique_ptr<MonitorChain> makeBq76pl455aChain(const MonitorConfig& cfg, int cellCount, uint64_t seed);

}  // namespace packsim
