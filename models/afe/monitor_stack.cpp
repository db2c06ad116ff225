#include "models/afe/monitor_stack.hpp"

#include <algorithm>
#include <cmath>

#include <bms/bms_crc.hpp>
#include "models/pack/cell_spread.hpp"
#include "models/random/random.hpp"

namespace packsim {

double readoutTime_s(const MonitorConfig& c, int cells) {
  bms::AfeConfig a{c.model, 1, static_cast<uint8_t>(c.cells_per_device), static_cast<uint8_t>(c.thermistors_per_device),
                   c.crc, 5};
  const int bytes = bms::afeFrameLength(a, static_cast<uint16_t>(cells), 0);
  const int channels = cells + c.thermistors_per_device + 1;
  return channels * c.conversion_s_per_channel + bytes * 10.0 / c.baud;
}

double stackReadoutTime_s(const MonitorConfig& c, int cellCount) {
  MonitorConfig link = c;
  if (c.measurement_period_s > 0.0) link.conversion_s_per_channel = 0.0;
  double total = 0.0;
  for (int d = 0; d < c.devices; ++d) {
    const int cells = std::min(c.cells_per_device, cellCount - d * c.cells_per_device);
    total += readoutTime_s(link, cells);
  }
  return total;
}

bool MonitorStack::Timer::running(double t, bool cond, double delay) {
  if (!cond) {
    since = -1.0;
    return false;
  }
  if (since < 0.0) since = t;
  return t - since >= delay - 1e-9;
}

MonitorStack::MonitorStack(const MonitorConfig& cfg, int cellCount, uint64_t seed)
    : cfg_(cfg), cells_(cellCount), dev_(static_cast<size_t>(cfg.devices)) {
  // Per-channel errors are a property of the part: drawn once, from their own stream.
  Rng rng(deriveSeed(seed, RngStream::MonitorChannelErrors));
  gain_.assign(static_cast<size_t>(cellCount), 0.0);
  offset_.assign(static_cast<size_t>(cellCount), 0.0);
  for (int c = 0; c < cellCount; ++c) {
    if (cfg.channel_gain_sd > 0.0) gain_[static_cast<size_t>(c)] = cfg.channel_gain_sd * standardNormal(rng);
    if (cfg.channel_offset_sd_V > 0.0) offset_[static_cast<size_t>(c)] = cfg.channel_offset_sd_V * standardNormal(rng);
  }
}

int MonitorStack::cellsOf(int d) const {
  const int first = d * cfg_.cells_per_device;
  return std::max(0, std::min(cfg_.cells_per_device, cells_ - first));
}

MonitorTruth MonitorStack::makeTruth() const {
  MonitorTruth t;
  const size_t n = static_cast<size_t>(cells_);
  t.cell_V.assign(n, 0.0);
  t.cell_gain_error.assign(n, 0.0);
  t.cell_offset_V.assign(n, 0.0);
  t.board_C.assign(static_cast<size_t>(cfg_.devices), 25.0);
  t.therm_C.assign(static_cast<size_t>(thermistorChannels()), 25.0);
  t.therm_fault.assign(static_cast<size_t>(thermistorChannels()), ThermistorFault::None);
  t.comm.assign(static_cast<size_t>(cfg_.devices), MonitorDeviceFault{});
  return t;
}

bool MonitorStack::replies(int d, const MonitorTruth& truth) const {
  if (truth.broken_link_above >= 0 && d > truth.broken_link_above) return false;
  return !truth.comm[static_cast<size_t>(d)].silent;
}

bool MonitorStack::linkUp(int d, const MonitorTruth& truth) const {
  return replies(d, truth) && truth.comm[static_cast<size_t>(d)].stuck_byte < 0;
}

double MonitorStack::pinVoltage(int cell, double v, const MonitorTruth& truth) const {
  const size_t c = static_cast<size_t>(cell);
  return v * (1.0 + truth.cell_gain_error[c]) + truth.cell_offset_V[c];
}

void MonitorStack::hostWrite(double t, const bms::Outputs& out, const MonitorTruth& truth) {
  for (int d = 0; d < cfg_.devices; ++d) {
    if (!linkUp(d, truth)) continue;
    Device& dv = dev_[static_cast<size_t>(d)];
    if (out.afeClearFaults) {
      // Write 1 then 0 to the latch bits: only conditions that are gone clear.
      if (dv.cov.since < 0.0) dv.covLatched = false, dv.covCells = 0;
      if (dv.cuv.since < 0.0) dv.cuvLatched = false, dv.cuvCells = 0;
      for (int k = 0; k < bms::kMaxThermPerDevice; ++k)
        if (dv.ot[k].since < 0.0) dv.otLatched[k] = false;
    }
    // CB_CTRL + CB_TIME: written by the driver when the mask changes.
    uint32_t mask = 0;
    for (int c = 0; c < cellsOf(d); ++c) {
      const int cell = d * cfg_.cells_per_device + c;
      if (out.balanceMask[cell / 32] & (1u << (cell % 32))) mask |= 1u << c;
    }
    // CB_TIME alone: the host re-arms the timer (its arm count moved on).
    const bool rearm = out.balanceArmCount != dv.lastArmCount;
    dv.lastArmCount = out.balanceArmCount;
    if (mask != dv.lastMaskWritten || (rearm && mask != 0)) {
      dv.lastMaskWritten = mask;
      dv.balanceMask = static_cast<uint16_t>(mask);
      // 0–63 units of seconds, or of minutes beyond 63 s (rounded up), at most 63 min.
      const double req = std::max(1.0, static_cast<double>(out.balanceTime_s));
      const double dur = req <= 63.0 ? req : std::min(63.0, std::ceil(req / 60.0)) * 60.0;
      dv.balanceUntil_s = t + dur;
    }
    dv.fetEnabled = out.afeFetEnable;
    dv.hostChg = out.chargeFetOn;
    dv.hostDsg = out.dischargeFetOn;
    dv.hostPdsg = out.prechargeClose;
  }
}

void MonitorStack::updateSecondary(Device& dv, int d, double t, const MonitorTruth& truth) {
  const SecondaryProtection& p = cfg_.secondary;
  if (!p.enabled) return;
  // The comparators see the true pin voltage (they are not the ADC).
  uint16_t over = 0, under = 0;
  for (int c = 0; c < cellsOf(d); ++c) {
    const double v = truth.cell_V[static_cast<size_t>(d * cfg_.cells_per_device + c)];
    if (v > p.cov_V) over |= static_cast<uint16_t>(1u << c);
    if (v < p.cuv_V) under |= static_cast<uint16_t>(1u << c);
  }
  if (dv.cov.running(t, over != 0, p.cov_delay_s)) dv.covLatched = true, dv.covCells |= over;
  if (dv.cuv.running(t, under != 0, p.cuv_delay_s)) dv.cuvLatched = true, dv.cuvCells |= under;
  for (int k = 0; k < cfg_.thermistors_per_device; ++k) {
    const size_t ch = static_cast<size_t>(d * cfg_.thermistors_per_device + k);
    // A shorted NTC looks infinitely hot to the comparator; an open one cold.
    const ThermistorFault f = truth.therm_fault[ch];
    const bool hot = f == ThermistorFault::Short || (f == ThermistorFault::None && truth.therm_C[ch] > p.ot_C);
    if (dv.ot[k].running(t, hot, p.ot_delay_s)) dv.otLatched[k] = true;
  }
}

void MonitorStack::updateBq952(Device& dv, int d, double t, const MonitorTruth& truth) {
  const Bq952Protection& p = cfg_.bq;
  const int n = cellsOf(d);
  double vmax = -1e9, vmin = 1e9;
  for (int c = 0; c < n; ++c) {
    const int cell = d * cfg_.cells_per_device + c;
    const double v = pinVoltage(cell, dv.heldCell_V[static_cast<size_t>(c)], truth);
    vmax = std::max(vmax, v);
    vmin = std::min(vmin, v);
  }
  double tmax = -1e9, tmin = 1e9, tfet = -1e9;
  for (int k = 0; k < cfg_.thermistors_per_device; ++k) {
    const ThermistorFault f = dv.heldThermFault[static_cast<size_t>(k)];
    const double T = f == ThermistorFault::Open ? -273.0 : f == ThermistorFault::Short ? 1000.0 : dv.heldTherm_C[static_cast<size_t>(k)];
    if (k == 2) {
      tfet = T;  // TS3 sits on the FETs
      continue;
    }
    tmax = std::max(tmax, T);
    tmin = std::min(tmin, T);
  }
  const double shunt_mV = dv.heldCurrent_A * cfg_.shunt_ohm * 1e3;  // + discharge

  uint8_t alertA = 0, A = dv.bqStatusA, B = dv.bqStatusB;
  auto latchIf = [](uint8_t& reg, uint8_t bit, bool trip) {
    if (trip) reg = static_cast<uint8_t>(reg | bit);
  };
  auto clearIf = [](uint8_t& reg, uint8_t bit, bool recovered) {
    if (recovered) reg = static_cast<uint8_t>(reg & ~bit);
  };
  // Voltage: recovery by hysteresis.
  if (vmax > p.cov_V) alertA |= bms::kBqCov;
  latchIf(A, bms::kBqCov, dv.bqCov.running(t, vmax > p.cov_V, p.cov_delay_s));
  clearIf(A, bms::kBqCov, vmax < p.cov_V - p.cov_recovery_V);
  if (vmin < p.cuv_V) alertA |= bms::kBqCuv;
  latchIf(A, bms::kBqCuv, dv.bqCuv.running(t, vmin < p.cuv_V, p.cuv_delay_s));
  clearIf(A, bms::kBqCuv, vmin > p.cuv_V + p.cuv_recovery_V);
  // Current: recovery after a time with the condition gone.
  const uint8_t currentBits = bms::kBqOcc | bms::kBqOcd1 | bms::kBqScd;
  if (-shunt_mV > p.occ_mV) alertA |= bms::kBqOcc;
  if (shunt_mV > p.ocd1_mV) alertA |= bms::kBqOcd1;
  const uint8_t before = A & currentBits;
  latchIf(A, bms::kBqOcc, dv.bqOcc.running(t, -shunt_mV > p.occ_mV, p.occ_delay_s));
  latchIf(A, bms::kBqOcd1, dv.bqOcd1.running(t, shunt_mV > p.ocd1_mV, p.ocd1_delay_s));
  latchIf(A, bms::kBqScd, shunt_mV > p.scd_mV);
  if ((A & currentBits) != 0 && before == 0) dv.bqCurrentTrip_s = t;
  if ((A & currentBits) != 0 && t - dv.bqCurrentTrip_s >= p.current_recovery_s - 1e-9 &&
      std::fabs(shunt_mV) < std::min(p.occ_mV, p.ocd1_mV))
    A = static_cast<uint8_t>(A & ~currentBits);
  // Temperature: recovery by hysteresis.
  const double h = p.temp_recovery_C;
  latchIf(B, bms::kBqOtc, dv.bqOtc.running(t, tmax > p.otc_C, p.ot_delay_s));
  clearIf(B, bms::kBqOtc, tmax < p.otc_C - h);
  latchIf(B, bms::kBqOtd, dv.bqOtd.running(t, tmax > p.otd_C, p.ot_delay_s));
  clearIf(B, bms::kBqOtd, tmax < p.otd_C - h);
  latchIf(B, bms::kBqOtf, dv.bqOtf.running(t, tfet > p.otf_C, p.ot_delay_s));
  clearIf(B, bms::kBqOtf, tfet < p.otf_C - h);
  latchIf(B, bms::kBqUtc, dv.bqUtc.running(t, tmin < p.utc_C, p.ut_delay_s));
  clearIf(B, bms::kBqUtc, tmin > p.utc_C + h);
  latchIf(B, bms::kBqUtd, dv.bqUtd.running(t, tmin < p.utd_C, p.ut_delay_s));
  clearIf(B, bms::kBqUtd, tmin > p.utd_C + h);
  dv.bqAlertA = alertA;
  dv.bqStatusA = A;
  dv.bqStatusB = B;

  // Coulomb counter: one conversion every 250 ms.
  if (t - dv.ccLast_s >= 0.25 - 1e-9) {
    dv.cc_As += dv.heldCurrent_A * (t - dv.ccLast_s);
    dv.ccLast_s = t;
  }
}

void MonitorStack::update(double t, const MonitorTruth& truth) {
  for (int d = 0; d < cfg_.devices; ++d) {
    Device& dv = dev_[static_cast<size_t>(d)];
    // Readings refresh once per measurement loop (every read for the SPI/UART parts).
    if (dv.heldAt_s < 0.0 || t - dv.heldAt_s >= cfg_.measurement_period_s - 1e-9) {
      dv.heldAt_s = t;
      for (int c = 0; c < cellsOf(d); ++c)
        dv.heldCell_V[static_cast<size_t>(c)] = truth.cell_V[static_cast<size_t>(d * cfg_.cells_per_device + c)];
      for (int k = 0; k < cfg_.thermistors_per_device; ++k) {
        const size_t ch = static_cast<size_t>(d * cfg_.thermistors_per_device + k);
        dv.heldTherm_C[static_cast<size_t>(k)] = truth.therm_C[ch];
        dv.heldThermFault[static_cast<size_t>(k)] = truth.therm_fault[ch];
      }
      dv.heldCurrent_A = truth.current_A;
    }
    if (cfg_.model == bms::AfeModel::Bq76952)
      updateBq952(dv, d, t, truth);
    else
      updateSecondary(dv, d, t, truth);
  }
}

bool MonitorStack::deviceFault(int d) const {
  const Device& dv = dev_[static_cast<size_t>(d)];
  if (cfg_.model == bms::AfeModel::Bq76952) return dv.bqStatusA != 0 || dv.bqStatusB != 0;
  bool ot = false;
  for (bool b : dv.otLatched) ot = ot || b;
  return dv.covLatched || dv.cuvLatched || ot;
}

bool MonitorStack::faultLine() const {
  for (int d = 0; d < cfg_.devices; ++d)
    if (deviceFault(d)) return true;
  return false;
}

bool MonitorStack::dischargeAllowed() const {
  if (cfg_.model != bms::AfeModel::Bq76952) return true;
  const uint8_t blockA = bms::kBqCuv | bms::kBqOcd1 | bms::kBqOcd2 | bms::kBqScd;
  const uint8_t blockB = bms::kBqOtd | bms::kBqUtd | bms::kBqOtf;
  for (const Device& dv : dev_)
    if (!dv.fetEnabled || (dv.bqStatusA & blockA) || (dv.bqStatusB & blockB)) return false;
  return true;
}

bool MonitorStack::chargeAllowed() const {
  if (cfg_.model != bms::AfeModel::Bq76952) return true;
  const uint8_t blockA = bms::kBqCov | bms::kBqOcc | bms::kBqScd;
  const uint8_t blockB = bms::kBqOtc | bms::kBqUtc | bms::kBqOtf;
  for (const Device& dv : dev_)
    if (!dv.fetEnabled || (dv.bqStatusA & blockA) || (dv.bqStatusB & blockB)) return false;
  return true;
}

bool MonitorStack::balancing(int cell, double t) const {
  const int d = cell / cfg_.cells_per_device;
  const Device& dv = dev_[static_cast<size_t>(d)];
  return t < dv.balanceUntil_s - 1e-9 && (dv.balanceMask & (1u << (cell % cfg_.cells_per_device))) != 0;
}

void MonitorStack::read(double t, const MonitorTruth& truth, Rng& rng, bms::Inputs& in) {
  for (int d = 0; d < bms::kMaxDevices; ++d) in.afe[d].length = 0;
  // The stack's FET permissions (BQ76952 FET_STATUS), the same for every reply.
  const bool dsgOk = dischargeAllowed(), chgOk = chargeAllowed();
  for (int d = 0; d < cfg_.devices; ++d) {
    bms::AfeFrame& f = in.afe[d];
    const MonitorDeviceFault& c = truth.comm[static_cast<size_t>(d)];
    if (!replies(d, truth)) continue;  // timeout: length 0
    buildFrame(dev_[static_cast<size_t>(d)], d, t, truth, dsgOk, chgOk, rng, f);
    if (c.stuck_byte >= 0) {
      for (int i = 0; i < f.length; ++i) f.bytes[i] = static_cast<uint8_t>(c.stuck_byte);
    } else if (c.crc_error_rate > 0.0) {
      const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
      if (u < c.crc_error_rate) {
        const uint64_t r = rng();
        f.bytes[r % f.length] ^= static_cast<uint8_t>(1u << ((r >> 32) % 8));
      }
    }
  }
}

namespace {

void putBe16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v >> 8);
  p[1] = static_cast<uint8_t>(v & 0xFF);
}
void putLe16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v & 0xFF);
  p[1] = static_cast<uint8_t>(v >> 8);
}
void putLe32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>((v >> (8 * i)) & 0xFF);
}
uint16_t clampU16(double v) { return static_cast<uint16_t>(std::clamp(std::nearbyint(v), 0.0, 65535.0)); }
int16_t clampI16(double v) { return static_cast<int16_t>(std::clamp(std::nearbyint(v), -32768.0, 32767.0)); }

}  // namespace

void MonitorStack::buildFrame(const Device& dv, int d, double t, const MonitorTruth& truth, bool dsgOk, bool chgOk,
                              Rng& rng, bms::AfeFrame& f) const {
  const int n = cellsOf(d);
  const int first = d * cfg_.cells_per_device;
  // The cell ADC channel: the part's error + this channel's drawn error + injected.
  auto cellCode = [&](int c) {
    const size_t cell = static_cast<size_t>(first + c);
    AdcChannel a = cfg_.cell_adc;
    a.gain_error += gain_[cell] + truth.cell_gain_error[cell];
    a.offset += offset_[cell] + truth.cell_offset_V[cell];
    const double v = cfg_.model == bms::AfeModel::Bq76952 ? dv.heldCell_V[static_cast<size_t>(c)] : truth.cell_V[cell];
    return a.convert(v, rng);
  };
  double module_V = 0.0;
  for (int c = 0; c < n; ++c) module_V += truth.cell_V[static_cast<size_t>(first + c)];
  if (cfg_.module_noise_V > 0.0) module_V += cfg_.module_noise_V * standardNormal(rng);
  // The die sits on its board, away from the cells' cores: board + its own dissipation.
  const double die_C = truth.board_C[static_cast<size_t>(d)] + cfg_.die_rise_C;
  auto thermCode = [&](int k) -> uint16_t {
    const size_t ch = static_cast<size_t>(d * cfg_.thermistors_per_device + k);
    if (k >= cfg_.thermistors_per_device) return 0;
    if (truth.therm_fault[ch] == ThermistorFault::Open) return static_cast<uint16_t>(cfg_.thermistor.fullScaleCode());
    if (truth.therm_fault[ch] == ThermistorFault::Short) return 0;
    return static_cast<uint16_t>(cfg_.thermistor.code(truth.therm_C[ch], rng));
  };

  switch (cfg_.model) {
    case bms::AfeModel::Bq76pl536a: {
      f.length = bms::kPl536FrameLen;
      uint8_t* b = f.bytes;
      b[0] = static_cast<uint8_t>((d + 1) << 1);
      b[1] = 0x00;
      b[2] = bms::kPl536DataLen;
      uint8_t* p = b + 3;
      bool ot = false;
      uint8_t alert = 0;
      for (int k = 0; k < 2; ++k)
        if (dv.otLatched[k]) ot = true, alert |= static_cast<uint8_t>(k == 0 ? bms::kPl536Ot1 : bms::kPl536Ot2);
      const bool fault = dv.covLatched || dv.cuvLatched;
      const bool cbt = t < dv.balanceUntil_s - 1e-9 && dv.balanceMask != 0;
      p[bms::kPl536Status] = static_cast<uint8_t>(bms::kPl536Drdy | (cbt ? bms::kPl536Cbt : 0) |
                                                  (ot ? bms::kPl536AlertBit : 0) | (fault ? bms::kPl536FaultBit : 0));
      putBe16(p + bms::kPl536Gpai, clampU16(module_V / (6.0 * cfg_.cell_adc.lsb)));
      for (int c = 0; c < bms::kPl536CellSlots; ++c)
        putBe16(p + bms::kPl536Cell1 + 2 * c, c < n ? static_cast<uint16_t>(cellCode(c)) : 0);
      putBe16(p + bms::kPl536Temp1, thermCode(0));
      putBe16(p + bms::kPl536Temp2, thermCode(1));
      p[bms::kPl536Alert] = alert;
      p[bms::kPl536Fault] = static_cast<uint8_t>((dv.covLatched ? bms::kPl536Cov : 0) | (dv.cuvLatched ? bms::kPl536Cuv : 0));
      p[bms::kPl536CovCells] = static_cast<uint8_t>(dv.covCells & 0x3F);
      p[bms::kPl536CuvCells] = static_cast<uint8_t>(dv.cuvCells & 0x3F);
      putBe16(p + bms::kPl536DieTemp, static_cast<uint16_t>(clampI16(die_C * 10.0)));
      b[bms::kPl536FrameLen - 1] = bms::crcCrc8(b, bms::kPl536FrameLen - 1);
      break;
    }
    case bms::AfeModel::Bq76pl455a: {
      const uint8_t len = bms::pl455DataLen(static_cast<uint8_t>(n));
      f.length = bms::pl455FrameLen(static_cast<uint8_t>(n));
      uint8_t* b = f.bytes;
      b[0] = static_cast<uint8_t>(len - 1);
      uint8_t* p = b + 1;
      bool adcOv = false, adcUv = false;
      for (int c = 0; c < n; ++c) {
        const int64_t code = cellCode(c);
        const double v = static_cast<double>(code) * cfg_.cell_adc.lsb;
        adcOv = adcOv || v > cfg_.secondary.cov_V;
        adcUv = adcUv || v < cfg_.secondary.cuv_V;
        putBe16(p + 2 * c, static_cast<uint16_t>(code));
      }
      uint8_t* q = p + 2 * n;
      putBe16(q, clampU16(module_V / (100.0 / 65535.0)));
      putBe16(q + 2, thermCode(0));
      putBe16(q + 4, thermCode(1));
      putBe16(q + 6, static_cast<uint16_t>(clampI16(die_C * 10.0)));
      const bool ot = dv.otLatched[0] || dv.otLatched[1];
      const uint16_t summary = static_cast<uint16_t>((adcUv ? bms::kPl455Uv : 0) | (adcOv ? bms::kPl455Ov : 0) |
                                                     (dv.cuvLatched ? bms::kPl455CmpUv : 0) |
                                                     (dv.covLatched ? bms::kPl455CmpOv : 0) | (ot ? bms::kPl455AuxOv : 0));
      putBe16(q + 8, summary);
      const uint16_t crc = bms::crcCrc16(b, static_cast<size_t>(1 + len));
      b[1 + len] = static_cast<uint8_t>(crc & 0xFF);
      b[2 + len] = static_cast<uint8_t>(crc >> 8);
      break;
    }
    case bms::AfeModel::Bq76952: {
      const uint8_t len = bms::bq952DataLen(static_cast<uint8_t>(n));
      f.length = bms::bq952FrameLen(static_cast<uint8_t>(n), cfg_.crc);
      uint8_t* b = f.bytes;
      b[0] = len;
      uint8_t* p = b + 1;
      for (int c = 0; c < n; ++c) putLe16(p + 2 * c, static_cast<uint16_t>(clampI16(static_cast<double>(cellCode(c)) * cfg_.cell_adc.lsb * 1e3)));
      uint8_t* q = p + 2 * n;
      putLe16(q, clampU16(module_V * 100.0));
      // The device converts its thermistor codes itself; a rail reads 0 K (open) or
      // the top of the register (short).
      const Thermistor& th = cfg_.thermistor;
      for (int k = 0; k < 3; ++k) {
        uint16_t raw = 2982;  // unused input: 25 °C
        if (k < cfg_.thermistors_per_device) {
          const uint16_t code = thermCode(k);
          if (code == 0) raw = 0xFFFF;
          else if (code >= th.fullScaleCode()) raw = 0;
          else {
            const double ratio = static_cast<double>(code) / static_cast<double>(th.fullScaleCode());
            const double r = th.pullup_ohm * ratio / (1.0 - ratio);
            const double T_K = 1.0 / (1.0 / 298.15 + std::log(r / th.r25_ohm) / th.beta_K);
            raw = clampU16(T_K * 10.0);
          }
        }
        putLe16(q + 2 + 2 * k, raw);
      }
      putLe16(q + 8, clampU16((die_C + 273.15) * 10.0));
      putLe16(q + 10, static_cast<uint16_t>(clampI16(dv.heldCurrent_A * 100.0)));  // CC2 in 10 mA
      putLe32(q + 12, static_cast<uint32_t>(static_cast<int32_t>(std::nearbyint(dv.cc_As * 1e3))));
      q[16] = dv.bqAlertA;
      q[17] = dv.bqStatusA;
      q[18] = dv.bqStatusB;
      q[19] = static_cast<uint8_t>((dv.fetEnabled && dv.hostChg && chgOk ? bms::kBqChgFet : 0) |
                                   (dv.fetEnabled && dv.hostDsg && dsgOk ? bms::kBqDsgFet : 0) |
                                   (dv.fetEnabled && dv.hostPdsg && dsgOk ? bms::kBqPdsgFet : 0) |
                                   (deviceFault(d) ? bms::kBqAlrtPin : 0));
      if (cfg_.crc) b[1 + len] = bms::crcCrc8(b, static_cast<size_t>(1 + len));
      break;
    }
  }
}

}  // namespace packsim
