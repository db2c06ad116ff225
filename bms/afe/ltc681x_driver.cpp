#include "ltc681x_driver.hpp"

#include "ltc681x_pec.hpp"

namespace bms {

namespace {

bool is6813(const LtcConfig& c) { return c.part == LtcPart::Ltc6813; }
uint8_t partCells(const LtcConfig& c) { return is6813(c) ? LTC6813_CELLS : LTC6811_CELLS; }
uint8_t partGpios(const LtcConfig& c) { return is6813(c) ? LTC6813_GPIOS : LTC6811_GPIOS; }
uint8_t devicesOf(const LtcConfig& c) { return c.deviceCount < kLtcMaxDevices ? c.deviceCount : kLtcMaxDevices; }

uint8_t cellsOf(const LtcConfig& c, uint8_t d) {
  const int32_t left = static_cast<int32_t>(c.cellCount) - static_cast<int32_t>(d) * c.cellsPerDevice;
  if (left <= 0) return 0;
  return static_cast<uint8_t>(left < c.cellsPerDevice ? left : c.cellsPerDevice);
}

bool valid(const LtcConfig& c) {
  return c.deviceCount >= 1 && c.deviceCount <= kLtcMaxDevices && c.cellsPerDevice >= 1 &&
         c.cellsPerDevice <= partCells(c) && c.thermistorsPerDevice <= partGpios(c) &&
         ltc681x_mode_index(c.adcMode, c.adcopt ? 1u : 0u) >= 0;
}

int32_t xfer(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, const uint8_t* tx,
             uint16_t txLen, uint8_t* rx, uint16_t rxLen) {
  const int32_t got = api->bus_transfer(b, c.bus, tx, txLen, rx, rxLen);
  s.lastActivity_us = api->now_us(b);
  return got;
}

void ensureAwake(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api);

// Every frame goes out through ensureAwake: the time since the last one decides whether
// the chain must be woken first.
void command(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, uint16_t cc) {
  ensureAwake(c, s, b, api);
  uint8_t f[LTC681X_CMD_LEN] = {LTC681X_CMD0(cc), LTC681X_CMD1(cc), 0, 0};
  ltcPutPec(f, 2);
  xfer(c, s, b, api, f, LTC681X_CMD_LEN, nullptr, 0);
}

// A write command with one block per device: the farthest device's block first.
void writeGroup(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, uint16_t cc,
                const uint8_t (*image)[LTC681X_GROUP_BYTES]) {
  ensureAwake(c, s, b, api);
  uint8_t* f = s.tx;
  f[0] = LTC681X_CMD0(cc);
  f[1] = LTC681X_CMD1(cc);
  ltcPutPec(f, 2);
  const uint8_t n = devicesOf(c);
  for (uint8_t k = 0; k < n; ++k) {
    const uint8_t d = static_cast<uint8_t>(n - 1u - k);
    uint8_t* slot = f + LTC681X_CMD_LEN + k * LTC681X_SLOT_BYTES;
    for (uint8_t i = 0; i < LTC681X_GROUP_BYTES; ++i) slot[i] = image[d][i];
    ltcPutPec(slot, LTC681X_GROUP_BYTES);
  }
  xfer(c, s, b, api, f, static_cast<uint16_t>(LTC681X_CMD_LEN + n * LTC681X_SLOT_BYTES), nullptr, 0);
}

FrameResult worse(FrameResult a, FrameResult b) { return a != FrameResult::Ok ? a : b; }

// One read command for every device into s.group / s.groupRes (Ok: the data is there).
// Device 0's slot comes first. A group with a BadCrc somewhere is read again (up to
// readRetries).
void readGroup(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, uint16_t cc) {
  const uint8_t n = devicesOf(c);
  FrameResult* res = s.groupRes;
  for (uint8_t d = 0; d < n; ++d) res[d] = FrameResult::Timeout;
  for (uint8_t attempt = 0; attempt <= c.readRetries; ++attempt) {
    ensureAwake(c, s, b, api);
    uint8_t f[LTC681X_CMD_LEN] = {LTC681X_CMD0(cc), LTC681X_CMD1(cc), 0, 0};
    ltcPutPec(f, 2);
    const uint16_t rxLen = static_cast<uint16_t>(n * LTC681X_SLOT_BYTES);
    const int32_t got = xfer(c, s, b, api, f, LTC681X_CMD_LEN, s.rx, rxLen);
    bool retry = false;
    for (uint8_t d = 0; d < n; ++d) {
      if (res[d] == FrameResult::Ok) continue;  // a good copy from an earlier attempt
      const uint8_t* slot = s.rx + d * LTC681X_SLOT_BYTES;
      if (got == PSFW_BUS_TIMEOUT || got == PSFW_BUS_ERROR) {
        res[d] = FrameResult::Timeout;
        continue;
      }
      if (got < static_cast<int32_t>(rxLen)) {
        res[d] = FrameResult::BadLength;
        continue;
      }
      if (ltcPecOk(slot, LTC681X_GROUP_BYTES)) {
        for (uint8_t i = 0; i < LTC681X_GROUP_BYTES; ++i) s.group[d][i] = slot[i];
        res[d] = FrameResult::Ok;
        continue;
      }
      ++s.pecErrors[d];
      bool allOnes = true;  // nothing drove the line: the device did not answer
      for (uint8_t i = 0; i < LTC681X_SLOT_BYTES; ++i) allOnes = allOnes && slot[i] == 0xFFu;
      res[d] = allOnes ? FrameResult::Timeout : FrameResult::BadCrc;
      retry = retry || !allOnes;
    }
    if (!retry) break;
  }
}

uint16_t le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }

void writeConfig(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api) {
  writeGroup(c, s, b, api, LTC681X_WRCFGA, s.cfga);
  if (is6813(c)) writeGroup(c, s, b, api, LTC681X_WRCFGB, s.cfgb);
}

// Wakes whatever the time since the last transfer may have put to sleep: the cores after
// the watchdog (their configuration is gone: written again, the reference given its
// power-up time), the isoSPI ports after their idle time.
void ensureAwake(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api) {
  const uint32_t quiet_us = api->now_us(b) - s.lastActivity_us;
  const bool asleep = !s.woken || s.recover || quiet_us >= LTC681X_T_SLEEP_MIN_US;
  s.recover = false;
  if (!asleep && quiet_us < LTC681X_T_IDLE_MIN_US) return;
  const uint8_t pulse = 0xFFu;
  for (uint8_t d = 0; d < devicesOf(c); ++d) {  // one pulse per device: each wakes the next
    xfer(c, s, b, api, &pulse, 1, nullptr, 0);
    api->delay_us(b, asleep ? LTC681X_T_WAKE_US : LTC681X_T_READY_US);
  }
  if (!asleep) {
    ++s.idleWakeups;
    return;
  }
  ++s.sleepWakeups;
  s.woken = true;
  writeConfig(c, s, b, api);
  api->delay_us(b, LTC681X_T_REFUP_US);
  ensureAwake(c, s, b, api);  // the ports idled while the reference came up
}

void convertAndWait(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, uint16_t cc,
                    enum ltc681x_conversion kind) {
  command(c, s, b, api, cc);
  api->delay_us(b, ltcConversionTime_us(c, kind));
}

// The cell groups in use of every device into out[d].cell; res[d] the worst group.
void readCells(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, LtcReading* out,
               FrameResult* res) {
  static const uint16_t kGroups[6] = {LTC681X_RDCVA, LTC681X_RDCVB, LTC681X_RDCVC,
                                      LTC681X_RDCVD, LTC681X_RDCVE, LTC681X_RDCVF};
  const uint8_t n = devicesOf(c);
  for (uint8_t d = 0; d < n; ++d) res[d] = FrameResult::Ok;
  const uint8_t groups = static_cast<uint8_t>((c.cellsPerDevice + 2u) / 3u);
  for (uint8_t g = 0; g < groups; ++g) {
    readGroup(c, s, b, api, kGroups[g]);
    for (uint8_t d = 0; d < n; ++d) {
      res[d] = worse(res[d], s.groupRes[d]);
      if (s.groupRes[d] == FrameResult::Ok)
        for (uint8_t i = 0; i < 3; ++i) out[d].cell[3 * g + i] = le16(s.group[d] + 2 * i);
    }
  }
}

// RDSTATB: cells 1-12's UV / OV flags (CxUV in even, CxOV in odd bits of STBR2..4),
// THSD and MUXFAIL; the flags of cells 13-18 are cleared here, RDAUXD sets them.
void readStatusB(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, LtcReading* out,
                 FrameResult* res) {
  readGroup(c, s, b, api, LTC681X_RDSTATB);
  for (uint8_t d = 0; d < devicesOf(c); ++d) {
    const FrameResult r = s.groupRes[d];
    res[d] = worse(res[d], r);
    if (r != FrameResult::Ok) continue;
    const uint8_t* data = s.group[d];
    out[d].ov = out[d].uv = 0;
    for (uint8_t k = 0; k < 12; ++k) {
      const uint8_t byte = data[2 + k / 4], sh = static_cast<uint8_t>(2u * (k % 4u));
      out[d].uv |= static_cast<uint32_t>((byte >> sh) & 1u) << k;
      out[d].ov |= static_cast<uint32_t>((byte >> (sh + 1u)) & 1u) << k;
    }
    out[d].statb5 = data[5];
  }
}

// RDAUXD bytes 4-5: the LTC6813's cells 13-18 UV / OV flags.
void upperFlags(const uint8_t* data, LtcReading& out) {
  for (uint8_t k = 0; k < 6; ++k) {
    const uint8_t byte = data[4 + k / 4], sh = static_cast<uint8_t>(2u * (k % 4u));
    out.uv |= static_cast<uint32_t>((byte >> sh) & 1u) << (12u + k);
    out.ov |= static_cast<uint32_t>((byte >> (sh + 1u)) & 1u) << (12u + k);
  }
}

void fillImage(const LtcConfig& c, LtcState& s) {
  const uint16_t vuv = ltc681x_vuv_code(c.uv_mV), vov = ltc681x_vov_code(c.ov_mV);
  for (uint8_t d = 0; d < devicesOf(c); ++d) {
    uint8_t* a = s.cfga[d];
    a[0] = static_cast<uint8_t>(LTC681X_CFGR0_DEFAULT | LTC681X_CFGR0_REFON | (c.adcopt ? LTC681X_CFGR0_ADCOPT : 0u));
    a[1] = static_cast<uint8_t>(vuv & 0xFFu);
    a[2] = static_cast<uint8_t>(((vov & 0x0Fu) << 4) | ((vuv >> 8) & 0x0Fu));
    a[3] = static_cast<uint8_t>(vov >> 4);
    a[4] = 0;
    a[5] = 0;
    uint8_t* bb = s.cfgb[d];
    bb[0] = LTC6813_CFGRB0_DEFAULT;
    for (uint8_t i = 1; i < LTC681X_GROUP_BYTES; ++i) bb[i] = 0;
  }
}

}  // namespace

uint32_t ltcConversionTime_us(const LtcConfig& c, enum ltc681x_conversion kind) {
  return ltc681x_conversion_us(c.adcMode, c.adcopt ? 1u : 0u, kind, 1);
}

bool ltcInit(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api) {
  s.woken = false;
  s.recover = false;
  s.readout_us = 0;
  s.configured = 0;
  s.sleepWakeups = s.idleWakeups = s.readouts = 0;
  for (uint8_t d = 0; d < kLtcMaxDevices; ++d) s.pecErrors[d] = 0;
  if (!valid(c)) return false;
  fillImage(c, s);
  ensureAwake(c, s, b, api);  // wakes from SLEEP: writes the configuration, waits for the reference
  const uint8_t(*back)[LTC681X_GROUP_BYTES] = s.group;
  const FrameResult* res = s.groupRes;
  readGroup(c, s, b, api, LTC681X_RDCFGA);
  bool same[kMaxDevices];
  for (uint8_t d = 0; d < devicesOf(c); ++d) {
    same[d] = res[d] == FrameResult::Ok;
    for (uint8_t i = 0; i < LTC681X_GROUP_BYTES && same[d]; ++i) {
      uint8_t mask = 0xFFu;
      if (i == 0) mask = static_cast<uint8_t>(~LTC681X_CFGR0_DTEN);  // the DTEN pin, read only
      same[d] = (back[d][i] & mask) == (s.cfga[d][i] & mask);
    }
  }
  if (is6813(c)) {
    readGroup(c, s, b, api, LTC681X_RDCFGB);
    for (uint8_t d = 0; d < devicesOf(c); ++d)
      same[d] = same[d] && res[d] == FrameResult::Ok && back[d][0] == s.cfgb[d][0] &&
                (back[d][1] & ~LTC6813_CFGRB1_MUTE) == s.cfgb[d][1];
  }
  for (uint8_t d = 0; d < devicesOf(c); ++d) s.configured = static_cast<uint8_t>(s.configured + (same[d] ? 1u : 0u));
  return s.configured == c.deviceCount;
}

void ltcReadAll(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, LtcReading* out,
                FrameResult* res) {
  const uint8_t n = devicesOf(c);
  ++s.readouts;
  if (!valid(c)) {
    for (uint8_t d = 0; d < n; ++d) res[d] = FrameResult::BadHeader;
    return;
  }
  if (s.recover) {
    // A device failed the last read-out: it may have reset and lost its configuration.
    // Waking the chain, writing the configuration and waiting for the references takes
    // about as long as a read-out (5 ms of 7 at 7 kHz). Both in one call overran a 10 ms
    // read-out period on every call while a device stayed silent, and the firmware missed
    // its deadline instead of counting the device lost: the call reads as well only where
    // the last good read-out's length still fits the period, else it reads nothing and a
    // device still silent fails the next read-out.
    const uint32_t start_us = api->now_us(b);
    ensureAwake(c, s, b, api);
    const uint32_t spent_us = api->now_us(b) - start_us;
    if (s.readout_us == 0 || spent_us + s.readout_us > c.period_us) {
      for (uint8_t d = 0; d < n; ++d) res[d] = FrameResult::NotRead;
      return;
    }
  }
  const uint32_t readStart_us = api->now_us(b);
  const uint8_t md = c.adcMode;
  convertAndWait(c, s, b, api, ltc681x_adcv(md, c.dischargePermitted ? 1u : 0u, LTC681X_CH_ALL), LTC681X_CONV_CELLS);
  readCells(c, s, b, api, out, res);

  const uint8_t(*data)[LTC681X_GROUP_BYTES] = s.group;
  const FrameResult* r = s.groupRes;
  readStatusB(c, s, b, api, out, res);  // the UV / OV flags of that conversion

  // GPIOs: ADAX, then AUXA.. as far as the thermistors go, at least AUXB (the 2nd
  // reference, a check of the ADC). The LTC6813's cells 13-18 keep their UV/OV flags in
  // AUXD: read it whenever those cells are used, with or without GPIOs.
  const bool gpios = c.thermistorsPerDevice > 0;
  const bool highFlags = is6813(c) && c.cellsPerDevice > 12;
  if (gpios || highFlags) {
    static const uint16_t kAux[4] = {LTC681X_RDAUXA, LTC681X_RDAUXB, LTC681X_RDAUXC, LTC681X_RDAUXD};
    if (gpios) convertAndWait(c, s, b, api, ltc681x_adax(md, LTC681X_CH_ALL), LTC681X_CONV_GPIOS);
    // AUXA holds GPIO1-3, AUXB GPIO4-5 and REF (read in any case), AUXC GPIO6-8, AUXD GPIO9.
    const uint8_t t = c.thermistorsPerDevice;
    uint8_t groups = !gpios ? 0u : t <= 5u ? 2u : t <= 8u ? 3u : 4u;
    if (highFlags) groups = 4;
    for (uint8_t g = gpios ? 0u : 3u; g < groups; ++g) {
      readGroup(c, s, b, api, kAux[g]);
      for (uint8_t d = 0; d < n; ++d) {
        res[d] = worse(res[d], r[d]);
        if (r[d] != FrameResult::Ok) continue;
        if (g == 0) for (uint8_t i = 0; i < 3; ++i) out[d].gpio[i] = le16(data[d] + 2 * i);
        if (g == 1) {
          out[d].gpio[3] = le16(data[d]);
          out[d].gpio[4] = le16(data[d] + 2);
          out[d].ref = le16(data[d] + 4);
        }
        if (g == 2) for (uint8_t i = 0; i < 3; ++i) out[d].gpio[5 + i] = le16(data[d] + 2 * i);
        if (g == 3) {
          if (gpios) out[d].gpio[8] = le16(data[d]);
          upperFlags(data[d], out[d]);
        }
      }
    }
  }

  if (c.readStatus) {
    convertAndWait(c, s, b, api, ltc681x_adstat(md, LTC681X_CH_ALL), LTC681X_CONV_STATUS);
    readGroup(c, s, b, api, LTC681X_RDSTATA);
    for (uint8_t d = 0; d < n; ++d) {
      res[d] = worse(res[d], r[d]);
      if (r[d] != FrameResult::Ok) continue;
      out[d].sc = le16(data[d]);
      out[d].itmp = le16(data[d] + 2);
    }
  }
  for (uint8_t d = 0; d < n; ++d) s.recover = s.recover || res[d] != FrameResult::Ok;
  if (!s.recover) s.readout_us = api->now_us(b) - readStart_us;
}

void ltcPollFlags(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, LtcReading* out,
                  FrameResult* res) {
  const uint8_t n = devicesOf(c);
  if (!valid(c)) {
    for (uint8_t d = 0; d < n; ++d) res[d] = FrameResult::BadHeader;
    return;
  }
  for (uint8_t d = 0; d < n; ++d) res[d] = FrameResult::Ok;
  convertAndWait(c, s, b, api, ltc681x_adcv(c.adcMode, c.dischargePermitted ? 1u : 0u, LTC681X_CH_ALL),
                 LTC681X_CONV_CELLS);
  readStatusB(c, s, b, api, out, res);
  if (is6813(c) && c.cellsPerDevice > 12) {
    readGroup(c, s, b, api, LTC681X_RDAUXD);
    for (uint8_t d = 0; d < n; ++d) {
      res[d] = worse(res[d], s.groupRes[d]);
      if (s.groupRes[d] == FrameResult::Ok && res[d] == FrameResult::Ok) upperFlags(s.group[d], out[d]);
    }
  }
  for (uint8_t d = 0; d < n; ++d) s.recover = s.recover || res[d] != FrameResult::Ok;
}

void ltcSetBalance(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, const uint32_t* mask,
                   uint32_t time_s) {
  if (!valid(c)) return;
  const uint8_t dcto = ltc681x_dcto_code(time_s);
  for (uint8_t d = 0; d < devicesOf(c); ++d) {
    uint32_t bits = 0;
    for (uint8_t i = 0; i < cellsOf(c, d); ++i) {
      const uint16_t cell = static_cast<uint16_t>(d * c.cellsPerDevice + i);
      if (mask[cell / 32u] & (1u << (cell % 32u))) bits |= 1u << i;
    }
    s.cfga[d][4] = static_cast<uint8_t>(bits & 0xFFu);
    s.cfga[d][5] = static_cast<uint8_t>((dcto << LTC681X_DCTO_SHIFT) | ((bits >> 8) & 0x0Fu));
    s.cfgb[d][0] = static_cast<uint8_t>((s.cfgb[d][0] & 0x0Fu) | (((bits >> 12) & 0x0Fu) << 4));
    s.cfgb[d][1] = static_cast<uint8_t>((s.cfgb[d][1] & ~0x07u) | ((bits >> 16) & 0x03u));
  }
  writeConfig(c, s, b, api);
}

void ltcSetMute(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, bool mute) {
  if (!valid(c) || !is6813(c)) return;
  command(c, s, b, api, mute ? LTC681X_MUTE : LTC681X_UNMUTE);
}

void ltcOpenWireCheck(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, LtcReading* pullUp,
                      LtcReading* pullDown, uint32_t* openPins, FrameResult* res) {
  const uint8_t n = devicesOf(c);
  if (!valid(c)) {
    for (uint8_t d = 0; d < n; ++d) res[d] = FrameResult::BadHeader;
    return;
  }
  const uint8_t dcp = c.dischargePermitted ? 1u : 0u;
  FrameResult rUp[kMaxDevices];
  for (int k = 0; k < 2; ++k)  // "at least twice", with the pull-up current
    convertAndWait(c, s, b, api, ltc681x_adow(c.adcMode, 1u, dcp, LTC681X_CH_ALL), LTC681X_CONV_CELLS);
  readCells(c, s, b, api, pullUp, rUp);
  for (int k = 0; k < 2; ++k)
    convertAndWait(c, s, b, api, ltc681x_adow(c.adcMode, 0u, dcp, LTC681X_CH_ALL), LTC681X_CONV_CELLS);
  readCells(c, s, b, api, pullDown, res);
  for (uint8_t d = 0; d < n; ++d) {
    res[d] = worse(rUp[d], res[d]);
    openPins[d] = 0;
    const uint8_t cells = cellsOf(c, d);
    if (res[d] != FrameResult::Ok || cells == 0) continue;
    const uint16_t* pu = pullUp[d].cell;
    const uint16_t* pd = pullDown[d].cell;
    if (pu[0] == 0) openPins[d] |= 1u;  // C0
    for (uint8_t p = 1; p < cells; ++p)  // C(p): cell p+1 drops under the pull-up
      if (static_cast<int32_t>(pu[p]) - static_cast<int32_t>(pd[p]) < -LTC681X_OPEN_WIRE_CODES) openPins[d] |= 1u << p;
    if (pd[cells - 1] == 0) openPins[d] |= 1u << cells;  // the top pin
  }
}

bool ltcToDeviceReading(const LtcConfig& c, uint8_t d, const LtcReading& r, DeviceReading& out) {
  const uint8_t cells = cellsOf(c, d);
  if (c.cellsPerDevice > kMaxCellsPerDevice) return false;
  for (uint8_t i = 0; i < kMaxCellsPerDevice; ++i)
    out.cell_mV[i] = i < cells ? afeCellCodeToMv(r.cell[i], static_cast<float>(LTC681X_LSB_UV)) : 0;
  for (uint8_t k = 0; k < kMaxThermPerDevice; ++k) {
    out.thermCode[k] = k < c.thermistorsPerDevice && k < LTC681X_GPIOS_MAX ? r.gpio[k] : 0;
  }
  const uint32_t factor = is6813(c) ? LTC6813_SC_FACTOR : LTC6811_SC_FACTOR;
  out.stack_mV = (static_cast<uint32_t>(r.sc) * factor * LTC681X_LSB_UV + 500u) / 1000u;
  // die (0.1 degC) = ITMP · 100 uV / 7.6 mV/degC - 276 degC
  out.die_dC = static_cast<int16_t>(static_cast<int32_t>(r.itmp) * 10 / 76 - LTC681X_ITMP_OFFSET_C * 10);
  const uint32_t used = cells >= 32 ? 0xFFFFFFFFu : ((1u << cells) - 1u);
  out.alert = ((r.ov | r.uv) & used) != 0;
  out.fault = false;
  out.safetyA = static_cast<uint8_t>(r.ov & 0xFFu);
  out.safetyB = static_cast<uint8_t>(r.uv & 0xFFu);
  out.fetStatus = 0;
  out.current_mA = 0;
  out.charge_mAs = 0;
  return true;
}

}  // namespace bms
