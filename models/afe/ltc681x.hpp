// An isoSPI daisy chain of LTC6811-1 (12 cells) or LTC6813-1 (18 cells) devices as the
// MCU's SPI port (through its isoSPI master) sees it, answering command frames byte for
// byte from each device's register groups (layout and command set: bms/afe/ltc681x_regs.h).
//
//   per device:  CFGRA (and CFGRB on the LTC6813), the result groups (cells, GPIOs and
//                the 2nd reference, status), a conversion in flight (results land at its
//                start + the data sheet's conversion time for its command and mode, + the
//                reference's power-up when REFON is 0), the discharge timer (DCTO), MUTE,
//                the core state (SLEEP / awake) and the isoSPI port state (IDLE / READY)
//   power-up:    every device in SLEEP with CFGRA/CFGRB at their defaults, results 0xFFFF
//   wake-up:     any transaction reaching a sleeping device wakes its core (ready after
//                wake_s) and stops there; one reaching an idle port wakes the port (ready
//                after ready_s) and stops there. The frame goes no further: a chain of N
//                devices needs N wake-up pulses, each after the previous device is ready
//                (what the data sheets' daisy-chain wake-up sequence does). Every transaction
//                a device hears restarts its watchdog and its port's idle timer.
//   watchdog:    no transaction for sleep_timeout_s: the core sleeps and CFGRA/CFGRB go back
//                to their defaults -- except the DCC bits and DCTO while the discharge timer
//                runs (DTEN pin high, DCTO != 0), which keep balancing until it expires
//   discharge:   DCC bits switch the cells' balancing switches unless the LTC6813 is MUTEd;
//                an ADCV / ADOW with DCP = 0 opens each cell's switch while the cell or a
//                neighbour converts (the cell reads without its I_bal·R drop; the switch
//                conducts for the rest of the time: balancingDuty); DCP = 1 leaves them;
//                a WRCFGA with DCTO != 0 (re)starts the timer, which clears every DCC bit
//                when it runs out; DCTO reads back the bucket of the time left
//   analog:      cell code = AdcChannel(cell_adc + this channel's drawn gain/offset + the
//                injected error)(V between its C pins), 100 uV LSB; an open C pin (setOpenWire)
//                holds its voltage on its filter capacitor in ADCV, and each ADOW's 100 uA
//                moves it by 100 uA · t_conv / sense_filter_F towards its upper (PUP=1) or
//                lower (PUP=0) neighbour -- why the data sheet runs ADOW at least twice;
//                GPIOk = VREF2 · R_ntc / (R_ntc +
//                pull-up) (open: VREF2, short: 0, pull-down on or no thermistor: 0); SC =
//                sum of cells / 20 (6811) or / 30 (6813); ITMP from the die temperature;
//                VA 5 V, VD 3 V, REF 3 V (nominal)
//   random:      per-channel gain/offset drawn once (cell_conversion.hpp, the same for
//                every part); conversion noise from its own
//                stream, per command in chain order then channel order; PEC bit flips from
//                a third stream
//   comm faults: a device beyond a broken link, or from a silent device on (it relays the
//                chain: a silent device silences everything beyond it), hears nothing and
//                leaves its read slots at 0xFF; a stuck device drives its slot and every
//                slot it relays to its stuck byte and takes no writes; a CRC error rate
//                flips one bit of the device's own slot. A frame with a bad command PEC
//                is ignored by every device; a write block with a bad PEC by its device.
//   link time:   (tx + rx bytes) · 8 / spi_clock_Hz. A write acts at the end of its frame,
//                a conversion starts there; a read answers from the state at its start.
//   outputs:     no FAULT line (the parts have none); balancing switches; thermistor bias
//                (VREF2 is up whenever the core is awake)
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <bms/afe/ltc681x_regs.h>

#include "models/afe/balance_pause.hpp"
#include "models/afe/cell_conversion.hpp"
#include "models/afe/monitor_part.hpp"
#include "models/sensors/adc.hpp"
#include "models/sensors/thermistor.hpp"

namespace packsim {

enum class Ltc681xPart { Ltc6811, Ltc6813 };

struct Ltc681xConfig {
  Ltc681xPart part = Ltc681xPart::Ltc6813;
  int devices = 1;
  int cells_per_device = 18;           // inputs C1..Cn in use (the last device may hold fewer)
  int thermistors_per_device = 2;      // NTCs on GPIO1..GPIOn
  AdcChannel cell_adc{1e-4, 0.0, 0.0, 0.0, 0, 65535};  // 100 uV LSB, 16 bit
  double channel_gain_sd = 0.0;        // per-channel gain error, drawn once from the seed
  double channel_offset_sd_V = 0.0;    // per-channel offset, drawn once from the seed
  double gpio_noise_V = 0.0;           // noise of a GPIO conversion
  Thermistor thermistor;               // NTC and its pull-up from VREF2 (only r25, beta, pull-up used)
  double spi_clock_Hz = 1e6;           // isoSPI 1 Mb/s
  bool dten_pin = true;                // DTEN tied high: the discharge timer is enabled
  // Timing: the data sheet's worst case for the host -- the shortest time-outs, the
  // longest wake-ups (electrical characteristics: tSLEEP 1.8 s min, tIDLE 4.3 ms min,
  // tWAKE 400 us max, tREADY 10 us max, tREFUP 4.4 ms max).
  double sleep_timeout_s = LTC681X_T_SLEEP_MIN_US * 1e-6;
  double idle_timeout_s = LTC681X_T_IDLE_MIN_US * 1e-6;
  double wake_s = LTC681X_T_WAKE_US * 1e-6;
  double ready_s = LTC681X_T_READY_US * 1e-6;
  double refup_s = LTC681X_T_REFUP_US * 1e-6;
  double sense_filter_F = 100e-9;      // the C pins' RC filter capacitor: an ADOW's 100 uA moves an
                                       // open pin by 100 uA · conversion time / this, per command
};

// The shared part of a MonitorConfig (devices, cells, thermistors, ADC errors, NTC, link
// speed) for an LTC681x chain; the part's own timing stays at its defaults.
Ltc681xConfig ltc681xConfigFrom(const MonitorConfig& m, Ltc681xPart part);

class Ltc681xChain final : public MonitorChain {
 public:
  Ltc681xChain(const Ltc681xConfig& cfg, int cellCount, uint64_t seed);

  int deviceCount() const override { return static_cast<int>(dev_.size()); }
  int cellsOf(int d) const override { return dev_[static_cast<size_t>(d)].cells; }
  DeviceAnalog& analog(int d) override { return dev_[static_cast<size_t>(d)].analog; }
  void setCommFault(int d, const MonitorDeviceFault& f) override { dev_[static_cast<size_t>(d)].comm = f; }
  void setBrokenLinkAbove(int d) override { brokenAbove_ = d; }

  void advance(double t) override;
  BusTransfer transfer(double t, const uint8_t* tx, size_t txLen, uint8_t* rx, size_t rxLen) override;

  bool faultLine() const override { return false; }
  bool balancing(int d, int cell) const override;
  double balancingDuty(int d, int cell, double t0, double t1) const override {
    return dev_[static_cast<size_t>(d)].pauses.conductingShare(cell, t0, t1);
  }
  std::string describe(const uint8_t* tx, size_t txLen, size_t rxLen) const override;
  bool thermistorBias(int d) const override;

  // An open sense wire on C pin `pin` (0 = C0 .. cells) of device d; closing it
  // reconnects the pin.
  void setOpenWire(int d, int pin, bool open);

  // Tests: the part's own channel errors, the registers as held, the core state.
  double channelGain(int cell) const { return errors_.gain(cell); }
  double channelOffset_V(int cell) const { return errors_.offset_V(cell); }
  uint8_t cfga(int d, int byte) const { return dev_[static_cast<size_t>(d)].cfga[static_cast<size_t>(byte)]; }
  uint8_t cfgb(int d, int byte) const { return dev_[static_cast<size_t>(d)].cfgb[static_cast<size_t>(byte)]; }
  uint16_t cellCode(int d, int cell) const { return dev_[static_cast<size_t>(d)].cell[static_cast<size_t>(cell)]; }
  bool asleep(int d) const { return dev_[static_cast<size_t>(d)].asleep; }
  int partCells() const { return partCells_; }

 private:
  enum class Conv { None, Cells, Gpios, Status };
  struct Device {
    int firstCell = 0, cells = 0;
    std::array<uint8_t, LTC681X_GROUP_BYTES> cfga{}, cfgb{};
    std::array<uint16_t, LTC681X_CELLS_MAX> cell{};
    std::array<uint16_t, LTC681X_GPIOS_MAX> gpio{};
    uint16_t ref = LTC681X_CLEARED, sc = LTC681X_CLEARED, itmp = LTC681X_CLEARED, va = LTC681X_CLEARED,
             vd = LTC681X_CLEARED;
    uint32_t ov = 0, uv = 0;  // flag bit per cell input
    bool thsd = false, muxfail = false;
    // conversion in flight: its results and which registers they land in
    Conv conv = Conv::None;
    double readyAt_s = 0.0;
    std::array<uint16_t, LTC681X_CELLS_MAX> pendCell{};
    std::array<uint16_t, LTC681X_GPIOS_MAX> pendGpio{};
    uint16_t pendRef = 0, pendSc = 0, pendItmp = 0, pendVa = 0, pendVd = 0;
    uint32_t pendMask = 0;  // cells / GPIOs (bit LTC681X_GPIOS_MAX: REF) / status items
    // core, port and timers
    bool asleep = true;
    double heard_s = 0.0, portReadyAt_s = 0.0, refUpAt_s = 0.0;
    bool dischargeTimer = false;
    double dischargeUntil_s = 0.0;
    bool muted = false;
    BalancePauses pauses;  // DCP = 0 conversions: discharge switches held open
    std::array<bool, LTC681X_CELLS_MAX + 1> open{};
    std::array<double, LTC681X_CELLS_MAX + 1> held{};  // open pin: the voltage its capacitor holds (NaN: not yet moved)
    DeviceAnalog analog;
    MonitorDeviceFault comm;
  };

  void settle(Device& dv, double t);
  void sleep(Device& dv);
  void expireDischarge(Device& dv);
  bool ready(const Device& dv, double t) const;
  void hear(Device& dv, double t);  // a transaction reaches it: wakes it up if needed
  void writeCfga(Device& dv, double t, const uint8_t* data);
  void writeCfgb(Device& dv, const uint8_t* data);
  void noteReadGroup(int d, uint16_t cc);
  void readGroup(const Device& dv, uint16_t cc, double t, uint8_t* out, bool& known) const;
  void convert(Device& dv, double t, uint16_t cc);
  void convertCells(Device& dv, uint8_t ch, bool openWire, bool pullUp, double conv_s, bool paused);
  void pauseDischarge(Device& dv, uint8_t ch, double start_s, double conv_s);
  double truePin(const Device& dv, int pin, bool paused = false) const;
  void convertGpios(Device& dv, uint8_t chg);
  void convertStatus(Device& dv, uint8_t chst);
  double pinVoltage(const Device& dv, int pin, bool paused = false) const;
  void clear(Device& dv, uint16_t cc);
  double linkTime_s(size_t bytes) const { return static_cast<double>(bytes) * 8.0 / cfg_.spi_clock_Hz; }
  bool is6813() const { return cfg_.part == Ltc681xPart::Ltc6813; }

  Ltc681xConfig cfg_;
  int partCells_, partGpios_;
  std::vector<Device> dev_;
  CellChannelErrors errors_;  // per channel, drawn once from the seed
  Rng noise_, commRng_;
  int brokenAbove_ = -1;
};

std::unique_ptr<MonitorChain> makeLtc681xChain(const Ltc681xConfig& cfg, int cellCount, uint64_t seed);

}  // namespace packsim
