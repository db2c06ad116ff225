#include "models/afe/reply_corruption.hpp"
#include "models/afe/bq76pl455a.hpp"
#include "models/afe/byte_copy.hpp"
#include "models/afe/window_masks.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <bms/afe/bq76pl455a_regs.h>
#include <bms/bms_crc.hpp>

#include "models/pack/cell_spread.hpp"

namespace packsim {

namespace {

constexpr uint32_t kBalanceTime_s[PL455_BALANCE_TIME_CODES] = PL455_BALANCE_TIME_S_INIT;
constexpr uint32_t kCommTimeout_ms[PL455_CTO_FAULT_CODES] = PL455_CTO_FAULT_MS_INIT;

uint16_t get16(const std::array<uint8_t, 256>& r, unsigned a) {
  return static_cast<uint16_t>((r[a] << 8) | r[a + 1]);
}
void set16(std::array<uint8_t, 256>& r, unsigned a, uint16_t v) {
  r[a] = static_cast<uint8_t>(v >> 8);
  r[a + 1] = static_cast<uint8_t>(v & 0xFF);
}
uint32_t get32(const std::array<uint8_t, 256>& r, unsigned a) {
  return (static_cast<uint32_t>(get16(r, a)) << 16) | get16(r, a + 2);
}
uint16_t clampU16(double v) { return static_cast<uint16_t>(std::clamp(std::nearbyint(v), 0.0, 65535.0)); }

// COMP_UV / COMP_OV field for a threshold (nearest 25 mV step) and back.
uint8_t compField(double v, unsigned base_mV) {
  const double steps = std::nearbyint((v * 1e3 - base_mV) / PL455_COMP_STEP_MV);
  return static_cast<uint8_t>(std::clamp(steps, 0.0, double{PL455_COMP_MAX_STEPS}) * 2.0);
}
double compVolts(uint8_t field, unsigned base_mV) {
  // exact for every 25 mV step (4300 / 1000 is the double nearest 4.3)
  return (base_mV + (field >> PL455_COMP_SHIFT) * double{PL455_COMP_STEP_MV}) / 1000.0;
}

// Which registers a write stores, which are write-1-to-clear fault flags, and which
// are read only; the EEPROM holds the configuration registers.
enum class Access { Stored, ReadOnly, ClearOnOne };
Access access(unsigned a) {
  if (a == PL455_REG_SREV || a == PL455_REG_STATUS) return Access::ReadOnly;
  if (a >= PL455_REG_FAULT_SUM && a <= PL455_REG_FAULT_GPI) return Access::ClearOnOne;
  return Access::Stored;
}
bool inEeprom(unsigned a) {
  return (a >= PL455_REG_CHANNELS && a <= PL455_REG_CBCONFIG && a != PL455_REG_ADDR && a != PL455_REG_DEV_CTRL) ||
         a == PL455_REG_CTO ||
         (a >= PL455_REG_FO_CTRL && a < PL455_REG_FO_CTRL + 2) ||
         (a >= PL455_REG_COMP_UV && a < PL455_REG_AUX_OV(7) + 2);
}

// Noiseless ratiometric code of a thermistor input (what its comparator sees).
double thermCodeIdeal(const Thermistor& th, double temp_C, ThermistorFault f) {
  if (f == ThermistorFault::Open) return static_cast<double>(th.fullScaleCode());
  if (f == ThermistorFault::Short) return 0.0;
  return th.idealCode(temp_C);
}
// Whether that code lies below `hotCode` (the input's hot comparator), its noiseless code
// kept in `kept` (ThermistorCodeCache::idealBelow: mostly no exp).
bool thermCodeBelow(const Thermistor& th, double temp_C, ThermistorFault f, double hotCode, ThermistorCodeCache& kept) {
  if (f == ThermistorFault::Open) return static_cast<double>(th.fullScaleCode()) < hotCode;
  if (f == ThermistorFault::Short) return 0.0 < hotCode;
  return kept.idealBelow(th, temp_C, hotCode);
}

// A register's data-sheet name (multi-byte registers by their first byte).
std::string registerName(unsigned a) {
  struct Span { unsigned at, len; const char* name; };
  static const Span kNames[] = {
      {PL455_REG_SREV, 1, "SREV"}, {PL455_REG_CMD, 1, "CMD"}, {PL455_REG_CHANNELS, 4, "CHANNELS"},
      {PL455_REG_OVERSMPL, 1, "OVERSMPL"}, {PL455_REG_ADDR, 1, "ADDR"}, {PL455_REG_GROUP_ID, 1, "GROUP_ID"},
      {PL455_REG_DEV_CTRL, 1, "DEV_CTRL"}, {PL455_REG_NCHAN, 1, "NCHAN"}, {PL455_REG_DEVCONFIG, 1, "DEVCONFIG"},
      {PL455_REG_PWRCONFIG, 1, "PWRCONFIG"}, {PL455_REG_COMCONFIG, 2, "COMCONFIG"}, {PL455_REG_TXHOLDOFF, 1, "TXHOLDOFF"},
      {PL455_REG_CBCONFIG, 1, "CBCONFIG"}, {PL455_REG_CBENBL, 2, "CBENBL"}, {PL455_REG_CTO, 1, "CTO"},
      {PL455_REG_STATUS, 1, "STATUS"}, {PL455_REG_FAULT_SUM, 2, "FAULT_SUM"}, {PL455_REG_FAULT_UV, 2, "FAULT_UV"},
      {PL455_REG_FAULT_OV, 2, "FAULT_OV"}, {PL455_REG_FAULT_AUX, 2, "FAULT_AUX"}, {PL455_REG_FAULT_2UV, 2, "FAULT_2UV"},
      {PL455_REG_FAULT_2OV, 2, "FAULT_2OV"}, {PL455_REG_FAULT_COM, 2, "FAULT_COM"}, {PL455_REG_FAULT_SYS, 1, "FAULT_SYS"},
      {PL455_REG_FAULT_DEV, 2, "FAULT_DEV"}, {PL455_REG_FAULT_GPI, 1, "FAULT_GPI"}, {PL455_REG_FO_CTRL, 2, "FO_CTRL"},
      {PL455_REG_MAGIC1, 4, "MAGIC1"}, {PL455_REG_COMP_UV, 1, "COMP_UV"}, {PL455_REG_COMP_OV, 1, "COMP_OV"},
      {PL455_REG_CELL_UV, 2, "CELL_UV"}, {PL455_REG_CELL_OV, 2, "CELL_OV"}, {PL455_REG_EE_BURN, 1, "EE_BURN"},
      {PL455_REG_MAGIC2, 4, "MAGIC2"},
  };
  for (const Span& n : kNames)
    if (a >= n.at && a < n.at + n.len) return n.name;
  for (unsigned k = 0; k < PL455_AUX_INPUTS; ++k) {
    if (a >= PL455_REG_AUX_UV(k) && a < PL455_REG_AUX_UV(k) + 2u) return "AUX" + std::to_string(k) + "_UV";
    if (a >= PL455_REG_AUX_OV(k) && a < PL455_REG_AUX_OV(k) + 2u) return "AUX" + std::to_string(k) + "_OV";
  }
  return "register " + hexByte(a, a > 0xFF ? 4 : 2);
}

}  // namespace

Bq76pl455aChain::Bq76pl455aChain(const MonitorConfig& cfg, int cellCount, uint64_t seed)
    : cfg_(cfg),
      cells_(cellCount),
      dev_(static_cast<size_t>(cfg.devices)),
      errors_(cellCount, cfg.channel_gain_sd, cfg.channel_offset_sd_V, seed),
      noise_(deriveSeed(seed, 0x455)),
      comm_(deriveSeed(seed, 0x455C)) {
  const SecondaryProtection& p = cfg.secondary;
  const double lsb = cfg.cell_adc.lsb;
  int log2os = 0;
  while ((1 << log2os) < cfg.oversampling && log2os < static_cast<int>(PL455_OVERSMPL_MAX_LOG2)) ++log2os;
  for (int d = 0; d < cfg.devices; ++d) {
    Device& dv = dev_[static_cast<size_t>(d)];
    const size_t n = static_cast<size_t>(cellsOf(d)), nt = static_cast<size_t>(cfg.thermistors_per_device);
    dv.analog.size(cellsOf(d), cfg.thermistors_per_device);
    // The EEPROM as the scenario programmed it: today's secondary protection.
    auto& e = dv.eeprom;
    e[PL455_REG_SREV] = 0x0C;
    e[PL455_REG_OVERSMPL] = static_cast<uint8_t>(log2os);
    e[PL455_REG_NCHAN] = static_cast<uint8_t>(n);
    e[PL455_REG_DEVCONFIG] = static_cast<uint8_t>(PL455_DEVCONFIG_ADDR_SEL | (p.enabled ? PL455_DEVCONFIG_COMP_ENA : 0));
    set16(e, PL455_REG_COMCONFIG,
          static_cast<uint16_t>((1u << PL455_COMCONFIG_BAUD_SHIFT) | PL455_COMCONFIG_UART_EN | PL455_COMCONFIG_COMM_HIGH |
                                PL455_COMCONFIG_COMM_LOW | PL455_COMCONFIG_FAULT_HIGH | PL455_COMCONFIG_FAULT_LOW));
    set16(e, PL455_REG_FO_CTRL,
          p.enabled ? PL455_FAULT_SUM_CMPUV | PL455_FAULT_SUM_CMPOV | PL455_FAULT_SUM_AUXUV : 0);
    e[PL455_REG_COMP_UV] = compField(p.cuv_V, PL455_COMP_UV_BASE_MV);
    e[PL455_REG_COMP_OV] = compField(p.cov_V, PL455_COMP_OV_BASE_MV);
    // ADC checks: code < CELL_UV is under (v < cuv_V), code > CELL_OV is over (v > cov_V).
    set16(e, PL455_REG_CELL_UV, clampU16(std::ceil(p.cuv_V / lsb - 1e-9)));
    set16(e, PL455_REG_CELL_OV, clampU16(std::floor(p.cov_V / lsb + 1e-9)));
    const double hotCode = thermCodeIdeal(cfg.thermistor, p.ot_C, ThermistorFault::None);
    for (unsigned k = 0; k < PL455_AUX_INPUTS; ++k) {
      set16(e, PL455_REG_AUX_UV(k), k < nt ? clampU16(hotCode) : 0);
      set16(e, PL455_REG_AUX_OV(k), 0xFFFF);
    }
    // The part trips at the scenario's ot_C exactly; the register shows it rounded.
    for (size_t k = 0; k < PL455_AUX_INPUTS; ++k) dv.eepromHotCode[k] = k < nt ? hotCode : 0.0;
    powerUp(dv);
  }
}

int Bq76pl455aChain::cellsOf(int d) const {
  const int first = d * cfg_.cells_per_device;
  return std::max(0, std::min(cfg_.cells_per_device, cells_ - first));
}

void Bq76pl455aChain::powerUp(Device& dv) {
  dv.reg = dv.eeprom;  // faults, STATUS, CBENBL, ADDR and the command registers come up 0
  dv.addressed = dv.autoAddress = false;
  std::copy(std::begin(dv.eepromHotCode), std::end(dv.eepromHotCode), std::begin(dv.hotCode));
  dv.cov = dv.cuv = DebounceTimer{};
  for (DebounceTimer& h : dv.hot) h = DebounceTimer{};
  dv.balanceUntil_s = 0.0;
  dv.heard_s = 0.0;
  dv.held.fill(0);
  dv.pending.fill(0);
  dv.heldChannels = dv.pendingChannels = 0;
  dv.ready_s = -1.0;
  dv.compared = false;
}

// A conversion whose time has come becomes the held result; the ADC thresholds
// are checked on it.
void Bq76pl455aChain::settleDue(Device& dv) {
  dv.held = dv.pending;
  dv.heldChannels = dv.pendingChannels;
  dv.ready_s = -1.0;
  dv.reg[PL455_REG_STATUS] |= PL455_STATUS_DRDY;
  const uint16_t uvCode = get16(dv.reg, PL455_REG_CELL_UV), ovCode = get16(dv.reg, PL455_REG_CELL_OV);
  uint16_t uv = get16(dv.reg, PL455_REG_FAULT_UV), ov = get16(dv.reg, PL455_REG_FAULT_OV);
  const unsigned nchan = std::min<unsigned>(dv.reg[PL455_REG_NCHAN], 16);
  // The cells converted among the first nchan (bit c: cell c + 1, CHANNELS bit 16 + c).
  const uint32_t cells = (dv.heldChannels >> 16) & ((1u << nchan) - 1u);
  // Every cell slot's code against both thresholds at once (the other slots masked off).
  uint32_t over = 0, under = 0;
  codeWindowMasks16(dv.held.data() + 16, uvCode, ovCode, over, under);
  uv = static_cast<uint16_t>(uv | (under & cells));
  ov = static_cast<uint16_t>(ov | (over & cells));
  set16(dv.reg, PL455_REG_FAULT_UV, uv);
  set16(dv.reg, PL455_REG_FAULT_OV, ov);
}

// The secondary comparators, independent of the ADC: true pin voltages against
// COMP_UV / COMP_OV, the AUX inputs' code against AUXn_UV (an NTC reads low when
// hot, 0 when shorted), each latching after its delay. The conditions are evaluated
// again only after the pins or a register changed (compare); the debounce timers run
// at every call.
void Bq76pl455aChain::compare(Device& dv, int d) {
  const double ov_V = compVolts(dv.reg[PL455_REG_COMP_OV], PL455_COMP_OV_BASE_MV);
  const double uv_V = compVolts(dv.reg[PL455_REG_COMP_UV], PL455_COMP_UV_BASE_MV);
  uint32_t overAll = 0, underAll = 0;
  windowMasks(dv.analog.cell_V.data(), cellsOf(d), uv_V, ov_V, overAll, underAll);  // (up to 16 cells)
  const uint16_t over = static_cast<uint16_t>(overAll), under = static_cast<uint16_t>(underAll);
  uint16_t hot = 0;
  const int nt = std::min(cfg_.thermistors_per_device, static_cast<int>(PL455_AUX_INPUTS));
  for (int k = 0; k < nt; ++k) {
    const size_t ks = static_cast<size_t>(k);
    if (thermCodeBelow(cfg_.thermistor, dv.analog.therm_C[ks], dv.analog.therm_fault[ks], dv.hotCode[k], dv.thermCode[k]))
      hot = static_cast<uint16_t>(hot | (1u << k));
  }
  dv.over = over;
  dv.under = under;
  dv.hotMask = hot;
  dv.compared = true;
  // Still nothing present with the timers at rest: still nothing to do. Else one pass
  // with these conditions (which puts the timers of absent conditions at rest).
  dv.quiet = dv.quiet && over == 0 && under == 0 && hot == 0;
}

void Bq76pl455aChain::runComparatorsPass(Device& dv, int d, double t) {
  if (!dv.compared) compare(dv, d);
  // With no condition present a pass only puts the timers at rest; after one it does
  // nothing (DebounceTimer::held with a false condition), so it is skipped.
  if (dv.quiet) return;
  const SecondaryProtection& p = cfg_.secondary;
  if (dv.cov.held(t, dv.over != 0, p.cov_delay_s))
    set16(dv.reg, PL455_REG_FAULT_2OV, static_cast<uint16_t>(get16(dv.reg, PL455_REG_FAULT_2OV) | dv.over));
  if (dv.cuv.held(t, dv.under != 0, p.cuv_delay_s))
    set16(dv.reg, PL455_REG_FAULT_2UV, static_cast<uint16_t>(get16(dv.reg, PL455_REG_FAULT_2UV) | dv.under));
  const int nt = std::min(cfg_.thermistors_per_device, static_cast<int>(PL455_AUX_INPUTS));
  for (int k = 0; k < nt; ++k)
    if (dv.hot[k].held(t, (dv.hotMask >> k) & 1u, p.ot_delay_s))
      set16(dv.reg, PL455_REG_FAULT_AUX, static_cast<uint16_t>(get16(dv.reg, PL455_REG_FAULT_AUX) | PL455_FAULT_AUX_UV(k)));
  dv.quiet = dv.over == 0 && dv.under == 0 && dv.hotMask == 0;
}

// The communication timeout: no valid frame heard for the CTO fault time.
void Bq76pl455aChain::superviseLink(Device& dv, double t) {
  const uint8_t code = dv.reg[PL455_REG_CTO] & PL455_CTO_FAULT_MASK;
  if (code != 0 && t - dv.heard_s >= kCommTimeout_ms[code] * 1e-3 - 1e-12) dv.reg[PL455_REG_FAULT_SYS] |= PL455_FAULT_SYS_CTO;
}

double Bq76pl455aChain::dueOf(const Device& dv) {
  constexpr double kNever = std::numeric_limits<double>::infinity();
  // superviseLink trips once t - heard_s >= timeout (computed in doubles): not while t is
  // below heard_s + timeout - 1 us (rounding moves t - heard_s by picoseconds at most).
  constexpr double kLinkMargin_s = 1e-6;
  const uint8_t code = dv.reg[PL455_REG_CTO] & PL455_CTO_FAULT_MASK;
  const double link = code != 0 ? dv.heard_s + (kCommTimeout_ms[code] * 1e-3 - 1e-12) - kLinkMargin_s : kNever;
  const double landing = dv.ready_s < 0.0 ? kNever : dv.ready_s - 1e-12;
  const double expiring = get16(dv.reg, PL455_REG_CBENBL) != 0 ? dv.balanceUntil_s - 1e-9 : kNever;
  return std::min(link, std::min(landing, expiring));
}

void Bq76pl455aChain::settleAll(double t) {
  double due = std::numeric_limits<double>::infinity();
  for (Device& dv : dev_) {
    settle(dv, t);
    superviseLink(dv, t);
    // The balance timer runs on the device: CBENBL clears when it expires.
    if (get16(dv.reg, PL455_REG_CBENBL) != 0 && t >= dv.balanceUntil_s - 1e-9) set16(dv.reg, PL455_REG_CBENBL, 0);
    due = std::min(due, dueOf(dv));
  }
  dueAt_s_ = due;
}

void Bq76pl455aChain::runAllComparators(double t) {
  bool calm = true;
  for (int d = 0; d < cfg_.devices; ++d) {
    Device& dv = dev_[static_cast<size_t>(d)];
    runComparators(dv, d, t);
    calm = calm && comparatorsAtRest(dv);
  }
  calm_ = calm;
}

// A device's timed work (results, FAULT_UV/OV from them, FAULT_SYS, CBENBL) and its
// comparators (FAULT_2UV/2OV, FAULT_AUX, from the pins and thresholds) touch different
// registers, and no other device: all of the one, then all of the other, is the
// device-by-device order's outcome.
void Bq76pl455aChain::advance(double t) {
  if (t >= dueAt_s_) settleAll(t);
  if (!calm_) runAllComparators(t);
}

// The detail registers FAULT_UV .. FAULT_GPI fill 0x54..0x63, sixteen bytes, each of
// them in one of faultSummary()'s tests: all zero, the summary is 0.
static_assert(PL455_REG_FAULT_GPI + 1 - PL455_REG_FAULT_UV == 16, "the fault detail registers span 16 bytes");

uint16_t Bq76pl455aChain::faultSummary(const Device& dv) const {
  const auto& r = dv.reg;
  // The usual device, no fault: two loads and a test instead of ten (faultLine asks
  // twice a tick per device, a register read once more).
  uint64_t lo, hi;
  std::memcpy(&lo, &r[PL455_REG_FAULT_UV], 8);
  std::memcpy(&hi, &r[PL455_REG_FAULT_UV + 8], 8);
  if ((lo | hi) == 0) return 0;
  const uint16_t aux = get16(r, PL455_REG_FAULT_AUX);
  uint16_t s = 0;
  if (get16(r, PL455_REG_FAULT_UV)) s |= PL455_FAULT_SUM_UV;
  if (get16(r, PL455_REG_FAULT_OV)) s |= PL455_FAULT_SUM_OV;
  if (aux & 0x00FF) s |= PL455_FAULT_SUM_AUXUV;
  if (aux & 0xFF00) s |= PL455_FAULT_SUM_AUXOV;
  if (get16(r, PL455_REG_FAULT_2UV)) s |= PL455_FAULT_SUM_CMPUV;
  if (get16(r, PL455_REG_FAULT_2OV)) s |= PL455_FAULT_SUM_CMPOV;
  if (get16(r, PL455_REG_FAULT_COM)) s |= PL455_FAULT_SUM_COMM;
  if (r[PL455_REG_FAULT_SYS]) s |= PL455_FAULT_SUM_SYS;
  if (get16(r, PL455_REG_FAULT_DEV)) s |= PL455_FAULT_SUM_CHIP;
  if (r[PL455_REG_FAULT_GPI]) s |= PL455_FAULT_SUM_GPI;
  return s;
}

bool Bq76pl455aChain::faultLine() const {
  for (const Device& dv : dev_)
    if ((faultSummary(dv) & get16(dv.reg, PL455_REG_FO_CTRL)) != 0) return true;
  return false;
}

// Each device's summary bits routed to the FAULT output (FO_CTRL), by the data sheet's
// names; a system fault names the communication timeout where that is what it holds.
std::string Bq76pl455aChain::faultCause() const {
  static const struct {
    uint16_t bit;
    const char* name;
  } kBits[] = {
      {PL455_FAULT_SUM_UV, "UV (cell under-voltage)"},
      {PL455_FAULT_SUM_OV, "OV (cell over-voltage)"},
      {PL455_FAULT_SUM_AUXUV, "AUXUV (an AUX input below its limit: an NTC over temperature)"},
      {PL455_FAULT_SUM_AUXOV, "AUXOV (an AUX input above its limit: an NTC cold or open)"},
      {PL455_FAULT_SUM_CMPUV, "CMPUV (comparator under-voltage)"},
      {PL455_FAULT_SUM_CMPOV, "CMPOV (comparator over-voltage)"},
      {PL455_FAULT_SUM_COMM, "COMM (communication fault)"},
      {PL455_FAULT_SUM_SYS, "SYS (system fault)"},
      {PL455_FAULT_SUM_CHIP, "CHIP (device fault)"},
      {PL455_FAULT_SUM_GPI, "GPI (a GPIO fault input)"},
  };
  std::string out;
  for (size_t d = 0; d < dev_.size(); ++d) {
    const Device& dv = dev_[d];
    const uint16_t on = faultSummary(dv) & get16(dv.reg, PL455_REG_FO_CTRL);
    const bool cto = (dv.reg[PL455_REG_FAULT_SYS] & PL455_FAULT_SYS_CTO) != 0;
    std::string why;
    for (const auto& b : kBits)
      if (on & b.bit)
        appendListed(why, b.bit == PL455_FAULT_SUM_SYS && cto
                              ? "SYS (communication timeout: no valid frame from the host within it)"
                              : b.name);
    if (!why.empty()) appendListed(out, "device " + std::to_string(d + 1) + ": " + why, "; ");
  }
  return out;
}

bool Bq76pl455aChain::balancing(int d, int cell) const {
  return (get16(dev_[static_cast<size_t>(d)].reg, PL455_REG_CBENBL) >> cell) & 1u;
}

uint32_t Bq76pl455aChain::balancingMask(int d) const {
  return get16(dev_[static_cast<size_t>(d)].reg, PL455_REG_CBENBL) & ((1u << cellsOf(d)) - 1u);
}

// Write 1s to latched flags: a flag clears only when its condition is gone.
void Bq76pl455aChain::clearWritten(Device& dv, uint8_t addr, uint8_t bits) {
  auto& r = dv.reg;
  auto clear16 = [&](unsigned a, uint16_t mask) { set16(r, a, static_cast<uint16_t>(get16(r, a) & ~mask)); };
  if (addr == PL455_REG_FAULT_SUM || addr == PL455_REG_FAULT_SUM + 1) {
    const uint16_t g = static_cast<uint16_t>(addr == PL455_REG_FAULT_SUM ? bits << 8 : bits);
    if (g & PL455_FAULT_SUM_UV) set16(r, PL455_REG_FAULT_UV, 0);
    if (g & PL455_FAULT_SUM_OV) set16(r, PL455_REG_FAULT_OV, 0);
    if (g & PL455_FAULT_SUM_AUXUV)
      for (unsigned k = 0; k < PL455_AUX_INPUTS; ++k)
        if (!dv.hot[k].active()) clear16(PL455_REG_FAULT_AUX, PL455_FAULT_AUX_UV(k));
    if (g & PL455_FAULT_SUM_AUXOV) clear16(PL455_REG_FAULT_AUX, 0xFF00);
    if ((g & PL455_FAULT_SUM_CMPUV) && !dv.cuv.active()) set16(r, PL455_REG_FAULT_2UV, 0);
    if ((g & PL455_FAULT_SUM_CMPOV) && !dv.cov.active()) set16(r, PL455_REG_FAULT_2OV, 0);
    if (g & PL455_FAULT_SUM_COMM) set16(r, PL455_REG_FAULT_COM, 0);
    if (g & PL455_FAULT_SUM_SYS) r[PL455_REG_FAULT_SYS] = 0;
    if (g & PL455_FAULT_SUM_CHIP) set16(r, PL455_REG_FAULT_DEV, 0);
    if (g & PL455_FAULT_SUM_GPI) r[PL455_REG_FAULT_GPI] = 0;
    return;
  }
  // A detail register: comparator flags hold while their condition does.
  const bool cmpHeld = (addr == PL455_REG_FAULT_2UV || addr == PL455_REG_FAULT_2UV + 1) ? dv.cuv.active()
                       : (addr == PL455_REG_FAULT_2OV || addr == PL455_REG_FAULT_2OV + 1) ? dv.cov.active()
                                                                                           : false;
  if (addr == PL455_REG_FAULT_AUX + 1)
    for (unsigned k = 0; k < PL455_AUX_INPUTS; ++k)
      if (dv.hot[k].active()) bits = static_cast<uint8_t>(bits & ~PL455_FAULT_AUX_UV(k));
  if (!cmpHeld) r[addr] = static_cast<uint8_t>(r[addr] & ~bits);
}

// Sample the selected channels now; the result is held once the conversion time
// has passed. Noise draws in a fixed order: cells bottom up, module, AUX inputs.
template <class Round>
[[gnu::always_inline]] inline void Bq76pl455aChain::startSampleWith(Device& dv, int d, double t) {
  const uint32_t ch = get32(dv.reg, PL455_REG_CHANNELS);
  const int samples = 1 << std::min<unsigned>(dv.reg[PL455_REG_OVERSMPL] & PL455_OVERSMPL_LOG2_MASK, PL455_OVERSMPL_MAX_LOG2);
  dv.replySlots.select(ch);  // the reply's order, made here: its count is the channels selected
  const int selected = static_cast<int>(dv.replySlots.count());
  // cell_adc.noise_rms is the noise at the configured oversampling; the register's
  // setting averages more or fewer samples.
  AdcChannel base = cfg_.cell_adc;
  base.noise_rms *= std::sqrt(static_cast<double>(std::max(1, cfg_.oversampling)) / samples);
  dv.pending.fill(0);
  const int n = cellsOf(d), first = d * cfg_.cells_per_device;
  // The part samples with its balancing switches as they are; a host that opens them
  // around its conversions (measure_paused) has them read without their I_bal·R drop.
  const std::vector<double>& cell_V = dv.analog.cellsSeen(dv.analog.host_opens_balancing);
  for (int c = 0; c < n; ++c) {
    if ((ch & PL455_CH_CELL(static_cast<unsigned>(c + 1))) == 0) continue;
    const size_t cell = static_cast<size_t>(first + c), cs = static_cast<size_t>(c);
    dv.pending[static_cast<size_t>(16 + c)] =
        static_cast<uint16_t>(errors_.convert<Round>(base, cell, dv.analog, cs, cell_V[cs], noise_));
  }
  if (ch & PL455_CH_MODULE) {
    const double module_V = moduleVoltage(cell_V, cfg_.module_noise_V, noise_);
    dv.pending[6] = clampU16(module_V / (PL455_MODULE_FULL_SCALE_MV * 1e-3 / PL455_CODE_FULL_SCALE));
  }
  for (unsigned k = 0; k < PL455_AUX_INPUTS; ++k) {
    if ((ch & PL455_CH_AUX(k)) == 0 || static_cast<int>(k) >= cfg_.thermistors_per_device) continue;
    const size_t ks = static_cast<size_t>(k);
    const int64_t code =
        thermistorCode(cfg_.thermistor, dv.analog.therm_fault[ks], dv.analog.therm_C[ks], dv.thermCode[k], noise_);
    dv.pending[static_cast<size_t>(8 + k)] = static_cast<uint16_t>(code);
  }
  if (ch & PL455_CH_DIE_TEMP)
    dv.pending[7] = static_cast<uint16_t>(static_cast<int16_t>(std::clamp(std::nearbyint(dv.analog.die_C * 10.0), -32768.0, 32767.0)));
  dv.pendingChannels = ch;
  dv.ready_s = t + selected * samples * cfg_.conversion_s_per_channel;
  if (dv.analog.host_opens_balancing) dv.pauses.add(t, dv.ready_s, (1u << n) - 1u);
  dv.reg[PL455_REG_STATUS] = static_cast<uint8_t>(dv.reg[PL455_REG_STATUS] & ~PL455_STATUS_DRDY);
}

// The SSE4.1 build of startSample (round_even.hpp): the same body, its cells' rounding and
// the module's and die temperature's std::nearbyint the one instruction roundsd.
__attribute__((target("sse4.1"))) void Bq76pl455aChain::startSampleNative(Device& dv, int d, double t) {
  startSampleWith<RoundNearbyint>(dv, d, t);
}

void Bq76pl455aChain::write(Device& dv, int d, const Frame& f, double t, bool takesAddress) {
  for (unsigned i = 0; i < f.size; ++i) {
    const unsigned a = f.reg + i;
    if (a >= PL455_REG_COUNT) {
      misuse_.note(t, d, registerName(a), "write past the register map (0x00..0xFF)");
      break;
    }
    const uint8_t v = f.data[i];
    if (a == PL455_REG_ADDR) {  // only auto-addressing assigns an address
      if (takesAddress) dv.reg[a] = v, dv.addressed = true, dv.autoAddress = false;
      continue;
    }
    switch (access(a)) {
      case Access::ReadOnly: misuse_.note(t, d, registerName(a), "read-only register written"); break;
      case Access::ClearOnOne: clearWritten(dv, static_cast<uint8_t>(a), v); break;
      case Access::Stored: dv.reg[a] = v; break;
    }
  }
  auto touched = [&](unsigned a, unsigned size) { return f.reg < a + size && a < f.reg + f.size; };
  if (touched(PL455_REG_AUX_UV(0), PL455_REG_AUX_OV(PL455_AUX_INPUTS - 1) - PL455_REG_AUX_UV(0)))  // the AUX block
    for (unsigned k = 0; k < PL455_AUX_INPUTS; ++k)
      if (touched(PL455_REG_AUX_UV(k), 2)) dv.hotCode[k] = get16(dv.reg, PL455_REG_AUX_UV(k)), dv.compared = false;
  if (touched(PL455_REG_COMP_UV, 1) || touched(PL455_REG_COMP_OV, 1)) dv.compared = false;  // a threshold changed
  if (touched(PL455_REG_DEV_CTRL, 1)) {
    const uint8_t c = dv.reg[PL455_REG_DEV_CTRL];
    if (c & PL455_DEV_CTRL_RESET) return powerUp(dv);
    if (c & PL455_DEV_CTRL_AUTO_ADDRESS) dv.autoAddress = true, dv.addressed = false;
  }
  if (touched(PL455_REG_CBENBL, 2)) {
    const uint32_t code = (dv.reg[PL455_REG_CBCONFIG] & PL455_CBCONFIG_TIME_MASK) >> PL455_CBCONFIG_TIME_SHIFT;
    const unsigned has = (1u << cellsOf(d)) - 1u, written = get16(dv.reg, PL455_REG_CBENBL);
    if (written & ~has)
      misuse_.note(t, d, registerName(PL455_REG_CBENBL), balanceBitsPastCells(written & ~has, cellsOf(d), 4));
    const uint16_t mask = static_cast<uint16_t>(written & has);
    set16(dv.reg, PL455_REG_CBENBL, kBalanceTime_s[code] == 0 ? 0 : mask);
    dv.balanceUntil_s = t + kBalanceTime_s[code];
  }
  if (touched(PL455_REG_EE_BURN, 1) && dv.reg[PL455_REG_EE_BURN] == PL455_EE_BURN_GO) {
    dv.reg[PL455_REG_EE_BURN] = 0;
    const bool unlocked = get32(dv.reg, PL455_REG_MAGIC1) == PL455_MAGIC1_KEY && get32(dv.reg, PL455_REG_MAGIC2) == PL455_MAGIC2_KEY;
    if (!unlocked) misuse_.note(t, d, registerName(PL455_REG_EE_BURN), "EEPROM burn without the MAGIC1/MAGIC2 keys (refused)");
    if (unlocked)
      for (unsigned a = 0; a < PL455_REG_COUNT; ++a)
        if (inEeprom(a)) dv.eeprom[a] = dv.reg[a];
    if (unlocked) std::copy(std::begin(dv.hotCode), std::end(dv.hotCode), std::begin(dv.eepromHotCode));
  }
  if (touched(PL455_REG_CMD, 1) && dv.reg[PL455_REG_CMD] == PL455_CMD_SAMPLE) startSample(dv, d, t);
}

void Bq76pl455aChain::reply(Device& dv, int d, const Frame& f, double t, double& ready_s, Reply& out) {
  out.size = 0;
  out.push(0);
  ready_s = t;
  if (f.reg == PL455_REG_CMD) {
    // A sample request with response: the results once converted; SEND_HELD: as held now.
    const uint8_t cmd = f.size > 0 ? f.data[0] : PL455_CMD_SAMPLE;
    if (cmd == PL455_CMD_SAMPLE && acceptsWrites(d)) {
      startSample(dv, d, t);
      ready_s = dv.ready_s;
    }
    const bool fresh = cmd == PL455_CMD_SAMPLE && acceptsWrites(d);
    if (!fresh) settle(dv, t);
    const auto& values = fresh ? dv.pending : dv.held;
    const uint32_t ch = fresh ? dv.pendingChannels : dv.heldChannels;
    if ((ch & ~dv.channelsRead) != 0) {  // a slot not carried before (the usual reply: none, no call)
      dv.channelsRead |= ch;
      noteRead(d, ch >> 16, (ch >> 8) & 0xFFu);  // slots 16 + c: cell c; 8 + k: AUX k
    }
    // (the length counted in a local: a byte stored through out.bytes may alias out.size,
    // which push() would reload and store again for every byte)
    size_t n = out.size;
    dv.replySlots.select(ch);  // the selected slots, highest first
    const uint8_t* slot = dv.replySlots.slots();
    for (unsigned i = 0, count = dv.replySlots.count(); i < count; ++i, n += 2) {
      const uint16_t v = values[slot[i]];
      out.bytes[n] = static_cast<uint8_t>(v >> 8);
      out.bytes[n + 1] = static_cast<uint8_t>(v & 0xFF);
    }
    out.size = n;
  } else {
    settle(dv, t);
    set16(dv.reg, PL455_REG_FAULT_SUM, faultSummary(dv));
    const unsigned count = (f.size > 0 ? f.data[0] & 0x7Fu : 0u) + 1u;
    size_t n = out.size;
    for (unsigned i = 0; i < count; ++i) out.bytes[n++] = f.reg + i < PL455_REG_COUNT ? dv.reg[f.reg + i] : 0;
    out.size = n;
  }
  if (out.size == 1) {  // nothing selected: no reply
    out.size = 0;
    return;
  }
  out.bytes[0] = static_cast<uint8_t>(out.size - 2);
  const uint16_t crc = dv.replyCrc.of(out.bytes.data(), out.size);
  out.push(static_cast<uint8_t>(crc & 0xFF));
  out.push(static_cast<uint8_t>(crc >> 8));
  corrupt(dv, out);
}

// Comm faults act on the reply bytes: stuck drives every byte; a CRC error rate
// flips one bit with that probability (draws only where the rate is set).
void Bq76pl455aChain::corrupt(const Device& dv, Reply& out) {
  corruptReply(dv.comm, comm_, out.bytes.data(), out.size);
}

BusTransfer Bq76pl455aChain::transfer(double t, const uint8_t* tx, size_t txLen, uint8_t* rx, size_t rxLen) {
  const double byte_s = PL455_UART_BITS_PER_BYTE / cfg_.baud;
  double now = t + static_cast<double>(txLen) * byte_s;  // the command is in once its last byte is
  advance(now);
  size_t received = 0;
  bool expectReply = false;
  size_t pos = 0;
  Reply out;
  while (pos < txLen && (tx[pos] & PL455_INIT_COMMAND) != 0) {
    Frame f;
    const uint8_t init = tx[pos];
    f.req = init & PL455_REQ_MASK;
    const bool addressed = (f.req & ~0x10u) != PL455_REQ_BROADCAST_R;
    const size_t regBytes = (init & PL455_INIT_ADDR16) ? 2 : 1;
    f.size = PL455_SIZE_BYTES(init & PL455_INIT_SIZE_MASK);
    const size_t len = 1 + (addressed ? 1 : 0) + regBytes + f.size + 2;
    if (pos + len > txLen) break;  // a truncated frame: nobody acts on it
    const uint8_t* p = tx + pos + 1;
    if (addressed) f.address = *p++;
    f.reg = regBytes == 2 ? static_cast<uint16_t>((p[0] << 8) | p[1]) : p[0];
    f.data = p + regBytes;
    const uint16_t crc = bms::crcCrc16(tx + pos, len - 2);
    const bool crcOk = tx[pos + len - 2] == (crc & 0xFF) && tx[pos + len - 1] == (crc >> 8);
    pos += len;
    const bool withReply = (f.req & 0x10u) == 0;
    if (crcOk)  // a valid frame restarts every listening device's link supervision
      for (int d = 0; d < cfg_.devices; ++d)
        if (hears(d)) dev_[static_cast<size_t>(d)].heard_s = now;
    if (!crcOk) {  // dropped by every device that heard it, and flagged
      for (int d = 0; d < cfg_.devices; ++d) {
        Device& dv = dev_[static_cast<size_t>(d)];
        if (!acceptsWrites(d)) continue;
        misuse_.note(now, d, registerName(f.reg), "frame with a bad CRC (dropped, FAULT_COM UART_CRC set)");
        set16(dv.reg, PL455_REG_FAULT_COM, get16(dv.reg, PL455_REG_FAULT_COM) | PL455_FAULT_COM_UART_CRC);
      }
      expectReply = expectReply || withReply;
      continue;
    }
    // Auto-addressing: a broadcast ADDR write goes to the lowest device still waiting for one.
    int capture = -1;
    if (!withReply && !addressed && f.reg <= PL455_REG_ADDR && PL455_REG_ADDR < f.reg + f.size)
      for (int d = 0; d < cfg_.devices && capture < 0; ++d)
        if (acceptsWrites(d) && dev_[static_cast<size_t>(d)].autoAddress) capture = d;
    if (!withReply) {
      for (int d = 0; d < cfg_.devices; ++d)
        if (acceptsWrites(d) && addressedBy(f, d)) {
          write(dev_[static_cast<size_t>(d)], d, f, now, d == capture);
          noteWritten(dev_[static_cast<size_t>(d)]);
        }
      continue;
    }
    expectReply = true;
    // Every addressed device acts on the frame when it arrives; replies travel down
    // the chain one after the other, the top device's first.
    const double arrived_s = now;
    for (int d = cfg_.devices - 1; d >= 0; --d) {
      if (!hears(d) || !addressedBy(f, d)) continue;
      double ready_s = arrived_s;
      reply(dev_[static_cast<size_t>(d)], d, f, arrived_s, ready_s, out);
      noteReplied(dev_[static_cast<size_t>(d)]);
      if (out.size == 0) continue;
      now = std::max(now, ready_s) + static_cast<double>(out.size) * byte_s;
      const size_t take = std::min(out.size, rxLen - received);  // what still fits (received <= rxLen)
      if (take > 0) copyBytes(rx + received, out.bytes.data(), take);
      received += take;
    }
  }
  BusTransfer r;
  if (expectReply && received < rxLen) now += kResponseTimeout_s;  // the MCU waited for more
  r.received = expectReply && received == 0 && rxLen > 0 ? -1 : static_cast<int>(received);
  r.duration_s = now - t;
  return r;
}

// Each command frame of the transaction: its request type, address and register.
std::string Bq76pl455aChain::describe(const uint8_t* tx, size_t txLen, size_t) const {
  std::string out;
  size_t pos = 0;
  while (pos < txLen && (tx[pos] & PL455_INIT_COMMAND) != 0) {
    const uint8_t init = tx[pos];
    const uint8_t req = init & PL455_REQ_MASK;
    const bool addressed = (req & ~0x10u) != PL455_REQ_BROADCAST_R;
    const size_t regBytes = (init & PL455_INIT_ADDR16) ? 2 : 1;
    const size_t size = PL455_SIZE_BYTES(init & PL455_INIT_SIZE_MASK);
    const size_t len = 1 + (addressed ? 1 : 0) + regBytes + size + 2;
    if (pos + len > txLen) break;
    const uint8_t* p = tx + pos + 1;
    const int address = addressed ? *p++ : -1;
    const unsigned reg = regBytes == 2 ? static_cast<unsigned>((p[0] << 8) | p[1]) : p[0];
    const bool reply = (req & 0x10u) == 0;
    const std::string to = (req & ~0x10u) == PL455_REQ_SINGLE_R  ? " to device address " + std::to_string(address)
                           : (req & ~0x10u) == PL455_REQ_GROUP_R ? " to group " + std::to_string(address)
                                                                 : " (broadcast)";
    if (!out.empty()) out += "; ";
    const unsigned count = (size > 0 ? p[regBytes] & 0x7Fu : 0u) + 1u;
    out += (reply && reg == PL455_REG_CMD ? std::string("sample and read the channels")
            : reply                       ? "read " + registerName(reg) + " (" + std::to_string(count) + " bytes)"
                  : "write " + registerName(reg) + (size > 1 ? " (" + std::to_string(size) + " bytes)" : " = " + hexByte(p[regBytes]))) +
           to;
    pos += len;
  }
  return out.empty() ? "no command frame" : out;
}

int pl455CommTimeoutCode(double timeout_s) {
  for (unsigned k = 0; k < PL455_CTO_FAULT_CODES; ++k)
    if (std::fabs(timeout_s * 1e3 - kCommTimeout_ms[k]) < 1e-6) return static_cast<int>(k);
  return -1;
}

std::unique_ptr<MonitorChain> makeBq76pl455aChain(const MonitorConfig& cfg, int cellCount, uint64_t seed) {
  return std::make_unique<Bq76pl455aChain>(cfg, cellCount, seed);
}

}  // namespace packsim
