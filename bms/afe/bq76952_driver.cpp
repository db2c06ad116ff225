#include "bq76952_driver.hpp"

#include "../bms_crc.hpp"

namespace bms {

namespace {

constexpr uint8_t kAddrW = static_cast<uint8_t>(BQ952_I2C_ADDR << 1);
constexpr uint8_t kAddrR = static_cast<uint8_t>(kAddrW | 1u);
constexpr uint16_t kScdThresholds_mV[BQ952_SCD_SETTINGS] = BQ952_SCD_THRESHOLDS_MV;
// A subcommand's reply block: 0x3E..0x61 (echo, buffer, checksum, length).
constexpr uint8_t kSubcmdBlock = BQ952_RESP_LENGTH - BQ952_SUBCMD_LOW + 1;
// The measurement block: cells 1..16, stack, PACK, LD, CC2 (0x14..0x3B).
constexpr uint8_t kMeasureBlock = BQ952_CC2_CURRENT + 2 - BQ952_CELL_VOLTAGE(1);
// Safety Alert A .. Safety Status C (0x02..0x07).
constexpr uint8_t kSafetyBlock = BQ952_SAFETY_STATUS_C + 1 - BQ952_SAFETY_ALERT_A;
constexpr uint8_t kMaxRead = kSubcmdBlock > kMeasureBlock ? kSubcmdBlock : kMeasureBlock;
constexpr uint8_t kMaxWrite = 2 + BQ952_TRANSFER_BUFFER_LEN;

// The safety block and FET_STATUS into the reading's protection flags.
void applySafety(const uint8_t* s, uint8_t fetStatus, DeviceReading& out) {
  const uint8_t alertA = s[0], statusA = s[1], alertB = s[2], statusB = s[3], statusC = s[5];
  out.safetyA = statusA;
  out.safetyB = statusB;
  out.fetStatus = fetStatus;
  out.fault = statusA != 0 || statusB != 0 || statusC != 0;
  out.alert = alertA != 0 || alertB != 0 || (fetStatus & BQ952_FET_ALRT_PIN) != 0;
}

uint16_t le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t le32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}
uint8_t crc1(uint8_t b) { return crcCrc8(&b, 1); }
int16_t clampI16(int32_t v) { return static_cast<int16_t>(v < -32768 ? -32768 : v > 32767 ? 32767 : v); }
// 0.1 K -> 0.1 degC (273.15 K, rounded half up)
int16_t kelvinToDc(uint16_t dK) { return clampI16(static_cast<int32_t>(dK) - 2731); }
uint8_t busOf(const Bq952DriverConfig& c, uint8_t d) { return static_cast<uint8_t>(c.firstBus + d); }

// One block read from a direct command: [addr][cmd] then n data bytes (each with its
// CRC in CRC mode). A bad CRC is retried.
FrameResult readDirect(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, uint8_t cmd, uint8_t* out, uint8_t n) {
  if (n > kMaxRead) return FrameResult::BadLength;
  const uint8_t tx[2] = {kAddrW, cmd};
  uint8_t rx[2 * kMaxRead];
  const uint16_t rxLen = static_cast<uint16_t>(c.crc ? 2 * n : n);
  FrameResult r = FrameResult::BadCrc;
  for (uint8_t attempt = 0; attempt <= c.crcRetries && r == FrameResult::BadCrc; ++attempt) {
    if (attempt > 0) ++drv.crcRetriesUsed;
    const int32_t got = drv.api->bus_transfer(drv.board, busOf(c, d), tx, 2, rx, rxLen);
    if (got < 0) return FrameResult::Timeout;
    if (got != rxLen) return FrameResult::BadLength;
    r = FrameResult::Ok;
    for (uint8_t k = 0; k < n; ++k) {
      if (c.crc) {
        const uint8_t first[4] = {kAddrW, cmd, kAddrR, rx[0]};
        const uint8_t want = k == 0 ? crcCrc8(first, 4) : crc1(rx[2 * k]);
        if (rx[2 * k + 1] != want) r = FrameResult::BadCrc;
        out[k] = rx[2 * k];
      } else {
        out[k] = rx[k];
      }
    }
  }
  return r;
}

// One write to a direct command, auto-incrementing: [addr][cmd][data...].
FrameResult writeDirect(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, uint8_t cmd, const uint8_t* data,
                        uint8_t n) {
  if (n > kMaxWrite) return FrameResult::BadLength;
  uint8_t tx[2 + 2 * kMaxWrite];
  tx[0] = kAddrW;
  tx[1] = cmd;
  uint16_t len = 2;
  for (uint8_t k = 0; k < n; ++k) {
    tx[len++] = data[k];
    if (c.crc) {
      const uint8_t first[3] = {kAddrW, cmd, data[0]};
      tx[len++] = k == 0 ? crcCrc8(first, 3) : crc1(data[k]);
    }
  }
  const int32_t got = drv.api->bus_transfer(drv.board, busOf(c, d), tx, len, nullptr, 0);
  return got < 0 ? FrameResult::Timeout : FrameResult::Ok;
}

uint8_t transferChecksum(uint16_t code, const uint8_t* data, uint8_t n) {
  uint32_t sum = (code & 0xFFu) + (code >> 8);
  for (uint8_t k = 0; k < n; ++k) sum += data[k];
  return static_cast<uint8_t>(~sum & 0xFFu);
}

// A subcommand without data (or the address of a read).
FrameResult subcommand(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, uint16_t code) {
  const uint8_t a[2] = {static_cast<uint8_t>(code & 0xFF), static_cast<uint8_t>(code >> 8)};
  const FrameResult r = writeDirect(drv, c, d, BQ952_SUBCMD_LOW, a, 2);
  drv.api->delay_us(drv.board, BQ952_SUBCMD_US);
  return r;
}

// A subcommand (or data-memory address) read: the echo at 0x3E/0x3F, the length and
// checksum at 0x60/0x61 frame the data like a header.
FrameResult subcommandRead(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, uint16_t code, uint8_t* out,
                           uint8_t n) {
  FrameResult r = subcommand(drv, c, d, code);
  if (r != FrameResult::Ok) return r;
  uint8_t b[kSubcmdBlock];
  r = readDirect(drv, c, d, BQ952_SUBCMD_LOW, b, kSubcmdBlock);
  if (r != FrameResult::Ok) return r;
  const uint8_t* data = b + (BQ952_TRANSFER_BUFFER - BQ952_SUBCMD_LOW);
  if (le16(b) != code) return FrameResult::BadHeader;
  const uint8_t length = b[BQ952_RESP_LENGTH - BQ952_SUBCMD_LOW];
  if (length < 4 + n || length > 4 + BQ952_TRANSFER_BUFFER_LEN) return FrameResult::BadLength;
  if (transferChecksum(code, data, static_cast<uint8_t>(length - 4)) != b[BQ952_RESP_CHECKSUM - BQ952_SUBCMD_LOW])
    return FrameResult::BadCrc;
  for (uint8_t k = 0; k < n; ++k) out[k] = data[k];
  return FrameResult::Ok;
}

// A subcommand (or data-memory) write: address + data, then checksum and length.
FrameResult subcommandWrite(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, uint16_t code,
                            const uint8_t* data, uint8_t n) {
  if (n > BQ952_TRANSFER_BUFFER_LEN) return FrameResult::BadLength;
  uint8_t w[kMaxWrite];
  w[0] = static_cast<uint8_t>(code & 0xFF);
  w[1] = static_cast<uint8_t>(code >> 8);
  for (uint8_t k = 0; k < n; ++k) w[2 + k] = data[k];
  FrameResult r = writeDirect(drv, c, d, BQ952_SUBCMD_LOW, w, static_cast<uint8_t>(2 + n));
  if (r != FrameResult::Ok) return r;
  const uint8_t tail[2] = {transferChecksum(code, data, n), static_cast<uint8_t>(4 + n)};
  r = writeDirect(drv, c, d, BQ952_RESP_CHECKSUM, tail, 2);
  drv.api->delay_us(drv.board, BQ952_SUBCMD_US);
  return r;
}

uint8_t nearestScd(uint16_t mV) {
  uint8_t best = 0;
  for (uint8_t k = 1; k < BQ952_SCD_SETTINGS; ++k) {
    const int32_t e = static_cast<int32_t>(kScdThresholds_mV[k]) - mV, eb = static_cast<int32_t>(kScdThresholds_mV[best]) - mV;
    if ((e < 0 ? -e : e) < (eb < 0 ? -eb : eb)) best = k;
  }
  return best;
}
// value / step, rounded, for unsigned firmware units
uint32_t steps(uint32_t value, float step) { return static_cast<uint32_t>(static_cast<float>(value) / step + 0.5f); }
uint32_t clampU(uint32_t v, uint32_t lo, uint32_t hi) { return v < lo ? lo : v > hi ? hi : v; }
// OCC / OCD1 delay setting: (n + 2) x 3.3 ms, n = 1..127
int32_t ocDelay(uint16_t ms) {
  const uint32_t n = steps(ms, BQ952_PROT_DELAY_LSB_MS);
  return static_cast<int32_t>(clampU(n > BQ952_OC_DELAY_OFFSET ? n - BQ952_OC_DELAY_OFFSET : 0, BQ952_OC_DELAY_MIN,
                                     BQ952_OC_DELAY_MAX));
}

constexpr uint8_t kMaxDmRows = 48;

struct DmRow {
  uint16_t address;
  uint8_t bytes;
  int32_t value;
};

// The data-memory image the configuration asks for: one row per setting.
uint8_t dmRows(const Bq952DriverConfig& c, DmRow* rows) {
  const Bq952ProtectionConfig& p = c.protection;
  const Bq952AutoBalanceConfig& b = c.autoBalance;
  const int8_t h = static_cast<int8_t>(p.tempRecovery_C);
  const DmRow table[] = {
      {BQ952_DM_DA_CONFIG, 1, 0x04 | (c.userAmps & 0x03)},
      {BQ952_DM_CB_INTERVAL, 1, c.balanceInterval_s},
      {BQ952_DM_COV_THRESHOLD, 1, static_cast<int32_t>(clampU(steps(p.cov_mV, BQ952_COV_CUV_LSB_MV), BQ952_COV_MIN, BQ952_COV_MAX))},
      {BQ952_DM_COV_DELAY, 2, static_cast<int32_t>(steps(p.covDelay_ms, BQ952_PROT_DELAY_LSB_MS))},
      {BQ952_DM_COV_RECOVERY_HYST, 1, static_cast<int32_t>(steps(p.covRecovery_mV, BQ952_COV_CUV_LSB_MV))},
      {BQ952_DM_CUV_THRESHOLD, 1, static_cast<int32_t>(clampU(steps(p.cuv_mV, BQ952_COV_CUV_LSB_MV), BQ952_CUV_MIN, BQ952_CUV_MAX))},
      {BQ952_DM_CUV_DELAY, 2, static_cast<int32_t>(steps(p.cuvDelay_ms, BQ952_PROT_DELAY_LSB_MS))},
      {BQ952_DM_CUV_RECOVERY_HYST, 1, static_cast<int32_t>(steps(p.cuvRecovery_mV, BQ952_COV_CUV_LSB_MV))},
      {BQ952_DM_OCC_THRESHOLD, 1, static_cast<int32_t>(clampU(steps(p.occ_mV, BQ952_OC_THRESHOLD_LSB_MV), BQ952_OCC_MIN, BQ952_OCC_MAX))},
      {BQ952_DM_OCC_DELAY, 1, ocDelay(p.occDelay_ms)},
      {BQ952_DM_OCD1_THRESHOLD, 1, static_cast<int32_t>(clampU(steps(p.ocd1_mV, BQ952_OC_THRESHOLD_LSB_MV), BQ952_OCD1_MIN, BQ952_OCD1_MAX))},
      {BQ952_DM_OCD1_DELAY, 1, ocDelay(p.ocd1Delay_ms)},
      {BQ952_DM_SCD_THRESHOLD, 1, nearestScd(p.scd_mV)},
      {BQ952_DM_SCD_RECOVERY_TIME, 1, p.currentRecovery_s},
      {BQ952_DM_PROT_RECOVERY_TIME, 1, p.currentRecovery_s},
      {BQ952_DM_OTC_THRESHOLD, 1, p.otc_C}, {BQ952_DM_OTC_DELAY, 1, p.otDelay_s}, {BQ952_DM_OTC_RECOVERY, 1, p.otc_C - h},
      {BQ952_DM_OTD_THRESHOLD, 1, p.otd_C}, {BQ952_DM_OTD_DELAY, 1, p.otDelay_s}, {BQ952_DM_OTD_RECOVERY, 1, p.otd_C - h},
      {BQ952_DM_OTF_THRESHOLD, 1, p.otf_C}, {BQ952_DM_OTF_DELAY, 1, p.otDelay_s}, {BQ952_DM_OTF_RECOVERY, 1, p.otf_C - h},
      {BQ952_DM_UTC_THRESHOLD, 1, p.utc_C}, {BQ952_DM_UTC_DELAY, 1, p.utDelay_s}, {BQ952_DM_UTC_RECOVERY, 1, p.utc_C + h},
      {BQ952_DM_UTD_THRESHOLD, 1, p.utd_C}, {BQ952_DM_UTD_DELAY, 1, p.utDelay_s}, {BQ952_DM_UTD_RECOVERY, 1, p.utd_C + h},
      {BQ952_DM_CB_CONFIG, 1, c.balancingConfig},
      {BQ952_DM_CB_MIN_CELL_TEMP, 1, b.minCellTemp_C},
      {BQ952_DM_CB_MAX_CELL_TEMP, 1, b.maxCellTemp_C},
      {BQ952_DM_CB_MAX_INT_TEMP, 1, b.maxIntTemp_C},
      {BQ952_DM_CB_MAX_CELLS, 1, b.maxCells},
      {BQ952_DM_CB_CHG_MIN_CELL_V, 2, b.minCell_mV}, {BQ952_DM_CB_CHG_MIN_DELTA, 1, b.startDelta_mV},
      {BQ952_DM_CB_CHG_STOP_DELTA, 1, b.stopDelta_mV},
      {BQ952_DM_CB_RLX_MIN_CELL_V, 2, b.minCell_mV}, {BQ952_DM_CB_RLX_MIN_DELTA, 1, b.startDelta_mV},
      {BQ952_DM_CB_RLX_STOP_DELTA, 1, b.stopDelta_mV},
  };
  static_assert(sizeof(table) / sizeof(table[0]) <= kMaxDmRows, "data-memory table larger than its buffer");
  const uint8_t n = static_cast<uint8_t>(sizeof(table) / sizeof(table[0]));
  for (uint8_t k = 0; k < n; ++k) rows[k] = table[k];
  return n;
}
void encodeRow(const DmRow& r, uint8_t* bytes) {
  const uint32_t v = static_cast<uint32_t>(r.value);
  bytes[0] = static_cast<uint8_t>(v & 0xFF);
  bytes[1] = static_cast<uint8_t>((v >> 8) & 0xFF);
}

}  // namespace

void bq952Init(Bq952Driver& drv, psfw_board* board, const psfw_board_api* api) {
  drv.board = board;
  drv.api = api;
  drv.crcRetriesUsed = 0;
  for (uint8_t d = 0; d < kMaxDevices; ++d) drv.dev[d] = Bq952DeviceState{0, 0, 0, 20};
}

uint8_t bq952CellsOf(const Bq952DriverConfig& c, uint8_t d) {
  const int32_t left = static_cast<int32_t>(c.cellCount) - static_cast<int32_t>(d) * c.cellsPerDevice;
  return static_cast<uint8_t>(left <= 0 ? 0 : left < c.cellsPerDevice ? left : c.cellsPerDevice);
}

FrameResult bq952Configure(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d) {
  uint8_t id[2];
  FrameResult r = subcommandRead(drv, c, d, BQ952_SUB_DEVICE_NUMBER, id, 2);
  if (r != FrameResult::Ok) return r;
  if (le16(id) != BQ952_DEVICE_NUMBER) return FrameResult::BadHeader;
  if (c.writeProtections) {
    DmRow rows[kMaxDmRows];
    const uint8_t n = dmRows(c, rows);
    // Data memory takes writes only in CONFIG_UPDATE mode.
    r = subcommand(drv, c, d, BQ952_SUB_SET_CFGUPDATE);
    for (uint8_t k = 0; k < n && r == FrameResult::Ok; ++k) {
      uint8_t bytes[2];
      encodeRow(rows[k], bytes);
      r = subcommandWrite(drv, c, d, rows[k].address, bytes, rows[k].bytes);
    }
    if (r == FrameResult::Ok) r = subcommand(drv, c, d, BQ952_SUB_EXIT_CFGUPDATE);
    if (r != FrameResult::Ok) return r;
    // Read every value back: a write the part refused (or lost) is a configuration fault.
    for (uint8_t k = 0; k < n; ++k) {
      uint8_t want[2], got[2];
      encodeRow(rows[k], want);
      r = subcommandRead(drv, c, d, rows[k].address, got, rows[k].bytes);
      if (r != FrameResult::Ok) return r;
      for (uint8_t b = 0; b < rows[k].bytes; ++b)
        if (got[b] != want[b]) return FrameResult::BadHeader;
    }
    drv.dev[d].interval_s = c.balanceInterval_s;
  }
  // Leave FET test mode.
  uint8_t mfg[2];
  r = subcommandRead(drv, c, d, BQ952_SUB_MANUFACTURING_STATUS, mfg, 2);
  if (r != FrameResult::Ok) return r;
  if ((le16(mfg) & BQ952_MFG_FET_EN) == 0) {
    r = subcommand(drv, c, d, BQ952_SUB_FET_ENABLE);
    if (r != FrameResult::Ok) return r;
  }
  return bq952ClearFaults(drv, c, d);
}

FrameResult bq952ClearFaults(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d) {
  const uint8_t all[2] = {0xFF, 0xFF};
  return writeDirect(drv, c, d, BQ952_ALARM_STATUS, all, 2);
}

FrameResult bq952Read(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, DeviceReading& out) {
  const uint8_t n = bq952CellsOf(c, d);
  const uint32_t userA_tenths_mA = BQ952_USER_AMPS_TENTHS_MA(c.userAmps & 0x03u);
  // Accumulated charge first: its echo/length/checksum catch a stuck or absent part
  // even without the CRC.
  uint8_t q[12];
  FrameResult r = subcommandRead(drv, c, d, BQ952_SUB_DASTATUS6, q, 12);
  if (r != FrameResult::Ok) return r;
  // A fresh measurement loop (FULLSCAN), if asked.
  uint8_t alarm[2];
  r = readDirect(drv, c, d, BQ952_ALARM_STATUS, alarm, 2);
  const uint32_t start_us = drv.api->now_us(drv.board);
  while (r == FrameResult::Ok && c.waitForScan && (le16(alarm) & BQ952_AL_FULLSCAN) == 0 &&
         drv.api->now_us(drv.board) - start_us < c.scanTimeout_us) {
    drv.api->delay_us(drv.board, BQ952_LOOP_SLOT_US);
    r = readDirect(drv, c, d, BQ952_ALARM_STATUS, alarm, 2);
  }
  if (r != FrameResult::Ok) return r;
  // Cells 1..16, stack, PACK, LD, CC2.
  uint8_t v[kMeasureBlock];
  r = readDirect(drv, c, d, BQ952_CELL_VOLTAGE(1), v, sizeof(v));
  if (r != FrameResult::Ok) return r;
  uint8_t s[kSafetyBlock];
  r = readDirect(drv, c, d, BQ952_SAFETY_ALERT_A, s, sizeof(s));
  if (r != FrameResult::Ok) return r;
  // Internal temperature .. FET Status.
  uint8_t t[BQ952_FET_STATUS + 1 - BQ952_INT_TEMPERATURE];
  r = readDirect(drv, c, d, BQ952_INT_TEMPERATURE, t, sizeof(t));
  if (r != FrameResult::Ok) return r;
  // This loop's results are taken: the next read-out waits for a new one.
  const uint8_t scan[2] = {static_cast<uint8_t>(BQ952_AL_FULLSCAN | BQ952_AL_ADSCAN), 0};
  r = writeDirect(drv, c, d, BQ952_ALARM_STATUS, scan, 2);
  if (r != FrameResult::Ok) return r;

  for (uint8_t k = 0; k < kMaxCellsPerDevice; ++k) {
    const int16_t mV = k < n ? static_cast<int16_t>(le16(v + 2 * k)) : 0;
    out.cell_mV[k] = static_cast<uint16_t>(mV < 0 ? 0 : mV);
  }
  for (uint8_t k = 0; k < kMaxThermPerDevice; ++k) {
    out.thermCode[k] = 0;
    out.temp_dC[k] = k < c.thermistorsPerDevice
                         ? kelvinToDc(le16(t + (BQ952_TS_TEMPERATURE(k) - BQ952_INT_TEMPERATURE)))
                         : static_cast<int16_t>(0);
  }
  out.stack_mV = static_cast<uint32_t>(le16(v + (BQ952_STACK_VOLTAGE - BQ952_CELL_VOLTAGE(1)))) * 10u;
  out.die_dC = kelvinToDc(le16(t));
  const int16_t cc2 = static_cast<int16_t>(le16(v + (BQ952_CC2_CURRENT - BQ952_CELL_VOLTAGE(1))));
  out.current_mA = -static_cast<int32_t>(cc2) * static_cast<int32_t>(userA_tenths_mA) / 10;
  // The cells and CC2 are one loop's; a loop that has not run since the last read-out
  // (FULLSCAN clear) is the same sample again. CC2 at an int16 rail is a current beyond
  // the register at this USER_AMPS, not the one the cells were under.
  out.sameLoop = (le16(alarm) & BQ952_AL_FULLSCAN) == 0;
  out.loopCurrent = cc2 != INT16_MAX && cc2 != INT16_MIN;
  // userAh (integer + 32-bit fraction) -> mA·s, positive in discharge
  const int64_t perUserAh_mAs = static_cast<int64_t>(userA_tenths_mA) * 360;
  const int64_t charge = static_cast<int64_t>(static_cast<int32_t>(le32(q))) * perUserAh_mAs +
                         ((static_cast<int64_t>(le32(q + 4)) * perUserAh_mAs) >> 32);
  out.charge_mAs = static_cast<int32_t>(-charge);
  applySafety(s, t[BQ952_FET_STATUS - BQ952_INT_TEMPERATURE], out);
  return FrameResult::Ok;
}

FrameResult bq952PollSafety(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, DeviceReading& io) {
  uint8_t s[kSafetyBlock];
  FrameResult r = readDirect(drv, c, d, BQ952_SAFETY_ALERT_A, s, sizeof(s));
  uint8_t fet = 0;
  if (r == FrameResult::Ok) r = readDirect(drv, c, d, BQ952_FET_STATUS, &fet, 1);
  if (r == FrameResult::Ok) applySafety(s, fet, io);
  return r;
}

FrameResult bq952SetBalance(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, uint16_t mask, uint32_t time_s) {
  Bq952DeviceState& s = drv.dev[d];
  const uint32_t now = drv.api->now_ms(drv.board);
  const uint8_t m[2] = {static_cast<uint8_t>(mask & 0xFF), static_cast<uint8_t>(mask >> 8)};
  const FrameResult r = subcommandWrite(drv, c, d, BQ952_SUB_CB_ACTIVE_CELLS, m, 2);
  if (r != FrameResult::Ok) return r;
  s.balanceMask = mask;
  s.balanceArmed_ms = now;
  s.balanceUntil_ms = now + time_s * 1000u;
  return r;
}

FrameResult bq952ServiceBalance(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d) {
  Bq952DeviceState& s = drv.dev[d];
  if (s.balanceMask == 0) return FrameResult::Ok;
  const uint32_t now = drv.api->now_ms(drv.board);
  if (static_cast<int32_t>(now - s.balanceUntil_ms) >= 0) return bq952SetBalance(drv, c, d, 0, 0);
  if (now - s.balanceArmed_ms < s.interval_s * 500u) return FrameResult::Ok;  // half the interval
  const uint32_t left_ms = s.balanceUntil_ms - now;
  const uint16_t mask = s.balanceMask;
  const FrameResult r = bq952SetBalance(drv, c, d, mask, 0);
  s.balanceUntil_ms = now + left_ms;
  return r;
}

FrameResult bq952SetFets(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, bool chargeOn, bool dischargeOn) {
  if (!chargeOn && !dischargeOn) return subcommand(drv, c, d, BQ952_SUB_ALL_FETS_OFF);
  FrameResult r = subcommand(drv, c, d, BQ952_SUB_ALL_FETS_ON);
  if (r == FrameResult::Ok && !chargeOn) r = subcommand(drv, c, d, BQ952_SUB_CHG_PCHG_OFF);
  if (r == FrameResult::Ok && !dischargeOn) r = subcommand(drv, c, d, BQ952_SUB_DSG_PDSG_OFF);
  return r;
}

}  // namespace bms
