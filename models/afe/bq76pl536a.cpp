#include "models/afe/reply_corruption.hpp"
#include "models/afe/bq76pl536a.hpp"
#include "models/afe/byte_copy.hpp"
#include "models/afe/window_masks.hpp"
#include "models/sensors/round_even.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include <bms/bms_crc.hpp>
#include "models/pack/cell_spread.hpp"

namespace packsim {

namespace {

void putBe16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v >> 8);
  p[1] = static_cast<uint8_t>(v & 0xFF);
}

uint16_t code16(int64_t code) { return static_cast<uint16_t>(std::clamp<int64_t>(code, 0, 65535)); }

uint32_t roundedU32(double v) { return static_cast<uint32_t>(std::max(0.0, std::nearbyint(v))); }

// The EEPROM image of CONFIG_COV..CONFIG_OTT (registers 0x42..0x47) as the team
// programmed it: MonitorConfig::secondary in the part's steps.
std::array<uint8_t, 8> programmedConfig(const MonitorConfig& cfg) {
  const SecondaryProtection& p = cfg.secondary;
  std::array<uint8_t, 8> e{};
  const uint8_t off = p.enabled ? 0 : BQ536_CONFIG_DISABLE;
  e[BQ536_CONFIG_COV - BQ536_FUNCTION_CONFIG] = static_cast<uint8_t>(off | bq536_cov_code(roundedU32(p.cov_V * 1e3)));
  e[BQ536_CONFIG_COVT - BQ536_FUNCTION_CONFIG] = bq536_delay_code(roundedU32(p.cov_delay_s * 1e6));
  e[BQ536_CONFIG_CUV - BQ536_FUNCTION_CONFIG] = static_cast<uint8_t>(off | bq536_cuv_code(roundedU32(p.cuv_V * 1e3)));
  e[BQ536_CONFIG_CUVT - BQ536_FUNCTION_CONFIG] = bq536_delay_code(roundedU32(p.cuv_delay_s * 1e6));
  const uint8_t ot = bq536_ot_code(static_cast<int32_t>(std::nearbyint(p.ot_C)));
  uint8_t otReg = 0;
  if (p.enabled && cfg.thermistors_per_device >= 1) otReg = ot;
  if (p.enabled && cfg.thermistors_per_device >= 2) otReg = static_cast<uint8_t>(otReg | (ot << 4));
  e[BQ536_CONFIG_OT - BQ536_FUNCTION_CONFIG] = otReg;
  e[BQ536_CONFIG_OTT - BQ536_FUNCTION_CONFIG] = bq536_ott_code(roundedU32(p.ot_delay_s * 1e3));
  return e;
}

// A register's data-sheet name (2-byte results by their first byte).
std::string registerName(uint8_t reg) {
  switch (reg) {
    case BQ536_DEVICE_STATUS: return "DEVICE_STATUS";
    case BQ536_GPAI: case BQ536_GPAI + 1: return "GPAI";
    case BQ536_TEMPERATURE1: case BQ536_TEMPERATURE1 + 1: return "TEMPERATURE1";
    case BQ536_TEMPERATURE2: case BQ536_TEMPERATURE2 + 1: return "TEMPERATURE2";
    case BQ536_ALERT_STATUS: return "ALERT_STATUS";
    case BQ536_FAULT_STATUS: return "FAULT_STATUS";
    case BQ536_COV_FAULT: return "COV_FAULT";
    case BQ536_CUV_FAULT: return "CUV_FAULT";
    case BQ536_ADC_CONTROL: return "ADC_CONTROL";
    case BQ536_IO_CONTROL: return "IO_CONTROL";
    case BQ536_CB_CTRL: return "CB_CTRL";
    case BQ536_CB_TIME: return "CB_TIME";
    case BQ536_ADC_CONVERT: return "ADC_CONVERT";
    case BQ536_SHDW_CTRL: return "SHDW_CTRL";
    case BQ536_ADDRESS_CONTROL: return "ADDRESS_CONTROL";
    case BQ536_RESET: return "RESET";
    case BQ536_FUNCTION_CONFIG: return "FUNCTION_CONFIG";
    case BQ536_IO_CONFIG: return "IO_CONFIG";
    case BQ536_CONFIG_COV: return "CONFIG_COV";
    case BQ536_CONFIG_COVT: return "CONFIG_COVT";
    case BQ536_CONFIG_CUV: return "CONFIG_CUV";
    case BQ536_CONFIG_CUVT: return "CONFIG_CUVT";
    case BQ536_CONFIG_OT: return "CONFIG_OT";
    case BQ536_CONFIG_OTT: return "CONFIG_OTT";
    default: break;
  }
  if (reg >= BQ536_VCELL1 && reg < BQ536_VCELL1 + 12) return "VCELL" + std::to_string((reg - BQ536_VCELL1) / 2 + 1);
  return "register " + hexByte(reg);
}

// The words (register pairs from `base`, n of them) both of whose registers are in `regs`.
uint32_t wordsIn(uint64_t regs, unsigned base, unsigned n) {
  uint32_t words = 0;
  for (unsigned i = 0; i < n; ++i)
    if (((regs >> (base + 2 * i)) & 3u) == 3u) words |= 1u << i;
  return words;
}

}  // namespace

Bq76pl536aChain::Bq76pl536aChain(const MonitorConfig& cfg, int cellCount, uint64_t seed)
    : cfg_(cfg),
      dev_(static_cast<size_t>(std::max(cfg.devices, 0))),
      errors_(cellCount, cfg.channel_gain_sd, cfg.channel_offset_sd_V, seed),
      noise_(deriveSeed(seed, 0x536A)),
      commRng_(deriveSeed(seed, 0x536C)),
      eeprom_(programmedConfig(cfg)) {
  if (cfg.cells_per_device < 1 || cfg.cells_per_device > static_cast<int>(BQ536_CELLS_MAX))
    throw std::invalid_argument("bq76pl536a: cells_per_device " + std::to_string(cfg.cells_per_device) +
                                " outside 1..6");
  if (cfg.devices < 1 || cfg.devices > static_cast<int>(BQ536_ADDR_MAX))
    throw std::invalid_argument("bq76pl536a: devices " + std::to_string(cfg.devices) + " outside 1..62");
  if (!(cfg.baud > 0.0)) throw std::invalid_argument("bq76pl536a: baud (SPI clock) must be > 0");
  const size_t therms = static_cast<size_t>(std::clamp(cfg.thermistors_per_device, 0, static_cast<int>(BQ536_TEMPS_MAX)));
  for (size_t d = 0; d < dev_.size(); ++d) {
    Device& dv = dev_[d];
    dv.firstCell = static_cast<int>(d) * cfg.cells_per_device;
    dv.cells = std::max(0, std::min(cfg.cells_per_device, cellCount - dv.firstCell));
    dv.analog.size(dv.cells, static_cast<int>(therms));
    reset(dv);
  }
}

void Bq76pl536aChain::reset(Device& dv) {
  dv.reg.fill(0);
  std::copy(eeprom_.begin(), eeprom_.end(), dv.reg.begin() + BQ536_FUNCTION_CONFIG);
  dv.reg[BQ536_FAULT_STATUS] = BQ536_FS_POR;
  dv.reg[BQ536_ALERT_STATUS] = BQ536_AS_AR;
  dv.shadowOpen = false;
  dv.compared = false;
  dv.lastLatchWrite[0] = dv.lastLatchWrite[1] = 0;
  dv.cov = DebounceTimer{};
  dv.cuv = DebounceTimer{};
  for (DebounceTimer& o : dv.ot) o = DebounceTimer{};
  dv.converting = false;
  dv.resultsValid = false;
  dv.convertedRegs = dv.pendingRegs = 0;
  dv.balanceUntil_s = 0.0;
  readSettings(dv);
  reach_ = reach();  // its address is gone
}

static_assert(BQ536_TEMPS_MAX * 4 == 8, "CONFIG_OT: one nibble per temperature input, the whole byte");

void Bq76pl536aChain::readSettings(Device& dv) {
  ComparatorSettings& c = dv.settings;
  const uint8_t covReg = dv.reg[BQ536_CONFIG_COV], cuvReg = dv.reg[BQ536_CONFIG_CUV];
  c.covOn = !(covReg & BQ536_CONFIG_DISABLE);
  c.cuvOn = !(cuvReg & BQ536_CONFIG_DISABLE);
  c.cov_V = bq536_cov_mV(covReg) * 1e-3;
  c.cuv_V = bq536_cuv_mV(cuvReg) * 1e-3;
  c.otOn = 0;
  for (size_t k = 0; k < BQ536_TEMPS_MAX; ++k) {
    const uint8_t nibble = static_cast<uint8_t>((dv.reg[BQ536_CONFIG_OT] >> (4 * k)) & 0x0F);
    if (nibble != 0) c.otOn = static_cast<uint8_t>(c.otOn | (1u << k));
    c.ot_C[k] = bq536_ot_C(nibble);
  }
  // Every comparator off (CONFIG_OT's two nibbles, its whole byte, 0): compare() finds
  // nothing present, whatever the inputs.
  dv.blind = !c.covOn && !c.cuvOn && c.otOn == 0;
}

uint8_t Bq76pl536aChain::status(const Device& dv) const {
  uint8_t s = 0;
  if (dv.resultsValid && !dv.converting) s |= BQ536_DS_DRDY;
  if (dv.reg[BQ536_CB_CTRL] != 0) s |= BQ536_DS_CBT;
  if (dv.reg[BQ536_ALERT_STATUS] != 0) s |= BQ536_DS_ALERT;
  if (dv.reg[BQ536_FAULT_STATUS] != 0) s |= BQ536_DS_FAULT;
  if (assigned(dv)) s |= BQ536_DS_ADDR_RQST;
  return s;
}

void Bq76pl536aChain::settleDue(Device& dv, double t) {
  // A conversion's results land when its last channel is done.
  if (dv.converting && t >= dv.readyAt_s - 1e-12) {
    std::memcpy(&dv.reg[BQ536_GPAI], &dv.pending[BQ536_GPAI], BQ536_RESULTS_LEN - BQ536_GPAI);
    dv.converting = false;
    dv.resultsValid = true;
    dv.convertedRegs |= dv.pendingRegs;
  }
  // The balancing timer runs on the device: it switches the cells off itself.
  if (dv.reg[BQ536_CB_CTRL] != 0 && t >= dv.balanceUntil_s - 1e-9) dv.reg[BQ536_CB_CTRL] = 0;
}

void Bq76pl536aChain::compare(Device& dv) {
  const DeviceAnalog& a = dv.analog;
  const ComparatorSettings& c = dv.settings;  // the registers' thresholds (readSettings)
  uint32_t overAll = 0, underAll = 0;  // the pin voltages: comparators are not the ADC
  windowMasks(a.cell_V.data(), dv.cells, c.cuv_V, c.cov_V, overAll, underAll);
  // A disabled comparator sees nothing (masked once, not tested per cell).
  uint8_t over = static_cast<uint8_t>(c.covOn ? overAll : 0u), under = static_cast<uint8_t>(c.cuvOn ? underAll : 0u), hot = 0;
  for (size_t k = 0; k < BQ536_TEMPS_MAX; ++k) {
    if (((c.otOn >> k) & 1u) && k < a.therm_C.size()) {
      // A shorted NTC looks infinitely hot to the comparator; an open one cold.
      const ThermistorFault f = a.therm_fault[k];
      if (f == ThermistorFault::Short || (f == ThermistorFault::None && a.therm_C[k] > c.ot_C[k]))
        hot |= static_cast<uint8_t>(1u << k);
    }
  }
  dv.over = over;
  dv.under = under;
  dv.hot = hot;
  dv.compared = true;
  // Still nothing present with the timers at rest: still nothing to do. Else one pass
  // with these conditions (which puts the timers of absent conditions at rest).
  dv.quiet = dv.quiet && over == 0 && under == 0 && hot == 0;
}

void Bq76pl536aChain::runComparatorsPass(Device& dv, double t) {
  if (!dv.compared) compare(dv);
  // With no condition present a pass only puts the timers at rest; after one it does
  // nothing (DebounceTimer::held with a false condition), so it is skipped.
  if (dv.quiet) return;
  if (dv.cov.held(t, dv.over != 0, bq536_delay_us(dv.reg[BQ536_CONFIG_COVT]) * 1e-6)) {
    dv.reg[BQ536_FAULT_STATUS] |= BQ536_FS_COV;
    dv.reg[BQ536_COV_FAULT] |= dv.over;
  }
  if (dv.cuv.held(t, dv.under != 0, bq536_delay_us(dv.reg[BQ536_CONFIG_CUVT]) * 1e-6)) {
    dv.reg[BQ536_FAULT_STATUS] |= BQ536_FS_CUV;
    dv.reg[BQ536_CUV_FAULT] |= dv.under;
  }
  const double otDelay_s = dv.reg[BQ536_CONFIG_OTT] * BQ536_OTT_STEP_MS * 1e-3;
  for (size_t k = 0; k < BQ536_TEMPS_MAX; ++k)
    if (dv.ot[k].held(t, (dv.hot >> k) & 1u, otDelay_s)) dv.reg[BQ536_ALERT_STATUS] |= static_cast<uint8_t>(BQ536_AS_OT1 << k);
  dv.quiet = dv.over == 0 && dv.under == 0 && dv.hot == 0;
}

void Bq76pl536aChain::settleAll(double t) {
  double due = std::numeric_limits<double>::infinity();
  for (Device& dv : dev_) {
    settle(dv, t);
    due = std::min(due, dueOf(dv));
  }
  dueAt_s_ = due;
}

void Bq76pl536aChain::runAllComparators(double t) {
  bool calm = true;
  for (Device& dv : dev_) {
    runComparators(dv, t);
    calm = calm && dv.compared && dv.quiet;
  }
  calm_ = calm;
}

// A device's settling and its comparators touch different registers (results, CB_CTRL;
// the fault latches) and no other device: all devices settled, then all compared, is the
// device-by-device order's outcome.
void Bq76pl536aChain::advance(double t) {
  if (t >= dueAt_s_) settleAll(t);
  if (!calm_) runAllComparators(t);
}

template <class Round>
[[gnu::always_inline]] inline void Bq76pl536aChain::startConversionWith(Device& dv, double t) {
  const uint8_t sel = dv.reg[BQ536_ADC_CONTROL];
  const int nCells = std::min<int>((sel & BQ536_AC_CELL_SEL_MASK) + 1, BQ536_CELLS_MAX);
  // The channels it does not convert keep their results.
  std::memcpy(&dv.pending[BQ536_GPAI], &dv.reg[BQ536_GPAI], BQ536_RESULTS_LEN - BQ536_GPAI);
  auto put = [&](uint8_t reg, uint16_t code) { putBe16(&dv.pending[reg], code); };
  int channels = 0;
  uint64_t converted = 0;  // the result registers this conversion gives a reading (Device::convertedRegs)
  const DeviceAnalog& a = dv.analog;
  // The part converts with its balancing switches as they are; a host that opens them
  // around its conversions (measure_paused) has them read without their I_bal·R drop.
  const std::vector<double>& cell_V = a.cellsSeen(a.host_opens_balancing);
  // Fixed order: GPAI, VCELL1..n, TS1, TS2 (the noise stream depends on it).
  if (sel & BQ536_AC_GPAI) {
    const double module_V = moduleVoltage(cell_V, cfg_.module_noise_V, noise_);
    const double lsb = BQ536_GPAI_CELL_LSBS * cfg_.cell_adc.lsb;
    put(BQ536_GPAI, code16(std::clamp<int64_t>(static_cast<int64_t>(Round::of(module_V / lsb)), 0,
                                               cfg_.cell_adc.code_max)));
    ++channels;
  }
  for (int c = 0; c < nCells; ++c, ++channels) {
    if (c >= dv.cells) {
      put(BQ536_VCELL(c), 0);  // unpopulated input
      continue;
    }
    const size_t i = static_cast<size_t>(c), cell = static_cast<size_t>(dv.firstCell + c);
    put(BQ536_VCELL(c), code16(errors_.convert<Round>(cfg_.cell_adc, cell, a, i, cell_V[i], noise_)));
    converted |= uint64_t{3} << BQ536_VCELL(c);
  }
  const uint8_t tsSel[BQ536_TEMPS_MAX] = {BQ536_AC_TS1, BQ536_AC_TS2};
  const uint8_t tsBias[BQ536_TEMPS_MAX] = {BQ536_IO_TS1, BQ536_IO_TS2};
  const uint8_t tsReg[BQ536_TEMPS_MAX] = {BQ536_TEMPERATURE1, BQ536_TEMPERATURE2};
  for (size_t k = 0; k < BQ536_TEMPS_MAX; ++k) {
    if (!(sel & tsSel[k])) continue;
    ++channels;
    uint16_t code = 0;  // no divider bias (or no thermistor): the input sits at 0
    if (k < a.therm_C.size() && (dv.reg[BQ536_IO_CONTROL] & tsBias[k])) {
      code = code16(thermistorCode(cfg_.thermistor, a.therm_fault[k], a.therm_C[k], dv.thermCode[k], noise_));
      converted |= uint64_t{3} << tsReg[k];
    }
    put(tsReg[k], code);
  }
  dv.converting = true;
  dv.pendingRegs = converted;
  dv.readyAt_s = t + channels * cfg_.conversion_s_per_channel;
  if (a.host_opens_balancing) dv.pauses.add(t, dv.readyAt_s, (1u << dv.cells) - 1u);
  settle(dv, t);  // a zero conversion time lands at once
}

// The SSE4.1 build of startConversion (round_even.hpp): the same body, its rounding roundsd.
__attribute__((target("sse4.1"))) void Bq76pl536aChain::startConversionNative(Device& dv, double t) {
  startConversionWith<RoundNearbyint>(dv, t);
}

void Bq76pl536aChain::clearLatches(Device& dv, uint8_t reg, uint8_t falling) {
  // Written 1 then 0: a protection latch clears only once its condition is gone;
  // the housekeeping bits (POR, CRC, AR, ...) clear at once.
  uint8_t clear = falling;
  if (reg == BQ536_FAULT_STATUS) {
    if (dv.cov.active()) clear = static_cast<uint8_t>(clear & ~BQ536_FS_COV);
    if (dv.cuv.active()) clear = static_cast<uint8_t>(clear & ~BQ536_FS_CUV);
    if (clear & BQ536_FS_COV) dv.reg[BQ536_COV_FAULT] = 0;
    if (clear & BQ536_FS_CUV) dv.reg[BQ536_CUV_FAULT] = 0;
  } else {
    for (size_t k = 0; k < BQ536_TEMPS_MAX; ++k)
      if (dv.ot[k].active()) clear = static_cast<uint8_t>(clear & ~(BQ536_AS_OT1 << k));
  }
  dv.reg[reg] = static_cast<uint8_t>(dv.reg[reg] & ~clear);
}

void Bq76pl536aChain::write(Device& dv, double t, uint8_t reg, uint8_t value) {
  const int device = static_cast<int>(&dv - dev_.data());
  const bool unlocked = dv.shadowOpen;
  dv.shadowOpen = false;  // the key opens exactly one write
  switch (reg) {
    case BQ536_ALERT_STATUS:
    case BQ536_FAULT_STATUS: {
      uint8_t& last = dv.lastLatchWrite[reg == BQ536_FAULT_STATUS ? 1 : 0];
      const uint8_t falling = static_cast<uint8_t>(last & ~value);
      last = value;
      clearLatches(dv, reg, falling);
      break;
    }
    case BQ536_ADC_CONTROL:
      dv.reg[reg] = static_cast<uint8_t>(value & 0x7F);
      break;
    case BQ536_IO_CONTROL:
      dv.reg[reg] = value;
      break;
    case BQ536_CB_CTRL:
    case BQ536_CB_TIME: {
      if (reg == BQ536_CB_CTRL) {
        const unsigned has = (1u << dv.cells) - 1u;
        if (value & ~has) misuse_.note(t, device, registerName(reg), balanceBitsPastCells(value & ~has, dv.cells, 2));
        dv.reg[reg] = static_cast<uint8_t>(value & has);
      } else
        dv.reg[reg] = static_cast<uint8_t>(value & (BQ536_CBT_MINUTES | BQ536_CBT_TIME_MASK));
      // Either write (re)starts the timer while switches are on; a zero time stops them.
      if (dv.reg[BQ536_CB_CTRL] != 0) dv.balanceUntil_s = t + bq536_cb_time_s(dv.reg[BQ536_CB_TIME]);
      break;
    }
    case BQ536_ADC_CONVERT:
      if (value & BQ536_CONV_START) startConversion(dv, t);
      break;
    case BQ536_SHDW_CTRL:
      dv.shadowOpen = value == BQ536_SHDW_KEY;
      break;
    case BQ536_ADDRESS_CONTROL: {
      const uint8_t a = static_cast<uint8_t>(value & BQ536_ADDR_MASK);
      dv.reg[reg] = a != 0 && a != BQ536_ADDR_BROADCAST ? static_cast<uint8_t>(a | BQ536_ADDR_ASSIGNED) : 0;
      reach_ = reach();
      break;
    }
    case BQ536_RESET:
      if (value == BQ536_RESET_KEY) reset(dv);
      else misuse_.note(t, device, registerName(reg), "written without its key (" + hexByte(BQ536_RESET_KEY) + ")");
      break;
    default:
      // Protected configuration: only right after the shadow key. Others are read-only.
      if (reg >= BQ536_FUNCTION_CONFIG && reg <= BQ536_CONFIG_OTT && unlocked) {
        dv.reg[reg] = value;
        dv.compared = false;  // a threshold may change
        readSettings(dv);
      } else if (reg >= BQ536_FUNCTION_CONFIG && reg <= BQ536_CONFIG_OTT)
        misuse_.note(t, device, registerName(reg), "protected register written without the SHDW_CTRL key just before");
      else
        misuse_.note(t, device, registerName(reg), "read-only or reserved register written");
      break;
  }
  settle(dv, t);
  // A conversion started or a balancing timer (re)set may be due before the chain's
  // earliest; a threshold written needs a comparator pass.
  dueAt_s_ = std::min(dueAt_s_, dueOf(dv));
  calm_ = calm_ && dv.compared;
}

int Bq76pl536aChain::reach() const {
  int n = 0;
  for (int d = 0; d < deviceCount(); ++d) {
    if (brokenAbove_ >= 0 && d > brokenAbove_) break;
    ++n;
    if (!assigned(dev_[static_cast<size_t>(d)])) break;  // it does not pass frames up
  }
  return n;
}

static_assert(BQ536_TEMPERATURE2 + 2u <= 64u, "the result registers fit Device::registersRead");

BusTransfer Bq76pl536aChain::transfer(double t, const uint8_t* tx, size_t txLen, uint8_t* rx, size_t rxLen) {
  BusTransfer r;
  r.duration_s = linkTime_s(txLen + rxLen);
  if (rx == nullptr) rxLen = 0;
  if (t >= dueAt_s_) settleAll(t);
  r.received = rxLen > 0 ? -1 : 0;
  if (tx == nullptr || txLen < BQ536_READ_REQUEST_LEN) return r;
  const uint8_t addr = static_cast<uint8_t>(tx[0] >> 1);
  const int n = reach_;  // as the frame set out: a write on its way may change an address

  if (tx[0] & 1u) {  // write frame: acted on once the device has it all
    if (txLen < BQ536_WRITE_FRAME_LEN) return r;
    const double tEnd = t + r.duration_s;
    const bool crcOk = writeCrc_.of(tx, 3) == tx[3];
    for (int i = 0; i < n; ++i) {
      Device& dv = dev_[static_cast<size_t>(i)];
      if (addr != BQ536_ADDR_BROADCAST && addressOf(dv) != addr) continue;
      if (dv.comm.silent || dv.comm.stuck_byte >= 0) continue;  // its link does not take writes
      if (!crcOk) {
        misuse_.note(t, static_cast<int>(&dv - dev_.data()), registerName(tx[1]), "write with a bad CRC (rejected, FAULT_STATUS CRC set)");
        dv.reg[BQ536_FAULT_STATUS] |= BQ536_FS_CRC;  // rejected, and flagged
        continue;
      }
      settle(dv, tEnd);
      write(dv, tEnd, tx[1], tx[2]);
    }
    return r;
  }

  // read frame: the one device with that address answers
  if (addr == BQ536_ADDR_BROADCAST || rxLen == 0) return r;
  Device* target = nullptr;
  for (int i = 0; i < n && target == nullptr; ++i) {
    Device& dv = dev_[static_cast<size_t>(i)];
    if (addressOf(dv) == addr) target = &dv;
  }
  if (target == nullptr || target->comm.silent) return r;
  const size_t count = tx[2], first = tx[1];
  if (const uint64_t span = registerSpan(first, count) & target->convertedRegs; (span & ~target->registersRead) != 0) {
    // registers holding a reading not read before (the usual read: none, no call): the
    // cells and thermistors whose words this read delivers whole
    target->registersRead |= span;
    noteRead(static_cast<int>(target - dev_.data()), wordsIn(span, BQ536_VCELL1, BQ536_CELLS_MAX),
             wordsIn(span, BQ536_TEMPERATURE1, BQ536_TEMPS_MAX));
  }
  uint8_t frame[3 + 256];
  std::copy(tx, tx + 3, frame);
  // The registers from `first` on; past the register file they read 0.
  const size_t inFile = first < BQ536_REGISTER_COUNT ? std::min(count, BQ536_REGISTER_COUNT - first) : 0;
  if (inFile > 0) copyBytes(frame + 3, target->reg.data() + first, inFile);
  if (inFile < count) zeroBytes(frame + 3 + inFile, count - inFile);
  if (first == BQ536_DEVICE_STATUS && count > 0) frame[3] = status(*target);
  frame[3 + count] = replyCrc(*target, frame, 3 + count);
  uint8_t* reply = frame + 3;
  const size_t replyLen = count + 1;
  corruptReply(target->comm, commRng_, reply, replyLen);
  const size_t got = std::min(rxLen, replyLen);
  copyBytes(rx, reply, got);  // (std::copy and memcpy compile to a rep movs here: slow for a few bytes)
  r.received = static_cast<int>(got);
  return r;
}

std::string Bq76pl536aChain::describe(const uint8_t* tx, size_t txLen, size_t) const {
  if (txLen < BQ536_READ_REQUEST_LEN) return "short frame";
  const uint8_t addr = static_cast<uint8_t>(tx[0] >> 1);
  const std::string at = addr == BQ536_ADDR_BROADCAST ? " (broadcast)" : " at address " + std::to_string(addr);
  if (tx[0] & 1u) return "write " + registerName(tx[1]) + " = " + hexByte(tx[2]) + at;
  return "read " + registerName(tx[1]) + (tx[2] > 1 ? " +" + std::to_string(tx[2] - 1) : std::string()) + at;
}

bool Bq76pl536aChain::faultLine() const {
  for (const Device& dv : dev_)
    if ((dv.reg[BQ536_FAULT_STATUS] & (BQ536_FS_COV | BQ536_FS_CUV)) ||
        (dv.reg[BQ536_ALERT_STATUS] & (BQ536_AS_OT1 | BQ536_AS_OT2)))
      return true;
  return false;
}

std::string Bq76pl536aChain::faultCause() const {
  std::string out;
  for (size_t d = 0; d < dev_.size(); ++d) {
    const uint8_t fs = dev_[d].reg[BQ536_FAULT_STATUS], as = dev_[d].reg[BQ536_ALERT_STATUS];
    std::string why;
    if (fs & BQ536_FS_COV) appendListed(why, "COV (cell over-voltage)");
    if (fs & BQ536_FS_CUV) appendListed(why, "CUV (cell under-voltage)");
    if (as & BQ536_AS_OT1) appendListed(why, "OT1 (over-temperature on TS1)");
    if (as & BQ536_AS_OT2) appendListed(why, "OT2 (over-temperature on TS2)");
    if (!why.empty()) appendListed(out, "device " + std::to_string(d + 1) + ": " + why, "; ");
  }
  return out;
}

bool Bq76pl536aChain::thermistorBias(int d) const {
  return (dev_[static_cast<size_t>(d)].reg[BQ536_IO_CONTROL] & (BQ536_IO_TS1 | BQ536_IO_TS2)) != 0;
}

bool Bq76pl536aChain::balancing(int d, int cell) const {
  return (dev_[static_cast<size_t>(d)].reg[BQ536_CB_CTRL] & (1u << cell)) != 0;
}

uint32_t Bq76pl536aChain::balancingMask(int d) const {
  const Device& dv = dev_[static_cast<size_t>(d)];
  return dv.reg[BQ536_CB_CTRL] & ((1u << dv.cells) - 1u);
}

std::unique_ptr<MonitorChain> makeBq76pl536aChain(const MonitorConfig& cfg, int cellCount, uint64_t seed) {
  return std::make_unique<Bq76pl536aChain>(cfg, cellCount, seed);
}

}  // namespace packsim
