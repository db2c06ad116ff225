#include "bms_afe.hpp"

#include "bms_crc.hpp"

namespace bms {

namespace {

uint16_t be16(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }
uint16_t le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t le32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}

int16_t kelvinTenthsToDeciC(uint16_t k) { return static_cast<int16_t>(static_cast<int32_t>(k) - 2732); }

void clearReading(DeviceReading& r) {
  for (uint8_t i = 0; i < kMaxCellsPerDevice; ++i) r.cell_mV[i] = 0;
  for (uint8_t i = 0; i < kMaxThermPerDevice; ++i) {
    r.thermCode[i] = 0;
    r.temp_dC[i] = 0;
  }
  r.stack_mV = 0;
  r.die_dC = 0;
  r.fault = false;
  r.alert = false;
  r.fetStatus = 0;
  r.safetyA = 0;
  r.safetyB = 0;
  r.current_mA = 0;
  r.charge_mAs = 0;
}

FrameResult parsePl536(uint8_t d, uint8_t cells, float lsb_uV, const AfeFrame& f, DeviceReading& r) {
  // Header: the device's own address shifted, register 0, the data length.
  if (f.bytes[0] != static_cast<uint8_t>((d + 1) << 1) || f.bytes[1] != 0x00 || f.bytes[2] != kPl536DataLen)
    return FrameResult::BadHeader;
  if (crcCrc8(f.bytes, kPl536FrameLen - 1) != f.bytes[kPl536FrameLen - 1]) return FrameResult::BadCrc;
  const uint8_t* p = f.bytes + 3;
  clearReading(r);
  for (uint8_t c = 0; c < cells; ++c) r.cell_mV[c] = afeCellCodeToMv(be16(p + kPl536Cell1 + 2 * c), lsb_uV);
  r.thermCode[0] = be16(p + kPl536Temp1);
  r.thermCode[1] = be16(p + kPl536Temp2);
  r.stack_mV = static_cast<uint32_t>(static_cast<float>(be16(p + kPl536Gpai)) * lsb_uV * kPl536GpaiCellLsbs * 0.001f + 0.5f);
  r.die_dC = static_cast<int16_t>(be16(p + kPl536DieTemp));
  r.fault = (p[kPl536Status] & kPl536FaultBit) != 0 || (p[kPl536Status] & kPl536AlertBit) != 0;
  r.alert = (p[kPl536Status] & kPl536AlertBit) != 0;
  r.safetyA = p[kPl536Fault];
  r.safetyB = p[kPl536Alert];
  return FrameResult::Ok;
}

FrameResult parsePl455(uint8_t cells, float lsb_uV, const AfeFrame& f, DeviceReading& r) {
  const uint8_t n = pl455DataLen(cells);
  // A response's init byte is its data length - 1 with the top bit clear.
  if (f.bytes[0] != static_cast<uint8_t>(n - 1)) return FrameResult::BadHeader;
  const uint16_t crc = crcCrc16(f.bytes, static_cast<size_t>(1 + n));
  if ((crc & 0xFFu) != f.bytes[1 + n] || (crc >> 8) != f.bytes[2 + n]) return FrameResult::BadCrc;
  const uint8_t* p = f.bytes + 1;
  clearReading(r);
  for (uint8_t c = 0; c < cells; ++c) r.cell_mV[c] = afeCellCodeToMv(be16(p + 2 * c), lsb_uV);
  const uint8_t* q = p + 2 * cells;
  r.stack_mV = static_cast<uint32_t>(static_cast<float>(be16(q)) * kPl455ModuleLsb_mV + 0.5f);
  r.thermCode[0] = be16(q + 2);
  r.thermCode[1] = be16(q + 4);
  r.die_dC = static_cast<int16_t>(be16(q + 6));
  const uint16_t summary = be16(q + 8);
  r.fault = (summary & (kPl455CmpUv | kPl455CmpOv | kPl455AuxOv)) != 0;
  r.alert = (summary & (kPl455Uv | kPl455Ov)) != 0;
  r.safetyA = static_cast<uint8_t>(summary & 0xFFu);
  r.safetyB = static_cast<uint8_t>(summary >> 8);
  return FrameResult::Ok;
}

FrameResult parseBq952(uint8_t cells, bool crcOn, const AfeFrame& f, DeviceReading& r) {
  const uint8_t n = bq952DataLen(cells);
  if (f.bytes[0] != n) return FrameResult::BadHeader;
  if (crcOn && crcCrc8(f.bytes, static_cast<size_t>(1 + n)) != f.bytes[1 + n]) return FrameResult::BadCrc;
  const uint8_t* p = f.bytes + 1;
  clearReading(r);
  for (uint8_t c = 0; c < cells; ++c) {
    const int16_t mv = static_cast<int16_t>(le16(p + 2 * c));
    r.cell_mV[c] = mv < 0 ? 0 : static_cast<uint16_t>(mv);
  }
  const uint8_t* q = p + 2 * cells;
  r.stack_mV = static_cast<uint32_t>(le16(q)) * 10u;
  for (uint8_t k = 0; k < 3; ++k) r.temp_dC[k] = kelvinTenthsToDeciC(le16(q + 2 + 2 * k));
  r.die_dC = kelvinTenthsToDeciC(le16(q + 8));
  r.current_mA = static_cast<int32_t>(static_cast<int16_t>(le16(q + 10))) * 10;  // CC2 in 10 mA
  r.charge_mAs = static_cast<int32_t>(le32(q + 12));
  const uint8_t alertA = q[16];
  r.safetyA = q[17];
  r.safetyB = q[18];
  r.fetStatus = q[19];
  r.fault = r.safetyA != 0 || r.safetyB != 0;
  r.alert = alertA != 0 || (r.fetStatus & kBqAlrtPin) != 0;
  return FrameResult::Ok;
}

}  // namespace

uint16_t afeCellCodeToMv(uint16_t code, float lsb_uV) {
  const float mv = static_cast<float>(code) * lsb_uV * 0.001f;
  if (mv <= 0.0f) return 0;
  if (mv >= 65535.0f) return 65535;
  return static_cast<uint16_t>(mv + 0.5f);
}

uint8_t afeCellsOf(const AfeConfig& c, uint16_t cellCount, uint8_t d) {
  const uint32_t first = static_cast<uint32_t>(d) * c.cellsPerDevice;
  if (first >= cellCount) return 0;
  const uint32_t left = cellCount - first;
  return static_cast<uint8_t>(left < c.cellsPerDevice ? left : c.cellsPerDevice);
}

uint8_t afeFrameLength(const AfeConfig& c, uint16_t cellCount, uint8_t d) {
  const uint8_t cells = afeCellsOf(c, cellCount, d);
  switch (c.model) {
    case AfeModel::Bq76pl536a: return kPl536FrameLen;
    case AfeModel::Bq76pl455a: return pl455FrameLen(cells);
    case AfeModel::Bq76952: return bq952FrameLen(cells, c.crcEnabled);
  }
  return 0;
}

FrameResult afeParse(const AfeConfig& c, uint16_t cellCount, uint8_t d, float cellLsb_uV, const AfeFrame& f,
                     DeviceReading& out) {
  if (f.length == 0) return FrameResult::Timeout;
  if (f.length != afeFrameLength(c, cellCount, d) || f.length > kMaxFrameBytes) return FrameResult::BadLength;
  const uint8_t cells = afeCellsOf(c, cellCount, d);
  switch (c.model) {
    case AfeModel::Bq76pl536a: return parsePl536(d, cells, cellLsb_uV, f, out);
    case AfeModel::Bq76pl455a: return parsePl455(cells, cellLsb_uV, f, out);
    case AfeModel::Bq76952: return parseBq952(cells, c.crcEnabled, f, out);
  }
  return FrameResult::BadHeader;
}

}  // namespace bms
