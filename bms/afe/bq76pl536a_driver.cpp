#include "bq76pl536a_driver.hpp"

#include <cstring>

#include "../bms_crc.hpp"
#include "bq76pl536a_regs.h"

namespace bms {

namespace {

uint8_t addrOf(uint8_t d) { return static_cast<uint8_t>(d + 1u); }  // device d answers d + 1

// One write's frame: command, register, value, CRC.
void writeFrame(uint8_t (&f)[BQ536_WRITE_FRAME_LEN], uint8_t addr, uint8_t reg, uint8_t value) {
  f[0] = BQ536_FRAME_WRITE(addr);
  f[1] = reg;
  f[2] = value;
  f[3] = crcCrc8(f, 3);
}

void writeReg(const Bq536Config& c, psfw_board* b, const psfw_board_api* api, uint8_t addr, uint8_t reg,
              uint8_t value) {
  uint8_t f[BQ536_WRITE_FRAME_LEN];
  writeFrame(f, addr, reg, value);
  api->bus_transfer(b, c.bus, f, BQ536_WRITE_FRAME_LEN, nullptr, 0);
}

// The CRC over a read's exchange (request and `count` registers). The read-out's two
// reads have lengths known at build time: unrolled there (crcCrc8Fixed), some 50
// instructions a read-out less on a host than the general loop.
uint8_t exchangeCrc(const uint8_t* f, uint8_t count) {
  switch (count) {
    case BQ536_RESULTS_LEN: return crcCrc8Fixed<BQ536_READ_REQUEST_LEN + BQ536_RESULTS_LEN>(f);
    case BQ536_FLAGS_LEN: return crcCrc8Fixed<BQ536_READ_REQUEST_LEN + BQ536_FLAGS_LEN>(f);
    default: return crcCrc8(f, BQ536_READ_REQUEST_LEN + count);
  }
}

// One read's exchange as it travels: the request, then the registers and their CRC.
struct ReadFrame {
  uint8_t bytes[BQ536_READ_REQUEST_LEN + 32 + 1];
  const uint8_t* regs() const { return bytes + BQ536_READ_REQUEST_LEN; }  // the registers read
};

// One read of `count` registers (f.regs() on Ok); checks length and CRC over the
// exchange, repeating after a bad CRC up to crcRetries times. Inline: every caller
// passes a count known at build time, so its length checks and CRC fold to that count
// (the read-out's two reads: some 40 instructions a read-out less on a host).
__attribute__((always_inline)) inline FrameResult readRegs(const Bq536Config& c, Bq536State& s, psfw_board* b, const psfw_board_api* api, uint8_t addr,
                     uint8_t reg, uint8_t count, ReadFrame& frame) {
  uint8_t* const f = frame.bytes;
  if (count > 32) return FrameResult::BadLength;
  FrameResult r = FrameResult::BadCrc;
  for (uint8_t attempt = 0; attempt <= c.crcRetries; ++attempt) {
    if (attempt > 0) ++s.crcRetries;
    f[0] = BQ536_FRAME_READ(addr);
    f[1] = reg;
    f[2] = count;
    const int32_t got = api->bus_transfer(b, c.bus, f, BQ536_READ_REQUEST_LEN, f + BQ536_READ_REQUEST_LEN,
                                          static_cast<uint16_t>(count + 1u));
    if (got == PSFW_BUS_TIMEOUT || got == PSFW_BUS_ERROR) return FrameResult::Timeout;
    if (got != count + 1) return FrameResult::BadLength;
    if (exchangeCrc(f, count) != f[BQ536_READ_REQUEST_LEN + count]) {
      r = FrameResult::BadCrc;
      continue;
    }
    return FrameResult::Ok;
  }
  return r;
}

// The same into data (count bytes, written on Ok only).
FrameResult readRegs(const Bq536Config& c, Bq536State& s, psfw_board* b, const psfw_board_api* api, uint8_t addr,
                     uint8_t reg, uint8_t count, uint8_t* data) {
  ReadFrame f;
  const FrameResult r = readRegs(c, s, b, api, addr, reg, count, f);
  if (r == FrameResult::Ok) std::memcpy(data, f.regs(), count);
  return r;
}

uint16_t be16(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }

uint8_t cellsOf(const Bq536Config& c, uint8_t d) {
  const int32_t left = static_cast<int32_t>(c.cellCount) - static_cast<int32_t>(d) * c.cellsPerDevice;
  if (left <= 0) return 0;
  return static_cast<uint8_t>(left < c.cellsPerDevice ? left : c.cellsPerDevice);
}

// Devices the driver serves: the configured count, at most one per stack address.
uint8_t devicesOf(const Bq536Config& c) {
  const uint8_t cap = BQ536_ADDR_MAX < kMaxDevices ? static_cast<uint8_t>(BQ536_ADDR_MAX) : kMaxDevices;
  return c.deviceCount < cap ? c.deviceCount : cap;
}

uint8_t channelsOf(const Bq536Config& c) {
  return static_cast<uint8_t>(c.cellsPerDevice + 1u + c.thermistorsPerDevice);  // cells, GPAI, TSx
}

// The CONFIG_COV..CONFIG_OTT image the firmware wants in every device.
void configImage(const Bq536Config& c, uint8_t* e) {
  const uint8_t off = c.protectionEnabled ? 0u : static_cast<uint8_t>(BQ536_CONFIG_DISABLE);
  e[0] = static_cast<uint8_t>(off | bq536_cov_code(c.cov_mV));
  e[1] = bq536_delay_code(c.covDelay_us);
  e[2] = static_cast<uint8_t>(off | bq536_cuv_code(c.cuv_mV));
  e[3] = bq536_delay_code(c.cuvDelay_us);
  const uint8_t ot = bq536_ot_code(c.ot_C);
  uint8_t otReg = 0;
  if (c.protectionEnabled && c.thermistorsPerDevice >= 1) otReg = ot;
  if (c.protectionEnabled && c.thermistorsPerDevice >= 2) otReg = static_cast<uint8_t>(otReg | (ot << 4));
  e[4] = otReg;
  e[5] = bq536_ott_code(c.otDelay_ms);
}

constexpr uint8_t kConfigCount = BQ536_CONFIG_OTT + 1u - BQ536_CONFIG_COV;

// ALERT_STATUS .. CUV_FAULT into the reading: the protections' latches (POR/AR/CRC are
// housekeeping, not a cell fault).
void applyFlags(const uint8_t* flags, DeviceReading& o) {
  const uint8_t alert = flags[BQ536_ALERT_STATUS - BQ536_FLAGS_FIRST];
  const uint8_t fault = flags[BQ536_FAULT_STATUS - BQ536_FLAGS_FIRST];
  o.alert = (alert & (BQ536_AS_OT1 | BQ536_AS_OT2)) != 0;
  o.fault = o.alert || (fault & (BQ536_FS_COV | BQ536_FS_CUV)) != 0;
  o.safetyA = fault;
  o.safetyB = alert;
}

}  // namespace

bool bq536Init(const Bq536Config& c, Bq536State& s, psfw_board* b, const psfw_board_api* api) {
  s.addressed = 0;
  s.configured = 0;
  writeFrame(s.convertFrame, BQ536_ADDR_BROADCAST, BQ536_ADC_CONVERT, BQ536_CONV_START);
  // 1. Every device back to address 0 (only addressed devices pass the frame on, so a
  //    stack that is already addressed resets top to bottom in one frame).
  writeReg(c, b, api, BQ536_ADDR_BROADCAST, BQ536_RESET, BQ536_RESET_KEY);
  // 2. Bottom-up: the lowest unaddressed device answers address 0 and takes the next one.
  for (uint8_t d = 0; d < devicesOf(c); ++d) {
    writeReg(c, b, api, BQ536_ADDR_DISCOVERY, BQ536_ADDRESS_CONTROL, addrOf(d));
    uint8_t got = 0;
    if (readRegs(c, s, b, api, addrOf(d), BQ536_ADDRESS_CONTROL, 1, &got) != FrameResult::Ok) break;
    if (got != static_cast<uint8_t>(addrOf(d) | BQ536_ADDR_ASSIGNED)) break;
    ++s.addressed;
  }
  // 3. Housekeeping latches of the reset (write 1 then 0), measurement set-up.
  bq536ClearFaults(c, b, api);
  const uint8_t io = static_cast<uint8_t>((c.thermistorsPerDevice >= 1 ? BQ536_IO_TS1 : 0u) |
                                          (c.thermistorsPerDevice >= 2 ? BQ536_IO_TS2 : 0u));
  writeReg(c, b, api, BQ536_ADDR_BROADCAST, BQ536_IO_CONTROL, io);
  for (uint8_t d = 0; d < s.addressed; ++d) {
    const uint8_t cells = cellsOf(c, d);
    const uint8_t adc = static_cast<uint8_t>(BQ536_AC_ADC_ON | BQ536_AC_GPAI |
                                             (c.thermistorsPerDevice >= 1 ? BQ536_AC_TS1 : 0u) |
                                             (c.thermistorsPerDevice >= 2 ? BQ536_AC_TS2 : 0u) |
                                             ((cells > 0 ? cells - 1u : 0u) & BQ536_AC_CELL_SEL_MASK));
    writeReg(c, b, api, addrOf(d), BQ536_ADC_CONTROL, adc);
  }
  // 4. The comparators' thresholds and delays: each protected write behind its key.
  uint8_t image[kConfigCount];
  configImage(c, image);
  for (uint8_t i = 0; i < kConfigCount; ++i) {
    writeReg(c, b, api, BQ536_ADDR_BROADCAST, BQ536_SHDW_CTRL, BQ536_SHDW_KEY);
    writeReg(c, b, api, BQ536_ADDR_BROADCAST, static_cast<uint8_t>(BQ536_CONFIG_COV + i), image[i]);
  }
  for (uint8_t d = 0; d < s.addressed; ++d) {
    uint8_t back[kConfigCount];
    if (readRegs(c, s, b, api, addrOf(d), BQ536_CONFIG_COV, kConfigCount, back) != FrameResult::Ok) continue;
    bool same = true;
    for (uint8_t i = 0; i < kConfigCount; ++i) same = same && back[i] == image[i];
    if (same) ++s.configured;
  }
  return c.deviceCount <= devicesOf(c) && s.addressed == c.deviceCount && s.configured == c.deviceCount;
}

void bq536ReadAll(const Bq536Config& c, Bq536State& s, psfw_board* b, const psfw_board_api* api,
                  DeviceReading* out, FrameResult* res) {
  ++s.readouts;
  api->bus_transfer(b, c.bus, s.convertFrame, BQ536_WRITE_FRAME_LEN, nullptr, 0);  // ADC_CONVERT, broadcast
  const uint32_t conv_us = static_cast<uint32_t>(channelsOf(c)) * c.conversionPerChannel_us;
  api->delay_us(b, conv_us);
  for (uint8_t d = 0; d < devicesOf(c); ++d) {
    // Decoded where they arrived (no copy of the registers).
    ReadFrame results, flagFrame;
    const uint8_t* const v = results.regs();
    const uint8_t* const flags = flagFrame.regs();
    FrameResult r = readRegs(c, s, b, api, addrOf(d), BQ536_RESULTS_FIRST, BQ536_RESULTS_LEN, results);
    if (r == FrameResult::Ok && !(v[0] & BQ536_DS_DRDY)) {
      // Not converted yet: one more conversion time, then the device must be ready.
      api->delay_us(b, conv_us);
      r = readRegs(c, s, b, api, addrOf(d), BQ536_RESULTS_FIRST, BQ536_RESULTS_LEN, results);
      if (r == FrameResult::Ok && !(v[0] & BQ536_DS_DRDY)) r = FrameResult::Timeout;
    }
    // A device that answers without its address (after a reset) is not the one asked.
    if (r == FrameResult::Ok && !(v[0] & BQ536_DS_ADDR_RQST)) r = FrameResult::BadHeader;
    if (r == FrameResult::Ok) r = readRegs(c, s, b, api, addrOf(d), BQ536_FLAGS_FIRST, BQ536_FLAGS_LEN, flagFrame);
    res[d] = r;
    if (r != FrameResult::Ok) continue;

    DeviceReading& o = out[d];
    const uint8_t cells = cellsOf(c, d);
    const uint8_t n = cells < kMaxCellsPerDevice ? cells : kMaxCellsPerDevice;
    // Every slot zeroed in a few wide stores, then the device's cells (the slots past
    // them one by one were two instructions each).
    std::memset(o.cell_mV, 0, sizeof o.cell_mV);
    for (uint8_t i = 0; i < n; ++i) o.cell_mV[i] = afeCellCodeToMv(be16(v + BQ536_VCELL(i)), c.cellLsb_uV);
    // Codes through afeSetThermCodes: an input reading the same code keeps the core's
    // conversion of it (nearly every read-out: a thermistor moves slowly).
    const uint16_t codes[kMaxThermPerDevice] = {be16(v + BQ536_TEMPERATURE1), be16(v + BQ536_TEMPERATURE2)};
    afeSetThermCodes(o, codes);
    o.stack_mV = static_cast<uint32_t>(static_cast<float>(be16(v + BQ536_GPAI)) * c.cellLsb_uV *
                                           static_cast<float>(BQ536_GPAI_CELL_LSBS) * 0.001f +
                                       0.5f);
    o.die_dC = 0;  // the part has no die-temperature result (only the TSD flag)
    applyFlags(flags, o);
    o.fetStatus = 0;
    o.current_mA = 0;
    o.charge_mAs = 0;
  }
}

void bq536PollFlags(const Bq536Config& c, Bq536State& s, psfw_board* b, const psfw_board_api* api, DeviceReading* io,
                    FrameResult* res) {
  for (uint8_t d = 0; d < devicesOf(c); ++d) {
    uint8_t flags[BQ536_FLAGS_LEN];
    res[d] = readRegs(c, s, b, api, addrOf(d), BQ536_FLAGS_FIRST, BQ536_FLAGS_LEN, flags);
    if (res[d] == FrameResult::Ok) applyFlags(flags, io[d]);
  }
}

void bq536ClearFaults(const Bq536Config& c, psfw_board* b, const psfw_board_api* api) {
  const uint8_t faultBits = BQ536_FS_COV | BQ536_FS_CUV | BQ536_FS_CRC | BQ536_FS_POR;
  const uint8_t alertBits = BQ536_AS_OT1 | BQ536_AS_OT2 | BQ536_AS_AR;
  writeReg(c, b, api, BQ536_ADDR_BROADCAST, BQ536_FAULT_STATUS, faultBits);
  writeReg(c, b, api, BQ536_ADDR_BROADCAST, BQ536_FAULT_STATUS, 0);
  writeReg(c, b, api, BQ536_ADDR_BROADCAST, BQ536_ALERT_STATUS, alertBits);
  writeReg(c, b, api, BQ536_ADDR_BROADCAST, BQ536_ALERT_STATUS, 0);
}

void bq536SetBalance(const Bq536Config& c, psfw_board* b, const psfw_board_api* api, const uint32_t* mask,
                     uint32_t time_s) {
  const uint8_t timeCode = bq536_cb_time_code(time_s);
  for (uint8_t d = 0; d < devicesOf(c); ++d) {
    uint8_t bits = 0;
    for (uint8_t i = 0; i < cellsOf(c, d); ++i) {
      const uint16_t cell = static_cast<uint16_t>(d * c.cellsPerDevice + i);
      if (mask[cell / 32u] & (1u << (cell % 32u))) bits = static_cast<uint8_t>(bits | (1u << i));
    }
    writeReg(c, b, api, addrOf(d), BQ536_CB_TIME, timeCode);
    writeReg(c, b, api, addrOf(d), BQ536_CB_CTRL, bits);
  }
}

}  // namespace bms
