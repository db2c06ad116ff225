// A stack of monitor ICs as the MCU sees them: every tick the stack converts the
// plant's truth (cell voltages at the pins, thermistor temperatures, current) with
// per-channel gain/offset error, noise and quantisation into reply frames (see
// bms/bms_afe.hpp for the layouts), runs each device's own protection (secondary
// comparators or BQ76952 protections and FETs), and enforces the host-written
// balance mask and timer.
//
//   state per device: latched flags and debounce timers, balance mask + expiry,
//                     BQ76952 FET states, coulomb counter, held readings
//   inputs per tick:  MonitorTruth (truth + injected faults), host writes (Outputs)
//   outputs:          frames into bms::Inputs, FAULT line, FET states, balance bits
//
// Injected comm faults act on the frames: a silent device (or every device above a
// broken link) gives no reply, a stuck one replies only 0x00 or 0xFF, a CRC error
// rate flips one bit of a reply at that probability. Host writes do not reach a
// device that cannot answer. The FAULT line is its own wire: it works without the link.
#pragma once
#include <array>
#include <vector>

#include <bms/bms_hal.hpp>

#include "models/afe/device_faults.hpp"
#include "models/afe/monitor_config.hpp"
#include "models/sensors/adc.hpp"

namespace packsim {

// What the stack sees at one read-out (sized once, reused).
struct MonitorTruth {
  std::vector<double> cell_V;            // per series position
  std::vector<double> cell_gain_error;   // injected per channel (added to the part's)
  std::vector<double> cell_offset_V;
  std::vector<double> board_C;           // per device: the board it sits on (its die = this + die_rise_C)
  std::vector<double> therm_C;           // per AFE thermistor channel
  std::vector<ThermistorFault> therm_fault;
  std::vector<MonitorDeviceFault> comm;          // per device
  int broken_link_above = -1;            // >= 0: devices above this index are silent
  double current_A = 0.0;                // positive discharges
};

class MonitorStack {
 public:
  MonitorStack(const MonitorConfig& cfg, int cellCount, uint64_t seed);

  const MonitorConfig& config() const { return cfg_; }
  int cellCount() const { return cells_; }
  int cellsOf(int d) const;
  int thermistorChannels() const { return cfg_.devices * cfg_.thermistors_per_device; }
  MonitorTruth makeTruth() const;

  // Host register writes of the previous decision (clear latches, balance mask and
  // timer, FET requests); only devices with a working link receive them.
  void hostWrite(double t, const bms::Outputs& out, const MonitorTruth& truth);
  // Devices' own protections and timers advance to t with this truth.
  void update(double t, const MonitorTruth& truth);
  // Reply frames of every device into in.afe[]; unused slots get length 0.
  void read(double t, const MonitorTruth& truth, Rng& rng, bms::Inputs& in);

  // FAULT / ALERT line: any device's own protection latched.
  bool faultLine() const;
  // BQ76952 FETs (for the other classes both follow the host: true).
  bool dischargeAllowed() const;
  bool chargeAllowed() const;
  bool balancing(int cell, double t) const;
  bool deviceFault(int d) const;
  double chargeCounter_As(int d) const { return dev_[static_cast<size_t>(d)].cc_As; }

  // Device d's channel errors drawn from the seed (tests use them).
  double channelGain(int cell) const { return gain_[static_cast<size_t>(cell)]; }
  double channelOffset_V(int cell) const { return offset_[static_cast<size_t>(cell)]; }

 private:
  struct Timer {
    double since = -1.0;  // time the condition started, -1 = not present
    bool running(double t, bool cond, double delay);  // true once held for delay
  };
  struct Device {
    // secondary comparators (PL536A / PL455A)
    Timer cov, cuv, ot[bms::kMaxThermPerDevice];
    uint16_t covCells = 0, cuvCells = 0;
    bool covLatched = false, cuvLatched = false, otLatched[bms::kMaxThermPerDevice] = {false, false, false};
    // balancing
    uint16_t balanceMask = 0;
    double balanceUntil_s = 0.0;
    uint32_t lastMaskWritten = 0;
    uint8_t lastArmCount = 0;  // host's re-arm counter as last received
    // BQ76952
    Timer bqCov, bqCuv, bqOcc, bqOcd1, bqOtc, bqOtd, bqOtf, bqUtc, bqUtd;
    uint8_t bqAlertA = 0, bqStatusA = 0, bqStatusB = 0;
    double bqCurrentTrip_s = -1.0;
    bool fetEnabled = false, hostChg = false, hostDsg = false, hostPdsg = false;
    double cc_As = 0.0, ccLast_s = 0.0;
    // held readings (BQ76952 measurement loop)
    double heldAt_s = -1.0;
    std::array<double, bms::kMaxCellsPerDevice> heldCell_V{};
    std::array<double, bms::kMaxThermPerDevice> heldTherm_C{};
    std::array<ThermistorFault, bms::kMaxThermPerDevice> heldThermFault{};
    double heldCurrent_A = 0.0;
  };

  bool replies(int d, const MonitorTruth& truth) const;  // answers at all (not silent, link intact)
  bool linkUp(int d, const MonitorTruth& truth) const;   // answers and receives host writes
  void updateSecondary(Device& dv, int d, double t, const MonitorTruth& truth);
  void updateBq952(Device& dv, int d, double t, const MonitorTruth& truth);
  void buildFrame(const Device& dv, int d, double t, const MonitorTruth& truth, bool dsgOk, bool chgOk, Rng& rng,
                  bms::AfeFrame& f) const;
  double pinVoltage(int cell, double v, const MonitorTruth& truth) const;

  MonitorConfig cfg_;
  int cells_;
  std::vector<Device> dev_;
  std::vector<double> gain_, offset_;
};

}  // namespace packsim
