// BQ76PL536A stack on a vertical SPI bus, answering the MCU's frames byte for byte
// from each device's register file (layout: bms/afe/bq76pl536a_regs.h).
//
//   per device:  register file 0x00..0x4F, address (0 after reset), shadow-write key,
//                conversion in progress (results land at start + channels · conversion
//                time; DRDY clear until then), secondary COV/CUV/OT comparators with
//                debounce timers run from the CONFIG_* registers, latches in
//                FAULT_STATUS / ALERT_STATUS / COV_FAULT / CUV_FAULT, balance switches
//                (CB_CTRL) switched off by the device when CB_TIME expires
//   power-up:    every device as after RESET: address 0, POR and AR set, CONFIG_* from
//                MonitorConfig::secondary (the EEPROM as programmed)
//   analog:      cell code = AdcChannel(cell_adc + this channel's drawn gain/offset +
//                the injected error)(V at the pins); GPAI = Σ cells + module noise, in
//                6 cell LSBs; TEMPERATUREx = Thermistor code (0 without the IO_CONTROL
//                bias; open = full scale, short = 0). The comparators see the true pin
//                voltages and thermistor temperatures (they are not the ADC).
//   random:      per-channel gain/offset drawn once (cell_conversion.hpp, the same
//                for every part); conversion noise from its own stream in
//                the fixed order GPAI, VCELL1..n, TS1, TS2 per conversion; CRC bit flips
//                from a third stream.
//   link time:   (tx + rx bytes) · 8 / MonitorConfig::baud (the SPI clock, Hz). A write
//                acts at the end of its frame; a read answers from the state at its start.
//   FAULT line:  any device's COV/CUV (FAULT_STATUS) or OT1/OT2 (ALERT_STATUS) latch;
//                the housekeeping bits (POR, AR, CRC) show in the registers only.
#pragma once
#include <array>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <bms/afe/bq76pl536a_regs.h>
#include <bms/bms_crc.hpp>

#include "models/afe/debounce_timer.hpp"
#include "models/afe/balance_pause.hpp"
#include "models/afe/cell_conversion.hpp"
#include "models/afe/frame_crc_memo.hpp"
#include "models/afe/monitor_part.hpp"
#include "models/sensors/adc.hpp"
#include "models/sensors/round_even.hpp"

namespace packsim {

class Bq76pl536aChain final : public MonitorChain {
 public:
  Bq76pl536aChain(const MonitorConfig& cfg, int cellCount, uint64_t seed);

  int deviceCount() const override { return static_cast<int>(dev_.size()); }
  int cellsOf(int d) const override { return dev_[static_cast<size_t>(d)].cells; }
  DeviceAnalog& analog(int d) override {  // the caller fills it: the comparators look again
    Device& dv = dev_[static_cast<size_t>(d)];
    if (!dv.blind) {  // (all off: they see nothing whatever the inputs, nothing to look at)
      dv.compared = false;
      calm_ = false;
    }
    return dv.analog;
  }
  void setCommFault(int d, const MonitorDeviceFault& f) override { dev_[static_cast<size_t>(d)].comm = f; }
  void setBrokenLinkAbove(int d) override {
    brokenAbove_ = d;
    reach_ = reach();
  }

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
  bool thermistorBias(int d) const override;  // IO_CONTROL TS1 / TS2

  // The part's own drawn channel errors (series cell index), for tests.
  double channelGain(int cell) const { return errors_.gain(cell); }
  double channelOffset_V(int cell) const { return errors_.offset_V(cell); }
  // A register as the device holds it (tests; the firmware reads through transfer()).
  uint8_t peek(int d, uint8_t reg) const {
    const Device& dv = dev_[static_cast<size_t>(d)];
    return reg == BQ536_DEVICE_STATUS ? status(dv) : dv.reg[reg];
  }

 private:
  struct ComparatorSettings {
    bool covOn = false, cuvOn = false;
    double cov_V = 0.0, cuv_V = 0.0;  // bq536_cov_mV / bq536_cuv_mV · 1e-3
    uint8_t otOn = 0;                 // bit k: input k's CONFIG_OT nibble set
    double ot_C[BQ536_TEMPS_MAX] = {};  // bq536_ot_C of each nibble
  };
  struct Device {
    int firstCell = 0, cells = 0;
    std::array<uint8_t, BQ536_REGISTER_COUNT> reg{};
    bool shadowOpen = false;
    uint64_t registersRead = 0;  // bit r: register r (< 64) read so far holding a conversion (MonitorChain::noteRead on a new one)
    // Bit r: result register r holds a conversion of its input (a cell ADC_CONTROL's
    // CELL_SEL took in, a thermistor converted with its divider biased); pending: those the
    // conversion in flight adds. A read of another one (a cell CELL_SEL leaves out) reads
    // no cell: counted as read, it hid cells the firmware never saw (monitor_unread).
    uint64_t convertedRegs = 0, pendingRegs = 0;
    uint8_t lastLatchWrite[2] = {0, 0};  // host's last value to ALERT_STATUS, FAULT_STATUS
    DebounceTimer cov, cuv, ot[BQ536_TEMPS_MAX];
    bool converting = false;
    bool resultsValid = false;
    double readyAt_s = 0.0;
    // The result registers (GPAI .. TEMPERATURE2) as the conversion in flight leaves them:
    // its channels' codes, the others as they were when it started (nothing but a
    // conversion writes them), so that it lands as one copy.
    std::array<uint8_t, BQ536_RESULTS_LEN> pending{};  // indexed by register (0x00 unused)
    double balanceUntil_s = 0.0;
    BalancePauses pauses;  // the host's, around its conversions
    DeviceAnalog analog;
    MonitorDeviceFault comm;
    // Each input's noiseless code for its last temperature (an exp): an input whose
    // temperature did not move since the last conversion (an unused one at 25 °C, a
    // slow node) needs none.
    ThermistorCodeCache thermCode[BQ536_TEMPS_MAX];
    // Its replies' CRC: a flags read (7 bytes) answers the same bytes tick after tick.
    FrameCrcMemo<uint8_t, bms::crcCrc8> replyCrc;
    // What the comparators see (cells over / under, thermistors hot) for the present
    // inputs and thresholds; the chain advances many times per tick (at every frame),
    // the inputs change only when filled or a threshold is written.
    bool compared = false;
    uint8_t over = 0, under = 0, hot = 0;
    // Every comparator disabled by its register (readSettings): over, under and hot
    // are 0 for any inputs, so new inputs need no compare (the plain ADC's stack: its
    // secondary off). Kept where those registers change: reset, a protected write.
    bool blind = false;
    // The comparators' settings decoded from CONFIG_COV / CONFIG_CUV / CONFIG_OT, kept with
    // blind (readSettings): compare() runs at every tick, the registers seldom change.
    ComparatorSettings settings;
    // No condition present and every debounce timer at rest: a pass changes nothing
    // (DebounceTimer::held with a false condition), so none is made until one appears.
    bool quiet = false;
  };

  uint8_t addressOf(const Device& dv) const { return dv.reg[BQ536_ADDRESS_CONTROL] & BQ536_ADDR_MASK; }
  bool assigned(const Device& dv) const { return (dv.reg[BQ536_ADDRESS_CONTROL] & BQ536_ADDR_ASSIGNED) != 0; }
  // How many devices a frame reaches on its way up: devices 0 .. n-1, bottom first (it
  // stops above an unaddressed device and at a broken link). Kept in reach_ (a loop over
  // the devices at every frame otherwise), worked out again wherever an address or the
  // broken link changes: setBrokenLinkAbove, an ADDRESS_CONTROL write, reset.
  int reach() const;
  void reset(Device& dv);
  // A conversion whose results are due lands, an expired balancing timer switches off.
  // The chain settles and runs its comparators at every frame (several per tick), and on
  // most calls neither has anything to do: the checks sit here, inline, the work out of
  // line (settleDue, runComparatorsPass).
  void settle(Device& dv, double t) {
    const bool landing = dv.converting && t >= dv.readyAt_s - 1e-12;
    const bool expiring = dv.reg[BQ536_CB_CTRL] != 0 && t >= dv.balanceUntil_s - 1e-9;
    if (landing || expiring) settleDue(dv, t);
  }
  void settleDue(Device& dv, double t);
  // The earliest t at which settle(dv, t) acts: t >= dueOf(dv) is `landing || expiring`
  // above (the same comparisons), +inf when neither can come.
  static double dueOf(const Device& dv) {
    constexpr double kNever = std::numeric_limits<double>::infinity();
    const double landing = dv.converting ? dv.readyAt_s - 1e-12 : kNever;
    const double expiring = dv.reg[BQ536_CB_CTRL] != 0 ? dv.balanceUntil_s - 1e-9 : kNever;
    return std::min(landing, expiring);
  }
  // Every device settled to t, and dueAt_s_ their earliest due time from then on.
  void settleAll(double t);
  // Every device's comparators run at t, and calm_ whether all are at rest from then on.
  void runAllComparators(double t);
  void compare(Device& dv);  // the comparators' view of the present inputs
  // Device::settings and blind from the registers (at reset and after a protected write).
  static void readSettings(Device& dv);
  // No pass while the conditions are known (compared) and none is present with the timers
  // at rest (quiet): it would change nothing.
  void runComparators(Device& dv, double t) {
    if (!(dv.compared && dv.quiet)) runComparatorsPass(dv, t);
  }
  void runComparatorsPass(Device& dv, double t);
  // DEVICE_STATUS, composed from the device's state when it is read (the register file's
  // byte 0x00 is not kept up to date: nothing else reads it).
  uint8_t status(const Device& dv) const;
  void write(Device& dv, double t, uint8_t reg, uint8_t value);
  void clearLatches(Device& dv, uint8_t reg, uint8_t falling);
  // ADC_CONVERT: every selected channel converted, its codes pending until the results
  // land. Two builds of one body (startConversionWith): the SSE4.1 one, its rounding one
  // instruction (round_even.hpp), where the CPU has it (nativeRounding), else the plain one.
  void startConversion(Device& dv, double t) {
    if (nativeRounding()) startConversionNative(dv, t);
    else startConversionWith<RoundHalfEven>(dv, t);
  }
  void startConversionNative(Device& dv, double t);
  template <class Round>
  void startConversionWith(Device& dv, double t);
  // A reply frame's CRC. The results read (request and GPAI .. TEMPERATURE2, every tick,
  // its bytes new each time) through the CRC unrolled for its length, as the firmware
  // checks it (some 30 instructions less than crcCrc8's loop and tail); others through
  // the device's memo (a flags reply repeats).
  static uint8_t replyCrc(Device& dv, const uint8_t* frame, size_t n) {
    constexpr size_t kResultsFrame = BQ536_READ_REQUEST_LEN + BQ536_RESULTS_LEN;
    return n == kResultsFrame ? bms::crcCrc8Fixed<kResultsFrame>(frame) : dv.replyCrc.of(frame, n);
  }
  double linkTime_s(size_t bytes) const { return static_cast<double>(bytes) * 8.0 / cfg_.baud; }

  MonitorConfig cfg_;
  std::vector<Device> dev_;
  CellChannelErrors errors_;  // per channel, drawn once from the seed
  Rng noise_, commRng_;
  int brokenAbove_ = -1;
  int reach_ = 0;
  std::array<uint8_t, 8> eeprom_{};  // registers 0x40..0x47 as programmed
  FrameCrcMemo<uint8_t, bms::crcCrc8> writeCrc_;  // the host's writes: its ADC_CONVERT every tick
  // The chain is advanced and settled at every frame (four or more times a tick), and on
  // most of them no device has anything to do: dueAt_s_ is at most the earliest dueOf()
  // of any device (lowered by every write, made exact by settleAll), calm_ true only
  // while every device's comparators are known quiet (compared && quiet). Before t
  // reaches dueAt_s_ no settle acts, and while calm_ no comparator pass would: both
  // loops are skipped (a device loop, its tests and calls per frame).
  double dueAt_s_ = -std::numeric_limits<double>::infinity();
  bool calm_ = false;
};

// The part's register-level chain (registered by core/parts/bq76pl536a_part.cpp).
std::unique_ptr<MonitorChain> makeBq76pl536aChain(const MonitorConfig& cfg, int cellCount, uint64_t seed);

}  // namespace packsim
