#include "bq76pl455a_driver.hpp"

#include <cstring>

#include "../bms_crc.hpp"

namespace bms {

namespace {

constexpr uint8_t kBroadcast = 0xFF;  // marks a frame without an address byte
constexpr uint32_t kBalanceTime_s[PL455_BALANCE_TIME_CODES] = PL455_BALANCE_TIME_S_INIT;
constexpr uint16_t kFaultOut = PL455_FAULT_SUM_CMPUV | PL455_FAULT_SUM_CMPOV | PL455_FAULT_SUM_AUXUV;

uint16_t be16(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }

// One command frame into out; returns its length.
uint16_t buildFrame(uint8_t* out, uint8_t req, uint8_t address, uint8_t reg, const uint8_t* data, uint8_t n) {
  uint16_t k = 0;
  out[k++] = static_cast<uint8_t>(PL455_INIT_COMMAND | req | PL455_SIZE_FIELD(n));
  if (address != kBroadcast) out[k++] = address;
  out[k++] = reg;
  for (uint8_t i = 0; i < n; ++i) out[k++] = data[i];
  const uint16_t crc = crcCrc16(out, k);
  out[k++] = static_cast<uint8_t>(crc & 0xFFu);
  out[k++] = static_cast<uint8_t>(crc >> 8);
  return k;
}

bool writeRegs(const Pl455Config& c, psfw_board* b, const psfw_board_api* api, uint8_t address, uint8_t reg,
               const uint8_t* data, uint8_t n) {
  uint8_t tx[16];
  const uint8_t req = address == kBroadcast ? PL455_REQ_BROADCAST_NR : PL455_REQ_SINGLE_NR;
  const uint16_t len = buildFrame(tx, req, address, reg, data, n);
  return api->bus_transfer(b, c.bus, tx, len, nullptr, 0) >= 0;
}

bool write8(const Pl455Config& c, psfw_board* b, const psfw_board_api* api, uint8_t address, uint8_t reg, uint8_t v) {
  return writeRegs(c, b, api, address, reg, &v, 1);
}

// One request with response (the frame tx, kPl455RequestLen bytes); checks length,
// header and CRC of the reply of `count` data bytes into rx (count + 3 bytes).
__attribute__((always_inline)) inline FrameResult request(const Pl455Config& c, psfw_board* b,
                                                          const psfw_board_api* api, const uint8_t* tx, uint8_t count,
                    uint8_t* rx) {
  const uint16_t want = static_cast<uint16_t>(count + PL455_RESPONSE_OVERHEAD);
  const int32_t got = api->bus_transfer(b, c.bus, tx, kPl455RequestLen, rx, want);
  if (got <= 0) return FrameResult::Timeout;
  if (got != want) return FrameResult::BadLength;
  if (rx[0] != static_cast<uint8_t>(count - 1)) return FrameResult::BadHeader;  // also a stuck 0xFF / 0x00 line
  const uint16_t crc = crcCrc16(rx, static_cast<uint16_t>(count + 1));
  if (rx[count + 1] != (crc & 0xFFu) || rx[count + 2] != (crc >> 8)) return FrameResult::BadCrc;
  return FrameResult::Ok;
}

// A request retried on a bad CRC only (the request does not change the device).
// Inline: a call and its frame less per read (a read-out makes two a device).
__attribute__((always_inline)) inline FrameResult requestRetried(const Pl455Config& c, Pl455State& s, psfw_board* b, const psfw_board_api* api,
                           const uint8_t* tx, uint8_t count, uint8_t* rx) {
  FrameResult r = request(c, b, api, tx, count, rx);
  for (uint8_t k = 0; k < c.crcRetries && r == FrameResult::BadCrc; ++k) {
    ++s.crcRetriesUsed;
    r = request(c, b, api, tx, count, rx);
  }
  return r;
}

// A request with response to device `address` (the frame built into tx).
const uint8_t* requestFrame(uint8_t* tx, uint8_t address, uint8_t reg, uint8_t data) {
  buildFrame(tx, PL455_REQ_SINGLE_R, address, reg, &data, 1);
  return tx;
}

// Device d's read-out request from the table init built; built into scratch for a chain
// longer than the part allows (no table entry).
const uint8_t* tableFrame(const uint8_t (&table)[PL455_MAX_DEVICES][kPl455RequestLen], uint8_t d, uint8_t reg,
                          uint8_t data, uint8_t* scratch) {
  return d < PL455_MAX_DEVICES ? table[d] : requestFrame(scratch, d, reg, data);
}

uint8_t thermsOf(const Pl455Config& c) {
  return c.thermistorsPerDevice > PL455_AUX_INPUTS ? PL455_AUX_INPUTS : c.thermistorsPerDevice;
}

uint32_t channelsOf(const Pl455Config& c, uint8_t d) {
  uint32_t ch = PL455_CH_CELLS(pl455CellsOf(c, d)) | PL455_CH_DIE_TEMP | PL455_CH_MODULE;
  for (uint8_t k = 0; k < thermsOf(c); ++k) ch |= PL455_CH_AUX(k);
  return ch;
}

// The number of bits channelsOf(c, d) sets, counted without building the mask: its
// cells (PL455_CH_CELLS keeps at most 16 in the word), the AUX inputs in use, the die
// temperature and the module voltage.
uint8_t selectedOf(const Pl455Config& c, uint8_t d) {
  const uint8_t cells = pl455CellsOf(c, d);
  return static_cast<uint8_t>((cells < 16u ? cells : 16u) + thermsOf(c) + 2u);
}

uint8_t compField(uint16_t mV, uint16_t base_mV) {
  const uint16_t steps = mV <= base_mV ? 0 : static_cast<uint16_t>((mV - base_mV + PL455_COMP_STEP_MV / 2) / PL455_COMP_STEP_MV);
  return static_cast<uint8_t>((steps > PL455_COMP_MAX_STEPS ? PL455_COMP_MAX_STEPS : steps) << PL455_COMP_SHIFT);
}

uint16_t cellCode(const Pl455Config& c, uint16_t mV) {
  const float code = static_cast<float>(mV) * 1000.0f / c.cellLsb_uV;
  return code >= 65535.0f ? 65535u : static_cast<uint16_t>(code + 0.5f);
}

// FAULT_SUM into the reading's protection flags.
void applySummary(uint16_t summary, DeviceReading& r) {
  r.fault = (summary & kFaultOut) != 0;
  r.alert = (summary & (PL455_FAULT_SUM_UV | PL455_FAULT_SUM_OV)) != 0;
  r.safetyA = static_cast<uint8_t>(summary & 0xFFu);
  r.safetyB = static_cast<uint8_t>(summary >> 8);
}

// The held results of device d, highest CHANNELS bit first, into r.
void decode(const Pl455Config& c, uint8_t d, const uint8_t* p, uint16_t summary, DeviceReading& r) {
  const uint8_t n = pl455CellsOf(c, d), nt = thermsOf(c);
  std::memset(r.cell_mV, 0, sizeof r.cell_mV);  // a few wide stores (18 slots is no whole count of lanes)
  for (uint8_t k = n; k >= 1; --k, p += 2) r.cell_mV[k - 1] = afeCellCodeToMv(be16(p), c.cellLsb_uV);
  // Codes through afeSetThermCodes: an input reading the same code keeps the core's
  // conversion of it (nearly every read-out: a thermistor moves slowly).
  uint16_t codes[kMaxThermPerDevice] = {};
  for (uint8_t k = nt; k >= 1; --k, p += 2) codes[k - 1] = be16(p);
  afeSetThermCodes(r, codes);
  r.die_dC = static_cast<int16_t>(be16(p) * PL455_DIE_TEMP_DC_PER_CODE);
  p += 2;
  r.stack_mV = static_cast<uint32_t>(static_cast<float>(be16(p)) * PL455_MODULE_FULL_SCALE_MV /
                                         static_cast<float>(PL455_CODE_FULL_SCALE) + 0.5f);
  applySummary(summary, r);
  r.fetStatus = 0;
  r.current_mA = 0;
  r.charge_mAs = 0;
}

}  // namespace

uint8_t pl455CellsOf(const Pl455Config& c, uint8_t device) {
  const int32_t left = static_cast<int32_t>(c.cellCount) - static_cast<int32_t>(device) * c.cellsPerDevice;
  return static_cast<uint8_t>(left <= 0 ? 0 : left < c.cellsPerDevice ? left : c.cellsPerDevice);
}

uint32_t pl455ConversionTime_us(const Pl455Config& c, uint8_t device) {
  const uint32_t channels = static_cast<uint32_t>(pl455CellsOf(c, device)) + thermsOf(c) + 2u;
  return channels * (1u << c.oversamplingLog2) * PL455_SAMPLE_US_PER_CHANNEL;
}

uint8_t pl455BalanceTimeCode(uint32_t time_s) {
  uint8_t code = 1;
  for (uint8_t k = 1; k < PL455_BALANCE_TIME_CODES; ++k)
    if (kBalanceTime_s[k] <= time_s) code = k;
  return code;
}

uint8_t pl455Init(const Pl455Config& c, Pl455State& s, psfw_board* b, const psfw_board_api* api) {
  s.devicesFound = 0;
  s.crcRetriesUsed = 0;
  s.readouts = 0;
  for (uint8_t d = 0; d < kMaxDevices; ++d) s.last[d] = FrameResult::Timeout;
  // Auto-addressing: every device listens for its address, the lowest takes each one.
  const uint8_t devconfig = static_cast<uint8_t>(PL455_DEVCONFIG_ADDR_SEL | (c.comparators ? PL455_DEVCONFIG_COMP_ENA : 0));
  write8(c, b, api, kBroadcast, PL455_REG_DEVCONFIG, devconfig);
  write8(c, b, api, kBroadcast, PL455_REG_DEV_CTRL, PL455_DEV_CTRL_AUTO_ADDRESS);
  for (uint8_t d = 0; d < c.deviceCount; ++d) write8(c, b, api, kBroadcast, PL455_REG_ADDR, d);
  uint8_t rx[8], tx[kPl455RequestLen];
  for (uint8_t d = 0; d < c.deviceCount; ++d)
    if (requestRetried(c, s, b, api, requestFrame(tx, d, PL455_REG_ADDR, 1), 2, rx) == FrameResult::Ok && rx[1] == d)
      ++s.devicesFound;
  // The read-out's frames, once.
  const uint8_t sample = PL455_CMD_SAMPLE;
  buildFrame(s.sampleCommand, PL455_REQ_BROADCAST_NR, kBroadcast, PL455_REG_CMD, &sample, 1);
  for (uint8_t d = 0; d < PL455_MAX_DEVICES; ++d) {
    requestFrame(s.statusRequest[d], d, PL455_REG_STATUS, 2);
    requestFrame(s.heldRequest[d], d, PL455_REG_CMD, PL455_CMD_SEND_HELD);
  }

  // Thresholds shared by every device, broadcast.
  write8(c, b, api, kBroadcast, PL455_REG_OVERSMPL, c.oversamplingLog2);
  if (c.compUv_mV != 0) write8(c, b, api, kBroadcast, PL455_REG_COMP_UV, compField(c.compUv_mV, PL455_COMP_UV_BASE_MV));
  if (c.compOv_mV != 0) write8(c, b, api, kBroadcast, PL455_REG_COMP_OV, compField(c.compOv_mV, PL455_COMP_OV_BASE_MV));
  for (uint8_t k = 0; k < 2; ++k) {  // CELL_UV, CELL_OV
    const uint16_t mV = k == 0 ? c.cellUv_mV : c.cellOv_mV;
    if (mV == 0) continue;
    const uint16_t code = cellCode(c, mV);
    const uint8_t bytes[2] = {static_cast<uint8_t>(code >> 8), static_cast<uint8_t>(code)};
    writeRegs(c, b, api, kBroadcast, static_cast<uint8_t>(PL455_REG_CELL_UV + 2 * k), bytes, 2);
  }
  // AUX over temperature (UV: the NTC reads low when hot) on the inputs in use.
  const uint8_t hot[2] = {static_cast<uint8_t>(c.auxHotCode >> 8), static_cast<uint8_t>(c.auxHotCode)};
  for (uint8_t k = 0; k < thermsOf(c) && c.auxHotCode != 0; ++k) writeRegs(c, b, api, kBroadcast, PL455_REG_AUX_UV(k), hot, 2);
  if (c.commTimeoutCode != 0)  // off at power-up
    write8(c, b, api, kBroadcast, PL455_REG_CTO, static_cast<uint8_t>(c.commTimeoutCode & PL455_CTO_FAULT_MASK));
  const uint16_t fo = static_cast<uint16_t>((c.comparators ? kFaultOut : 0) | (c.commTimeoutCode != 0 ? PL455_FAULT_SUM_SYS : 0));
  const uint8_t foBytes[2] = {static_cast<uint8_t>(fo >> 8), static_cast<uint8_t>(fo)};
  writeRegs(c, b, api, kBroadcast, PL455_REG_FO_CTRL, foBytes, 2);
  // Channel select and connected cells differ on a partly populated top device.
  for (uint8_t d = 0; d < c.deviceCount; ++d) {
    const uint32_t ch = channelsOf(c, d);
    const uint8_t sel[4] = {static_cast<uint8_t>(ch >> 24), static_cast<uint8_t>(ch >> 16), static_cast<uint8_t>(ch >> 8),
                            static_cast<uint8_t>(ch)};
    writeRegs(c, b, api, d, PL455_REG_CHANNELS, sel, 4);
    write8(c, b, api, d, PL455_REG_NCHAN, pl455CellsOf(c, d));
  }
  pl455ClearFaults(c, b, api);
  return s.devicesFound;
}

void pl455ReadAll(const Pl455Config& c, Pl455State& s, psfw_board* b, const psfw_board_api* api, DeviceReading* out,
                  FrameResult* result) {
  ++s.readouts;
  // Every device samples at once; the slowest conversion bounds the wait.
  api->bus_transfer(b, c.bus, s.sampleCommand, kPl455BroadcastLen, nullptr, 0);
  uint32_t wait_us = 0;
  for (uint8_t d = 0; d < c.deviceCount; ++d) {
    const uint32_t t = pl455ConversionTime_us(c, d);
    wait_us = t > wait_us ? t : wait_us;
  }
  api->delay_us(b, wait_us);
  uint8_t rx[PL455_MAX_RESPONSE_DATA + PL455_RESPONSE_OVERHEAD];
  uint8_t scratch[kPl455RequestLen];
  for (uint8_t d = 0; d < c.deviceCount; ++d) {
    // STATUS and FAULT_SUM in one read; a sample not yet done gets one more wait.
    const uint8_t* const status = tableFrame(s.statusRequest, d, PL455_REG_STATUS, 2, scratch);
    FrameResult r = requestRetried(c, s, b, api, status, 3, rx);
    if (r == FrameResult::Ok && (rx[1] & PL455_STATUS_DRDY) == 0) {
      api->delay_us(b, pl455ConversionTime_us(c, d));
      r = requestRetried(c, s, b, api, status, 3, rx);
    }
    if (r == FrameResult::Ok) {
      const uint16_t summary = be16(rx + 2);
      const uint8_t selected = selectedOf(c, d);
      const uint8_t* const held = tableFrame(s.heldRequest, d, PL455_REG_CMD, PL455_CMD_SEND_HELD, scratch);
      r = requestRetried(c, s, b, api, held, static_cast<uint8_t>(2 * selected), rx);
      if (r == FrameResult::Ok) decode(c, d, rx + 1, summary, out[d]);
    }
    result[d] = r;
    s.last[d] = r;
  }
}

void pl455PollFaults(const Pl455Config& c, Pl455State& s, psfw_board* b, const psfw_board_api* api, DeviceReading* io,
                     FrameResult* result) {
  uint8_t rx[8], scratch[kPl455RequestLen];
  for (uint8_t d = 0; d < c.deviceCount; ++d) {
    result[d] = requestRetried(c, s, b, api, tableFrame(s.statusRequest, d, PL455_REG_STATUS, 2, scratch), 3, rx);
    if (result[d] == FrameResult::Ok) applySummary(be16(rx + 2), io[d]);
  }
}

bool pl455ClearFaults(const Pl455Config& c, psfw_board* b, const psfw_board_api* api) {
  const uint8_t all[2] = {static_cast<uint8_t>(PL455_FAULT_SUM_ALL >> 8), static_cast<uint8_t>(PL455_FAULT_SUM_ALL & 0xFFu)};
  return writeRegs(c, b, api, kBroadcast, PL455_REG_FAULT_SUM, all, 2);
}

bool pl455WriteBalance(const Pl455Config& c, psfw_board* b, const psfw_board_api* api, const uint32_t* balanceMask,
                       uint32_t time_s) {
  const uint8_t cbconfig = static_cast<uint8_t>(pl455BalanceTimeCode(time_s) << PL455_CBCONFIG_TIME_SHIFT);
  bool ok = true;
  for (uint8_t d = 0; d < c.deviceCount; ++d) {
    uint16_t mask = 0;
    for (uint8_t k = 0; k < pl455CellsOf(c, d); ++k) {
      const uint16_t cell = static_cast<uint16_t>(d * c.cellsPerDevice + k);
      if (balanceMask[cell / 32] & (1u << (cell % 32))) mask = static_cast<uint16_t>(mask | (1u << k));
    }
    // CBCONFIG then CBENBL (consecutive): writing the mask starts the device's timer.
    const uint8_t regs[3] = {cbconfig, static_cast<uint8_t>(mask >> 8), static_cast<uint8_t>(mask)};
    ok = writeRegs(c, b, api, d, PL455_REG_CBCONFIG, regs, 3) && ok;
  }
  return ok;
}

}  // namespace bms
