#include "models/afe/ltc681x.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <bms/afe/ltc681x_pec.hpp>

#include "models/afe/reply_corruption.hpp"

namespace packsim {

namespace {

constexpr double kLsb_V = LTC681X_LSB_UV * 1e-6;
constexpr double kVref2_V = LTC681X_VREF2_MV * 1e-3;
constexpr double kVa_V = 5.0;  // VREG, nominal
constexpr double kVd_V = 3.0;  // VREGD, nominal
constexpr uint32_t kRefBit = 1u << LTC681X_GPIOS_MAX;

uint16_t code16(double v_V, double lsb_V) {
  return static_cast<uint16_t>(std::clamp(std::nearbyint(v_V / lsb_V), 0.0, 65535.0));
}

void put16(uint8_t* p, uint16_t v) {  // result registers: low byte first
  p[0] = static_cast<uint8_t>(v & 0xFF);
  p[1] = static_cast<uint8_t>(v >> 8);
}

// A command's data-sheet name; conversions with their mode fields (MD, DCP, PUP, CH).
std::string commandName(uint16_t cc) {
  switch (cc) {
    case LTC681X_WRCFGA: return "WRCFGA";
    case LTC681X_RDCFGA: return "RDCFGA";
    case LTC681X_WRCFGB: return "WRCFGB";
    case LTC681X_RDCFGB: return "RDCFGB";
    case LTC681X_RDCVA: return "RDCVA";
    case LTC681X_RDCVB: return "RDCVB";
    case LTC681X_RDCVC: return "RDCVC";
    case LTC681X_RDCVD: return "RDCVD";
    case LTC681X_RDCVE: return "RDCVE";
    case LTC681X_RDCVF: return "RDCVF";
    case LTC681X_RDAUXA: return "RDAUXA";
    case LTC681X_RDAUXB: return "RDAUXB";
    case LTC681X_RDAUXC: return "RDAUXC";
    case LTC681X_RDAUXD: return "RDAUXD";
    case LTC681X_RDSTATA: return "RDSTATA";
    case LTC681X_RDSTATB: return "RDSTATB";
    case LTC681X_MUTE: return "MUTE";
    case LTC681X_UNMUTE: return "UNMUTE";
    case LTC681X_CLRCELL: return "CLRCELL";
    case LTC681X_CLRAUX: return "CLRAUX";
    case LTC681X_CLRSTAT: return "CLRSTAT";
    default: break;
  }
  const unsigned md = (cc >> LTC681X_MD_SHIFT) & 3u, ch = cc & LTC681X_CH_MASK;
  const uint16_t fields = static_cast<uint16_t>(cc & ~(3u << LTC681X_MD_SHIFT));
  const std::string mode = " MD=" + std::to_string(md);
  const std::string dcp = " DCP=" + std::to_string((cc & LTC681X_DCP_BIT) ? 1 : 0);
  if ((fields & ~(LTC681X_DCP_BIT | LTC681X_CH_MASK)) == LTC681X_ADCV_BASE)
    return "ADCV" + mode + dcp + " CH=" + std::to_string(ch);
  if ((fields & ~(LTC681X_PUP_BIT | LTC681X_DCP_BIT | LTC681X_CH_MASK)) == LTC681X_ADOW_BASE)
    return "ADOW" + mode + " PUP=" + std::to_string((cc & LTC681X_PUP_BIT) ? 1 : 0) + dcp + " CH=" + std::to_string(ch);
  if ((fields & ~LTC681X_CH_MASK) == LTC681X_ADAX_BASE) return "ADAX" + mode + " CHG=" + std::to_string(ch);
  if ((fields & ~LTC681X_CH_MASK) == LTC681X_ADSTAT_BASE) return "ADSTAT" + mode + " CHST=" + std::to_string(ch);
  return "command " + hexByte(cc, 3);
}

uint16_t vuvOf(const std::array<uint8_t, 6>& a) { return static_cast<uint16_t>(a[1] | ((a[2] & 0x0F) << 8)); }
uint16_t vovOf(const std::array<uint8_t, 6>& a) { return static_cast<uint16_t>((a[2] >> 4) | (a[3] << 4)); }

}  // namespace

Ltc681xConfig ltc681xConfigFrom(const MonitorConfig& m, Ltc681xPart part) {
  Ltc681xConfig c;
  c.part = part;
  c.devices = m.devices;
  c.cells_per_device = m.cells_per_device;
  c.thermistors_per_device = m.thermistors_per_device;
  c.cell_adc.gain_error = m.cell_adc.gain_error;
  c.cell_adc.offset = m.cell_adc.offset;
  c.cell_adc.noise_rms = m.cell_adc.noise_rms;
  c.channel_gain_sd = m.channel_gain_sd;
  c.channel_offset_sd_V = m.channel_offset_sd_V;
  c.thermistor = m.thermistor;
  c.spi_clock_Hz = m.baud;
  return c;
}

Ltc681xChain::Ltc681xChain(const Ltc681xConfig& cfg, int cellCount, uint64_t seed)
    : cfg_(cfg),
      partCells_(cfg.part == Ltc681xPart::Ltc6813 ? static_cast<int>(LTC6813_CELLS) : static_cast<int>(LTC6811_CELLS)),
      partGpios_(cfg.part == Ltc681xPart::Ltc6813 ? static_cast<int>(LTC6813_GPIOS) : static_cast<int>(LTC6811_GPIOS)),
      errors_(cellCount, cfg.channel_gain_sd, cfg.channel_offset_sd_V, seed),
      noise_(deriveSeed(seed, 0x681A)),
      commRng_(deriveSeed(seed, 0x681C)) {
  const std::string name = is6813() ? "ltc6813" : "ltc6811";
  if (cfg.cells_per_device < 1 || cfg.cells_per_device > partCells_)
    throw std::invalid_argument(name + ": cells_per_device " + std::to_string(cfg.cells_per_device) + " outside 1.." +
                                std::to_string(partCells_));
  if (cfg.thermistors_per_device < 0 || cfg.thermistors_per_device > partGpios_)
    throw std::invalid_argument(name + ": thermistors_per_device " + std::to_string(cfg.thermistors_per_device) +
                                " outside 0.." + std::to_string(partGpios_));
  if (cfg.devices < 1) throw std::invalid_argument(name + ": devices must be >= 1");
  if (!(cfg.spi_clock_Hz > 0.0)) throw std::invalid_argument(name + ": spi_clock_Hz must be > 0");
  dev_.resize(static_cast<size_t>(cfg.devices));
  for (size_t d = 0; d < dev_.size(); ++d) {
    Device& dv = dev_[d];
    dv.firstCell = static_cast<int>(d) * cfg.cells_per_device;
    dv.cells = std::max(0, std::min(cfg.cells_per_device, cellCount - dv.firstCell));
    dv.analog.size(dv.cells, cfg.thermistors_per_device);
    dv.cell.fill(LTC681X_CLEARED);
    dv.gpio.fill(LTC681X_CLEARED);
    sleep(dv);  // power-up: the core sleeps with its registers at their defaults
    dv.cfga[4] = dv.cfga[5] = 0;
    dv.cfgb[0] = LTC6813_CFGRB0_DEFAULT;
    dv.cfgb[1] = 0;
  }
}

// --- core state ---------------------------------------------------------------

void Ltc681xChain::sleep(Device& dv) {
  // Watchdog: CFGRA/CFGRB back to their defaults; the DCC bits and DCTO stay while the
  // discharge timer runs.
  const uint8_t keepA4 = dv.dischargeTimer ? dv.cfga[4] : 0;
  const uint8_t keepA5 = dv.dischargeTimer ? dv.cfga[5] : 0;
  const uint8_t keepB0 = dv.dischargeTimer ? static_cast<uint8_t>(dv.cfgb[0] & 0xF0) : 0;
  const uint8_t keepB1 = dv.dischargeTimer ? static_cast<uint8_t>(dv.cfgb[1] & 0x07) : 0;
  dv.cfga = {LTC681X_CFGR0_DEFAULT, 0, 0, 0, keepA4, keepA5};
  dv.cfgb = {static_cast<uint8_t>(LTC6813_CFGRB0_DEFAULT | keepB0), keepB1, 0, 0, 0, 0};
  dv.muted = false;
  dv.conv = Conv::None;
  dv.asleep = true;
}

void Ltc681xChain::expireDischarge(Device& dv) {
  dv.dischargeTimer = false;
  dv.cfga[4] = 0;
  dv.cfga[5] = 0;  // DCC12..9 and DCTO: "disabled or timed out"
  dv.cfgb[0] = static_cast<uint8_t>(dv.cfgb[0] & 0x0F);
  dv.cfgb[1] = static_cast<uint8_t>(dv.cfgb[1] & ~0x07);
}

void Ltc681xChain::settle(Device& dv, double t) {
  if (dv.conv != Conv::None && t >= dv.readyAt_s - 1e-12) {
    for (int i = 0; i < static_cast<int>(LTC681X_CELLS_MAX); ++i)
      if (dv.conv == Conv::Cells && (dv.pendMask >> i) & 1u) {
        const uint16_t c = dv.pendCell[static_cast<size_t>(i)];
        dv.cell[static_cast<size_t>(i)] = c;
        // Every converted cell against the thresholds (UV: (VUV+1)·16, OV: VOV·16 codes).
        const uint32_t bit = 1u << i;
        dv.ov = c > vovOf(dv.cfga) * 16u ? (dv.ov | bit) : (dv.ov & ~bit);
        dv.uv = c < (vuvOf(dv.cfga) + 1u) * 16u ? (dv.uv | bit) : (dv.uv & ~bit);
      }
    if (dv.conv == Conv::Gpios) {
      for (int k = 0; k < static_cast<int>(LTC681X_GPIOS_MAX); ++k)
        if ((dv.pendMask >> k) & 1u) dv.gpio[static_cast<size_t>(k)] = dv.pendGpio[static_cast<size_t>(k)];
      if (dv.pendMask & kRefBit) dv.ref = dv.pendRef;
    }
    if (dv.conv == Conv::Status) {
      if (dv.pendMask & 1u) dv.sc = dv.pendSc;
      if (dv.pendMask & 2u) dv.itmp = dv.pendItmp;
      if (dv.pendMask & 4u) dv.va = dv.pendVa;
      if (dv.pendMask & 8u) dv.vd = dv.pendVd;
    }
    dv.conv = Conv::None;
  }
  const double sleepAt = dv.heard_s + cfg_.sleep_timeout_s;
  if (dv.dischargeTimer && dv.dischargeUntil_s <= std::min(t, sleepAt)) expireDischarge(dv);
  if (!dv.asleep && t >= sleepAt) sleep(dv);
  if (dv.dischargeTimer && t >= dv.dischargeUntil_s) expireDischarge(dv);
}

void Ltc681xChain::advance(double t) {
  for (Device& dv : dev_) settle(dv, t);
}

bool Ltc681xChain::ready(const Device& dv, double t) const {
  return !dv.asleep && t >= dv.portReadyAt_s - 1e-12 && t < dv.heard_s + cfg_.idle_timeout_s;
}

void Ltc681xChain::hear(Device& dv, double t) {
  if (dv.asleep) {
    dv.asleep = false;  // SLEEP -> STANDBY: the regulator starts, the port with it
    dv.portReadyAt_s = t + cfg_.wake_s;
    dv.refUpAt_s = std::numeric_limits<double>::infinity();
  } else if (t >= dv.heard_s + cfg_.idle_timeout_s) {
    dv.portReadyAt_s = t + cfg_.ready_s;  // isoSPI IDLE -> READY
  }
  dv.heard_s = t;
}

// --- registers ----------------------------------------------------------------

void Ltc681xChain::writeCfga(Device& dv, double t, const uint8_t* data) {
  const bool refWasOn = (dv.cfga[0] & LTC681X_CFGR0_REFON) != 0;
  for (size_t i = 0; i < LTC681X_GROUP_BYTES; ++i) dv.cfga[i] = data[i];
  dv.cfga[0] = static_cast<uint8_t>(dv.cfga[0] & ~LTC681X_CFGR0_DTEN);  // read only
  if ((dv.cfga[0] & LTC681X_CFGR0_REFON) && !refWasOn) dv.refUpAt_s = t + cfg_.refup_s;
  const uint8_t dcto = static_cast<uint8_t>(dv.cfga[5] >> LTC681X_DCTO_SHIFT);
  dv.dischargeTimer = cfg_.dten_pin && dcto != 0;
  if (dv.dischargeTimer) dv.dischargeUntil_s = t + ltc681x_dcto_s(dcto);
}

void Ltc681xChain::writeCfgb(Device& dv, const uint8_t* data) {
  dv.cfgb[0] = data[0];
  dv.cfgb[1] = static_cast<uint8_t>(data[1] & ~LTC6813_CFGRB1_MUTE);  // MUTE reads the state
  for (size_t i = 2; i < LTC681X_GROUP_BYTES; ++i) dv.cfgb[i] = 0;    // reserved
}

// A read command's register group as MonitorChain::noteRead's cells and GPIO inputs.
void Ltc681xChain::noteReadGroup(int d, uint16_t cc) {
  switch (cc) {
    case LTC681X_RDCVA: noteRead(d, 7u << 0, 0u); return;
    case LTC681X_RDCVB: noteRead(d, 7u << 3, 0u); return;
    case LTC681X_RDCVC: noteRead(d, 7u << 6, 0u); return;
    case LTC681X_RDCVD: noteRead(d, 7u << 9, 0u); return;
    case LTC681X_RDCVE: noteRead(d, 7u << 12, 0u); return;
    case LTC681X_RDCVF: noteRead(d, 7u << 15, 0u); return;
    case LTC681X_RDAUXA: noteRead(d, 0u, 7u << 0); return;  // GPIO1-3
    case LTC681X_RDAUXB: noteRead(d, 0u, 3u << 3); return;  // GPIO4-5
    case LTC681X_RDAUXC: noteRead(d, 0u, 7u << 5); return;  // GPIO6-8
    case LTC681X_RDAUXD: noteRead(d, 0u, 1u << 8); return;  // GPIO9
    default: return;
  }
}

void Ltc681xChain::readGroup(const Device& dv, uint16_t cc, double t, uint8_t* out, bool& known) const {
  known = true;
  auto cells3 = [&](int first) {
    for (int i = 0; i < 3; ++i) put16(out + 2 * i, dv.cell[static_cast<size_t>(first + i)]);
  };
  switch (cc) {
    case LTC681X_RDCFGA: {
      for (size_t i = 0; i < LTC681X_GROUP_BYTES; ++i) out[i] = dv.cfga[i];
      if (cfg_.dten_pin) out[0] = static_cast<uint8_t>(out[0] | LTC681X_CFGR0_DTEN);
      uint8_t left = 0;  // DCTO reads the bucket of the time left
      if (dv.dischargeTimer) {
        const double remain_s = dv.dischargeUntil_s - t;
        left = 1;
        while (left < LTC681X_DCTO_CODES - 1 && ltc681x_dcto_s(left) < remain_s) ++left;
      }
      out[5] = static_cast<uint8_t>((out[5] & 0x0F) | (left << LTC681X_DCTO_SHIFT));
      return;
    }
    case LTC681X_RDCFGB:
      if (!is6813()) break;
      for (size_t i = 0; i < LTC681X_GROUP_BYTES; ++i) out[i] = dv.cfgb[i];
      if (dv.muted) out[1] = static_cast<uint8_t>(out[1] | LTC6813_CFGRB1_MUTE);
      return;
    case LTC681X_RDCVA: cells3(0); return;
    case LTC681X_RDCVB: cells3(3); return;
    case LTC681X_RDCVC: cells3(6); return;
    case LTC681X_RDCVD: cells3(9); return;
    case LTC681X_RDCVE: if (!is6813()) break; cells3(12); return;
    case LTC681X_RDCVF: if (!is6813()) break; cells3(15); return;
    case LTC681X_RDAUXA:
      for (int i = 0; i < 3; ++i) put16(out + 2 * i, dv.gpio[static_cast<size_t>(i)]);
      return;
    case LTC681X_RDAUXB:
      put16(out, dv.gpio[3]);
      put16(out + 2, dv.gpio[4]);
      put16(out + 4, dv.ref);
      return;
    case LTC681X_RDAUXC:
      if (!is6813()) break;
      for (int i = 0; i < 3; ++i) put16(out + 2 * i, dv.gpio[static_cast<size_t>(5 + i)]);
      return;
    case LTC681X_RDAUXD: {
      if (!is6813()) break;
      put16(out, dv.gpio[8]);
      out[2] = out[3] = 0xFF;  // reserved
      uint8_t f4 = 0, f5 = 0;
      for (int c = 12; c < 16; ++c)
        f4 = static_cast<uint8_t>(f4 | (((dv.uv >> c) & 1u) << (2 * (c - 12))) | (((dv.ov >> c) & 1u) << (2 * (c - 12) + 1)));
      for (int c = 16; c < 18; ++c)
        f5 = static_cast<uint8_t>(f5 | (((dv.uv >> c) & 1u) << (2 * (c - 16))) | (((dv.ov >> c) & 1u) << (2 * (c - 16) + 1)));
      out[4] = f4;
      out[5] = f5;
      return;
    }
    case LTC681X_RDSTATA:
      put16(out, dv.sc);
      put16(out + 2, dv.itmp);
      put16(out + 4, dv.va);
      return;
    case LTC681X_RDSTATB: {
      put16(out, dv.vd);
      for (int b = 0; b < 3; ++b) {  // STBR2..4: cells 1-4, 5-8, 9-12 -- CxUV in even, CxOV in odd bits
        uint8_t f = 0;
        for (int j = 0; j < 4; ++j) {
          const int c = 4 * b + j;
          f = static_cast<uint8_t>(f | (((dv.uv >> c) & 1u) << (2 * j)) | (((dv.ov >> c) & 1u) << (2 * j + 1)));
        }
        out[2 + b] = f;
      }
      out[5] = static_cast<uint8_t>((dv.thsd ? LTC681X_STB5_THSD : 0u) | (dv.muxfail ? LTC681X_STB5_MUXFAIL : 0u));
      return;
    }
    default: break;
  }
  known = false;
}

void Ltc681xChain::clear(Device& dv, uint16_t cc) {
  if (cc == LTC681X_CLRCELL) dv.cell.fill(LTC681X_CLEARED);
  if (cc == LTC681X_CLRAUX) {
    dv.gpio.fill(LTC681X_CLEARED);
    dv.ref = LTC681X_CLEARED;
  }
  if (cc == LTC681X_CLRSTAT) {
    dv.sc = dv.itmp = dv.va = dv.vd = LTC681X_CLEARED;
    dv.ov = dv.uv = (1u << LTC681X_CELLS_MAX) - 1u;  // every flag set, as the data sheet says
    dv.thsd = dv.muxfail = true;
  }
}

// --- conversions ----------------------------------------------------------------

double Ltc681xChain::truePin(const Device& dv, int pin, bool paused) const {
  const std::vector<double>& cell_V = dv.analog.cellsSeen(paused);
  double v = 0.0;
  for (int c = 0; c < std::min(pin, dv.cells); ++c) v += cell_V[static_cast<size_t>(c)];
  return v;
}

double Ltc681xChain::pinVoltage(const Device& dv, int pin, bool paused) const {
  const double h = dv.held[static_cast<size_t>(pin)];
  return dv.open[static_cast<size_t>(pin)] && !std::isnan(h) ? h : truePin(dv, pin, paused);
}

// DCP = 0: the part opens a cell's discharge switch while it converts the cell or a
// neighbour. CH = all converts in six equal steps (step j: cells j, j+6, j+12); one
// pair / triple is one step of the whole conversion time.
void Ltc681xChain::pauseDischarge(Device& dv, uint8_t ch, double start_s, double conv_s) {
  const int steps = ch == LTC681X_CH_ALL ? 6 : 1;
  const double step_s = conv_s / steps;
  const uint32_t part = (1u << partCells_) - 1u;
  for (int s = 0; s < steps; ++s) {
    const int first = ch == LTC681X_CH_ALL ? s : ch - 1;
    uint32_t open = 0;
    for (int i = first; i < partCells_; i += 6) open |= (7u << i) >> 1;  // cells i-1, i, i+1
    dv.pauses.add(start_s + s * step_s, start_s + (s + 1) * step_s, open & part);
  }
}

void Ltc681xChain::convertCells(Device& dv, uint8_t ch, bool openWire, bool pullUp, double conv_s, bool paused) {
  if (openWire) {  // the 100 uA sources move every open pin towards a neighbour
    const double step_V = LTC681X_ADOW_CURRENT_UA * 1e-6 * conv_s / cfg_.sense_filter_F;
    for (int p = 0; p <= partCells_; ++p) {
      if (!dv.open[static_cast<size_t>(p)]) continue;
      double& h = dv.held[static_cast<size_t>(p)];
      if (std::isnan(h)) h = truePin(dv, p);
      const double target = truePin(dv, pullUp ? std::min(p + 1, partCells_) : std::max(p - 1, 0));
      h = target > h ? std::min(target, h + step_V) : std::max(target, h - step_V);
    }
  }
  dv.pendMask = 0;
  for (int i = 0; i < partCells_; ++i) {  // ADC k measures cells 6k+1..6k+6: CH = j converts j, j+6 (, j+12)
    if (ch != LTC681X_CH_ALL && (i % 6) + 1 != ch) continue;
    // unused inputs are shorted: 0 V through the part's converter alone
    const int64_t code = i < dv.cells ? errors_.convert(cfg_.cell_adc, static_cast<size_t>(dv.firstCell + i), dv.analog,
                                                        static_cast<size_t>(i), pinVoltage(dv, i + 1, paused) - pinVoltage(dv, i, paused),
                                                        noise_)
                                      : cfg_.cell_adc.convert(0.0, noise_);
    dv.pendCell[static_cast<size_t>(i)] = static_cast<uint16_t>(std::clamp<int64_t>(code, 0, 65535));
    dv.pendMask |= 1u << i;
  }
}

void Ltc681xChain::convertGpios(Device& dv, uint8_t chg) {
  dv.pendMask = 0;
  auto one = [&](int k) {  // GPIO(k+1)
    double v = 0.0;
    const bool pulledDown = k < 5 ? !((dv.cfga[0] >> (LTC681X_CFGR0_GPIO_SHIFT + k)) & 1u)
                                  : !((dv.cfgb[0] >> (k - 5)) & 1u);
    if (!pulledDown && k < static_cast<int>(dv.analog.therm_C.size())) {
      const ThermistorFault f = dv.analog.therm_fault[static_cast<size_t>(k)];
      if (f == ThermistorFault::Open) {
        v = kVref2_V;
      } else if (f == ThermistorFault::None) {
        const double r = cfg_.thermistor.resistance_ohm(dv.analog.therm_C[static_cast<size_t>(k)]);
        v = kVref2_V * r / (cfg_.thermistor.pullup_ohm + r);
      }
    }
    if (cfg_.gpio_noise_V > 0.0) v += cfg_.gpio_noise_V * standardNormal(noise_);
    dv.pendGpio[static_cast<size_t>(k)] = code16(v, kLsb_V);
    dv.pendMask |= 1u << k;
  };
  if (chg == LTC681X_CH_ALL) {
    for (int k = 0; k < partGpios_; ++k) one(k);
  } else if (chg >= 1 && chg <= 5) {
    one(chg - 1);
    if (is6813() && chg - 1 + 5 < partGpios_) one(chg - 1 + 5);  // the LTC6813 pairs GPIOk with GPIO(k+5)
  }
  if (chg == LTC681X_CH_ALL || chg == 6) {
    dv.pendRef = code16(kVref2_V, kLsb_V);
    dv.pendMask |= kRefBit;
  }
}

void Ltc681xChain::convertStatus(Device& dv, uint8_t chst) {
  dv.pendMask = 0;
  const double factor = is6813() ? LTC6813_SC_FACTOR : LTC6811_SC_FACTOR;
  if (chst == 0 || chst == 1) {
    dv.pendSc = code16(pinVoltage(dv, partCells_), kLsb_V * factor);
    dv.pendMask |= 1u;
  }
  if (chst == 0 || chst == 2) {
    dv.pendItmp = code16((dv.analog.die_C + LTC681X_ITMP_OFFSET_C) * LTC681X_ITMP_UV_PER_C * 1e-6, kLsb_V);
    dv.pendMask |= 2u;
  }
  if (chst == 0 || chst == 3) {
    dv.pendVa = code16(kVa_V, kLsb_V);
    dv.pendMask |= 4u;
  }
  if (chst == 0 || chst == 4) {
    dv.pendVd = code16(kVd_V, kLsb_V);
    dv.pendMask |= 8u;
  }
}

void Ltc681xChain::convert(Device& dv, double t, uint16_t cc) {
  const uint8_t md = static_cast<uint8_t>((cc >> LTC681X_MD_SHIFT) & 3u);
  const uint8_t adcopt = dv.cfga[0] & LTC681X_CFGR0_ADCOPT;
  const uint16_t fields = static_cast<uint16_t>(cc & ~(3u << LTC681X_MD_SHIFT));
  const uint8_t ch = static_cast<uint8_t>(cc & LTC681X_CH_MASK);
  Conv kind;
  enum ltc681x_conversion table;
  if ((fields & ~(LTC681X_DCP_BIT | LTC681X_CH_MASK)) == LTC681X_ADCV_BASE) {
    kind = Conv::Cells;
    table = LTC681X_CONV_CELLS;
  } else if ((fields & ~(LTC681X_PUP_BIT | LTC681X_DCP_BIT | LTC681X_CH_MASK)) == LTC681X_ADOW_BASE) {
    kind = Conv::Cells;
    table = LTC681X_CONV_CELLS;
  } else if ((fields & ~LTC681X_CH_MASK) == LTC681X_ADAX_BASE && ch <= 6) {  // CHG 7 is ADCVSC
    kind = Conv::Gpios;
    table = LTC681X_CONV_GPIOS;
  } else if ((fields & ~LTC681X_CH_MASK) == LTC681X_ADSTAT_BASE && ch <= 4) {  // CHST 7 is ADCVAX
    kind = Conv::Status;
    table = LTC681X_CONV_STATUS;
  } else {
    return;
  }
  const uint32_t conv_us = ltc681x_conversion_us(md, adcopt, table, ch == LTC681X_CH_ALL);
  if (conv_us == 0) return;  // MD = 00 (422 Hz / 1 kHz): not modelled, the model ignores it
  // With REFON = 0 the reference powers up first (REFUP); with REFON = 1 it is up once
  // tREFUP has passed since it was switched on.
  double start = t;
  if (!(dv.cfga[0] & LTC681X_CFGR0_REFON)) start = t + cfg_.refup_s;
  else if (dv.refUpAt_s > t) start = std::isfinite(dv.refUpAt_s) ? dv.refUpAt_s : t + cfg_.refup_s;
  // A new conversion replaces one still in flight (the model's choice: its results never land).
  if (kind == Conv::Cells) {
    const bool adow = (fields & ~(LTC681X_PUP_BIT | LTC681X_DCP_BIT | LTC681X_CH_MASK)) == LTC681X_ADOW_BASE;
    const bool dischargePermitted = (fields & LTC681X_DCP_BIT) != 0;
    convertCells(dv, ch, adow, (fields & LTC681X_PUP_BIT) != 0, conv_us * 1e-6, !dischargePermitted);
    if (!dischargePermitted) pauseDischarge(dv, ch, start, conv_us * 1e-6);
  } else if (kind == Conv::Gpios) {
    convertGpios(dv, ch);
  } else {
    convertStatus(dv, ch);
  }
  dv.conv = kind;
  dv.readyAt_s = start + conv_us * 1e-6;
}

// --- the link ---------------------------------------------------------------------

BusTransfer Ltc681xChain::transfer(double t, const uint8_t* tx, size_t txLen, uint8_t* rx, size_t rxLen) {
  BusTransfer r;
  if (rx == nullptr) rxLen = 0;
  r.duration_s = linkTime_s(txLen + rxLen);
  std::fill(rx, rx + rxLen, uint8_t{0xFF});  // nothing driven reads as 1s
  r.received = static_cast<int>(rxLen);      // SPI clocks in what it asks for
  for (Device& dv : dev_) settle(dv, t);
  if (tx == nullptr || txLen == 0) return r;

  // Up the chain: every device hears the frame until one is not ready for it (it wakes
  // and the frame ends there), a silent device, or a broken link.
  int n = 0;
  for (int d = 0; d < deviceCount(); ++d) {
    if (brokenAbove_ >= 0 && d > brokenAbove_) break;
    Device& dv = dev_[static_cast<size_t>(d)];
    if (dv.comm.silent) break;
    const bool wasReady = ready(dv, t);
    hear(dv, t);
    if (!wasReady) break;
    ++n;
  }
  if (txLen < LTC681X_CMD_LEN || n == 0) return r;  // a wake-up pulse, or nobody ready
  const uint16_t cc = static_cast<uint16_t>(((tx[0] & 0x07u) << 8) | tx[1]);
  if (!bms::ltcPecOk(tx, 2)) {  // bad command PEC: ignored by all
    misuse_.note(t, -1, commandName(cc), "bad command PEC (frame ignored)");
    return r;
  }
  const double tEnd = t + r.duration_s;

  if (cc == LTC681X_WRCFGA || (cc == LTC681X_WRCFGB && is6813())) {
    // Data blocks: the farthest device's first, device 0's last.
    const size_t blocks = (txLen - LTC681X_CMD_LEN) / LTC681X_SLOT_BYTES;
    for (int d = 0; d < n; ++d) {
      Device& dv = dev_[static_cast<size_t>(d)];
      if (dv.comm.stuck_byte >= 0) continue;  // its link takes no writes
      if (static_cast<size_t>(d) >= blocks) {  // the frame ended before its block
        misuse_.note(t, d, commandName(cc), "no data block for this device (" + std::to_string(blocks) + " in the frame)");
        continue;
      }
      const uint8_t* block = tx + LTC681X_CMD_LEN + (blocks - 1 - static_cast<size_t>(d)) * LTC681X_SLOT_BYTES;
      if (!bms::ltcPecOk(block, LTC681X_GROUP_BYTES)) {
        misuse_.note(t, d, commandName(cc), "data block with a bad PEC (write ignored)");
        continue;
      }
      settle(dv, tEnd);
      if (cc == LTC681X_WRCFGA) writeCfga(dv, tEnd, block);
      else writeCfgb(dv, block);
    }
    return r;
  }
  if (cc == LTC681X_MUTE || cc == LTC681X_UNMUTE) {
    if (!is6813()) misuse_.note(t, -1, commandName(cc), "the LTC6811 has no such command");
    if (is6813())
      for (int d = 0; d < n; ++d) dev_[static_cast<size_t>(d)].muted = cc == LTC681X_MUTE;
    return r;
  }
  if (cc == LTC681X_CLRCELL || cc == LTC681X_CLRAUX || cc == LTC681X_CLRSTAT) {
    for (int d = 0; d < n; ++d) clear(dev_[static_cast<size_t>(d)], cc);
    return r;
  }
  if (cc & 0x200u || cc & 0x400u) {  // conversion commands (bit 9 or 10 set)
    for (int d = 0; d < n; ++d) {
      Device& dv = dev_[static_cast<size_t>(d)];
      settle(dv, tEnd);
      convert(dv, tEnd, cc);
    }
    return r;
  }
  // A read: device 0's slot first. A stuck device drives its own slot and every slot it
  // relays from beyond.
  int stuck = -1;
  for (int d = 0; d < n; ++d) {
    const size_t at = static_cast<size_t>(d) * LTC681X_SLOT_BYTES;
    if (at >= rxLen) break;
    Device& dv = dev_[static_cast<size_t>(d)];
    if (stuck < 0 && dv.comm.stuck_byte >= 0) stuck = dv.comm.stuck_byte;
    uint8_t slot[LTC681X_SLOT_BYTES];
    bool known = false;
    readGroup(dv, cc, t, slot, known);
    if (!known) {  // a command the part does not have: nothing driven
      misuse_.note(t, -1, commandName(cc), std::string("the ") + (is6813() ? "LTC6813" : "LTC6811") + " has no such command");
      return r;
    }
    noteReadGroup(d, cc);
    bms::ltcPutPec(slot, LTC681X_GROUP_BYTES);
    if (stuck >= 0) {
      std::fill(std::begin(slot), std::end(slot), static_cast<uint8_t>(stuck));
    } else {
      corruptReply(dv.comm, commRng_, slot, LTC681X_SLOT_BYTES);
    }
    std::copy(slot, slot + std::min<size_t>(LTC681X_SLOT_BYTES, rxLen - at), rx + at);
  }
  if (stuck >= 0)  // what the stuck device relays from beyond the ready devices reads stuck too
    for (size_t at = static_cast<size_t>(n) * LTC681X_SLOT_BYTES; at < rxLen; ++at) rx[at] = static_cast<uint8_t>(stuck);
  return r;
}

std::string Ltc681xChain::describe(const uint8_t* tx, size_t txLen, size_t) const {
  if (tx == nullptr || txLen < LTC681X_CMD_LEN) return "wake-up pulse";
  return commandName(static_cast<uint16_t>(((tx[0] & 0x07u) << 8) | tx[1]));
}

// --- outputs -----------------------------------------------------------------------

bool Ltc681xChain::balancing(int d, int cell) const {
  const Device& dv = dev_[static_cast<size_t>(d)];
  if (dv.muted || cell < 0 || cell >= partCells_) return false;
  if (cell < 8) return (dv.cfga[4] >> cell) & 1u;
  if (cell < 12) return (dv.cfga[5] >> (cell - 8)) & 1u;
  if (!is6813()) return false;
  if (cell < 16) return (dv.cfgb[0] >> (cell - 12 + 4)) & 1u;
  return (dv.cfgb[1] >> (cell - 16)) & 1u;
}

bool Ltc681xChain::thermistorBias(int d) const {
  const Device& dv = dev_[static_cast<size_t>(d)];
  return !dv.asleep && !dv.analog.therm_C.empty();
}

void Ltc681xChain::setOpenWire(int d, int pin, bool open) {
  Device& dv = dev_[static_cast<size_t>(d)];
  if (pin < 0 || pin > partCells_) throw std::invalid_argument("ltc681x: open-wire pin outside 0.." + std::to_string(partCells_));
  dv.open[static_cast<size_t>(pin)] = open;
  dv.held[static_cast<size_t>(pin)] = std::numeric_limits<double>::quiet_NaN();  // holds the pin's voltage until an ADOW moves it
}

std::unique_ptr<MonitorChain> makeLtc681xChain(const Ltc681xConfig& cfg, int cellCount, uint64_t seed) {
  return std::make_unique<Ltc681xChain>(cfg, cellCount, seed);
}

}  // namespace packsim
