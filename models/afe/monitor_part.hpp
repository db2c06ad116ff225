// The part API every register-level monitor-IC model implements (one file per IC,
// models/afe/<part>.*; the registered parts: bms/afe/monitor_parts.def). A MonitorChain is what one MCU bus reaches: a
// stack of devices on a vertical SPI bus or a UART daisy chain, or one I2C device.
// It answers bus transactions byte for byte, in the part's own frame format and
// CRC, from a register map the firmware drivers share (bms/afe/<part>_regs.h).
//
//   each step:  analog(d) is filled with the truth at t (cells at the pins, thermistors,
//               die, shunt current), comm faults are set, advance(t) runs the device's
//               own comparators/protections, conversions and balancing timers; then
//               the firmware's transfers at t (and later, within the step) are answered.
//   outputs:    the FAULT / ALERT line, each cell's balancing switch, BQ76952 FETs.
//
// Comm faults act on the bytes: a silent device (or every device above a broken
// link) does not answer and does not receive writes; a stuck device drives every
// reply byte to 0x00 or 0xFF; a CRC error rate flips one bit of a reply with that
// probability. The FAULT line is its own wire and works without the link.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "models/afe/device_faults.hpp"
#include "models/afe/monitor_config.hpp"
#include "models/afe/register_misuse.hpp"

namespace packsim {

// Appends `item` to a list in words ("COV (...), OT1 (...)"; per device "device 1: ...;
// device 2: ..."): the parts' FAULT-line causes and the hardware's join of them.
inline void appendListed(std::string& list, const std::string& item, const char* separator = ", ") {
  if (item.empty()) return;
  if (!list.empty()) list += separator;
  list += item;
}

// What one device's pins see at t.
struct DeviceAnalog {
  std::vector<double> cell_V;           // its cells, bottom first (truth at the pins)
  // The same with every balancing switch open: what a conversion sees while the switch of
  // the cell is held open for it (no I_bal·R drop). Empty: as cell_V (no switch is on).
  std::vector<double> cell_unloaded_V;
  std::vector<double> cell_gain_error;  // injected per channel (added to the part's own)
  std::vector<double> cell_offset_V;    // injected per channel
  std::vector<double> therm_C;          // its thermistor inputs
  std::vector<ThermistorFault> therm_fault;
  double die_C = 25.0;
  double current_A = 0.0;               // through the shunt (BQ76952), positive discharges
  // The host opens the balancing switches around each conversion it starts
  // (bms.balancing.measure_paused): used by the parts that do not pause on their own.
  bool host_opens_balancing = false;

  // The cells a conversion sees: with the switches open (paused) or as they are.
  const std::vector<double>& cellsSeen(bool paused) const {
    return paused && cell_unloaded_V.size() == cell_V.size() ? cell_unloaded_V : cell_V;
  }

  // Sized for `cells` inputs and `thermistors` thermistor inputs: 0 V, no injected
  // error, 25 °C, no thermistor fault.
  void size(int cells, int thermistors) {
    const size_t n = static_cast<size_t>(std::max(cells, 0)), k = static_cast<size_t>(std::max(thermistors, 0));
    cell_V.assign(n, 0.0);
    cell_gain_error.assign(n, 0.0);
    cell_offset_V.assign(n, 0.0);
    therm_C.assign(k, 25.0);
    therm_fault.assign(k, ThermistorFault::None);
  }
};

struct BusTransfer {
  int received = -1;        // bytes received, -1 = timeout (nothing answered)
  double duration_s = 0.0;  // time the transaction held the bus
};

class MonitorChain {
 public:
  virtual ~MonitorChain() = default;

  virtual int deviceCount() const = 0;
  virtual int cellsOf(int d) const = 0;
  // Sized at construction; fill before advance(t). Ask again for every change: a part
  // keeps what it derived from the pins (its comparators' conditions) until then.
  virtual DeviceAnalog& analog(int d) = 0;
  virtual void setCommFault(int d, const MonitorDeviceFault& f) = 0;
  virtual void setBrokenLinkAbove(int d) = 0;  // -1: link intact

  // The devices' own protections, conversions in progress and timers advance to t.
  virtual void advance(double t) = 0;
  // One transaction started by the MCU at t: txLen bytes out, up to rxLen bytes in.
  virtual BusTransfer transfer(double t, const uint8_t* tx, size_t txLen, uint8_t* rx, size_t rxLen) = 0;

  // Pins and switches the rest of the hardware sees.
  virtual bool faultLine() const = 0;
  // What holds the FAULT line now, in the part's own words: its latched protections by
  // their data-sheet names ("" when the line is released, or for a part that cannot say).
  // Asked at the line's rising edge only.
  virtual std::string faultCause() const { return ""; }
  virtual bool balancing(int d, int cell) const = 0;  // cell index within device d
  // Device d's switches at once: bit c is balancing(d, c), for each of its cells (none
  // above). The hardware asks every tick for every cell; a part answers from its switch
  // register in one read instead of one call per cell.
  virtual uint32_t balancingMask(int d) const {
    uint32_t m = 0;
    for (int c = 0; c < cellsOf(d); ++c)
      if (balancing(d, c)) m |= 1u << c;
    return m;
  }
  // The share of [t0, t1) the balancing switch of device d's `cell`, held on, conducts:
  // below 1 where the part (or the host, DeviceAnalog::host_opens_balancing) opens it
  // for conversions. The plant scales the branch's current by it.
  virtual double balancingDuty(int /*d*/, int /*cell*/, double /*t0*/, double /*t1*/) const { return 1.0; }
  virtual bool dischargeFetOn() const { return true; }  // BQ76952 FETs; others: not in the path
  virtual bool chargeFetOn() const { return true; }
  // Whether the part drives FETs at all (else both calls above are always true): asked
  // once, so that the hardware need not ask those every tick.
  virtual bool hasFetDrivers() const { return false; }
  // Why that FET driver is off now, in the part's own words ("" when on, or a part without).
  virtual std::string fetOffCause(bool /*discharge*/) const { return ""; }
  // Whether device d's thermistor inputs are biased (their divider draws current from
  // the device's top cell: MonitorConfig::thermistor_bias_A); parts without a switch
  // for it bias them whenever they have thermistors.
  virtual bool thermistorBias(int d) const { return cellsOf(d) > 0; }

  // What a transaction the MCU starts is, by the part's own names ("read Cell 1
  // Voltage", "WRCFGA", "write CB_CTRL = 0x05 at address 2"): the bus trace's
  // decoding (output.bus_trace). Reads nothing of the device's state; every part
  // names its own (a test's fake chain may leave it empty).
  virtual std::string describe(const uint8_t*, size_t, size_t) const { return ""; }

  // The writes the part ignored so far (register_misuse.hpp), for the run's events.
  const RegisterMisuseLog& misuse() const { return misuse_; }

  // What the MCU read so far, per device (index d; shorter than deviceCount() when the
  // upper devices were never read): bit c of cells[d] once a read of cell c's result
  // reached device d (a read the device never heard -- silent, unaddressed, beyond a
  // broken link -- does not count), bit k of thermistors[d] for its thermistor input k.
  // The run's end names the cells and thermistors a firmware never read
  // (core/sim/read_coverage.hpp).
  struct ReadCoverage {
    std::vector<uint32_t> cells, thermistors;
  };
  const ReadCoverage& readCoverage() const { return read_; }

 protected:
  void noteRead(int d, uint32_t cells, uint32_t thermistors) {
    const size_t i = static_cast<size_t>(d);
    if (i >= read_.cells.size()) {
      read_.cells.resize(i + 1, 0u);
      read_.thermistors.resize(i + 1, 0u);
    }
    read_.cells[i] |= cells;
    read_.thermistors[i] |= thermistors;
  }

  RegisterMisuseLog misuse_;

 private:
  ReadCoverage read_;
};

// Bit i for each of the n two-byte result registers from `base` on (i = 0 .. n-1, n <= 31)
// that a read of `count` bytes from register `first` covers whole: the cells (or
// thermistor inputs) a register read delivers, for MonitorChain::noteRead.
inline uint32_t wordsCovered(size_t first, size_t count, size_t base, size_t n) {
  const size_t end = first + count;
  if (end < base + 2) return 0u;
  const size_t lo = first <= base ? 0 : (first - base + 1) / 2;
  const size_t hi = std::min((end - base) / 2, n);  // exclusive
  return lo >= hi ? 0u : ((1u << hi) - 1u) & ~((1u << lo) - 1u);
}

// Bit r for each register r below 64 that a read of `count` registers from `first` covers:
// a part's record of what was read, so that it calls noteRead only for a new register.
inline uint64_t registerSpan(size_t first, size_t count) {
  if (first >= 64 || count == 0) return 0u;
  return (count >= 64 ? ~uint64_t{0} : (uint64_t{1} << count) - 1u) << first;
}

// Each part's factory is declared in its own header (models/afe/<part>.hpp) and
// registered by its descriptor (core/parts/<part>_part.cpp, MonitorPart::make_chain).

}  // namespace packsim
