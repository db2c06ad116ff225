#include "core/sim/result_channels.hpp"

#include <bms/bms_balance.hpp>
#include <bms/bms_config.hpp>
#include <bms/bms_names.hpp>
#include <bms/bms_soc.hpp>
#include <bms/bms_telemetry.hpp>

#include <algorithm>
#include <cmath>

#include "core/sim/bms_bridge.hpp"
#include "core/sim/plant.hpp"
#include "models/sensors/round_half_away.hpp"
#include "models/vehicle/vehicle.hpp"

namespace packsim {

namespace {

using S = ChannelSample;
template <typename T>
using V = std::vector<T>;

// "0=init,1=standby,..." from one of bms/'s name functions.
template <typename Enum>
std::string enumNames(const char* (*name)(Enum), uint8_t count) {
  std::string s;
  for (uint8_t i = 0; i < count; ++i)
    s += (i ? "," : "") + std::to_string(i) + "=" + name(static_cast<Enum>(i));
  return s;
}

// Per cell / per series group / per device loops.
template <typename T, typename F>
void perCell(const S& s, V<T>& v, F f) {
  for (int c = 0; c < s.plant.pack().cellCount(); ++c) v.push_back(f(c));
}
template <typename T, typename F>
void perGroup(const S& s, V<T>& v, F f) {
  for (int g = 0; g < s.plant.pack().series; ++g) v.push_back(f(g));
}
uint8_t flag(bool b) { return b ? 1 : 0; }
const HardwareStatus& hwStatus(const S& s) { return s.hw->status(); }

double cellSoc(const S& s, int c) { return s.plant.cellStates(s.x, c)[CellLayout::soc]; }

double trueMeanSoc(const S& s) {
  double sum = 0.0;
  for (int c = 0; c < s.plant.pack().cellCount(); ++c) sum += cellSoc(s, c);
  return sum / s.plant.pack().cellCount();
}

constexpr ChannelAttr kNoAttr{};
// A vehicle channel over time that xarray also indexes by the distance driven.
const ChannelAttr kAtDistance{"coordinates", [](const Recording&) { return std::string("distance_m"); }};

std::vector<ResultChannel> makeChannels() {
  using A = Axis;
  using P = Presence;
  // clang-format off
  return {
  {"/time_s", "s", A::None, P::Always, "simulation time",
   Column<double>{&Recording::time_s, [](const S& s, V<double>& v) { v.push_back(s.t_s); }}, kNoAttr},
  // --- truth: the simulated plant
  {"/truth/cell_voltage_V", "V", A::Cell, P::Always, "cell terminal voltage (simulated truth)",
   Column<double>{&Recording::cell_voltage_V, [](const S& s, V<double>& v) {
     perCell(s, v, [&](int c) { return s.sig.cell_voltage_V[static_cast<size_t>(c)]; }); }}, kNoAttr},
  {"/truth/cell_current_A", "A", A::Cell, P::Always, "cell current, positive discharging (simulated truth)",
   Column<double>{&Recording::cell_current_A, [](const S& s, V<double>& v) {
     perCell(s, v, [&](int c) { return s.sig.cell_current_A[static_cast<size_t>(c)]; }); }}, kNoAttr},
  {"/truth/cell_soc", "1", A::Cell, P::Always, "cell state of charge (simulated truth)",
   Column<double>{&Recording::cell_soc, [](const S& s, V<double>& v) {
     perCell(s, v, [&](int c) { return cellSoc(s, c); }); }}, kNoAttr},
  {"/truth/cell_temp_C", "degC", A::Cell, P::Always, "cell temperature (simulated truth)",
   Column<double>{&Recording::cell_temp_C, [](const S& s, V<double>& v) {
     perCell(s, v, [&](int c) { return s.x[s.plant.tempIndex(c)]; }); }}, kNoAttr},
  {"/truth/pack_voltage_V", "V", A::None, P::Always, "pack terminal voltage (simulated truth)",
   Column<double>{&Recording::pack_voltage_V, [](const S& s, V<double>& v) { v.push_back(s.sig.pack_voltage_V); }}, kNoAttr},
  {"/truth/pack_current_A", "A", A::None, P::Always, "pack current, positive discharging (simulated truth)",
   Column<double>{&Recording::pack_current_A, [](const S& s, V<double>& v) { v.push_back(s.sig.pack_current_A); }}, kNoAttr},
  // --- measured: exactly what the BMS core saw, in its own units
  {"/measured/cell_voltage_mV", "mV", A::Series, P::Always, "series cell voltage as read by the monitor ICs",
   Column<uint16_t>{&Recording::meas_cell_voltage_mV, [](const S& s, V<uint16_t>& v) {
     perGroup(s, v, [&](int g) { return s.out.telemetry.cellVoltage_mV[g]; }); }}, kNoAttr},
  {"/measured/temperature_dC", "0.1 degC", A::Thermistor, P::Always, "thermistor temperature as read by the monitor ICs",
   Column<int16_t>{&Recording::meas_temperature_dC, [](const S& s, V<int16_t>& v) {
     for (int k = 0; k < s.rec.thermistors; ++k) v.push_back(s.out.telemetry.temperature_dC[k]); }},
   {"invalid_value", [](const Recording&) { return std::string("-32768 (sensor open or shorted)"); }}},
  {"/measured/current_mA", "mA", A::None, P::Always, "pack current as read by the current sensor",
   Column<int32_t>{&Recording::meas_current_mA, [](const S& s, V<int32_t>& v) { v.push_back(s.out.telemetry.packCurrent_mA); }}, kNoAttr},
  // --- bms: what the firmware decided
  {"/bms/state", nullptr, A::None, P::Always, "BMS state machine state (see names)",
   Column<uint8_t>{&Recording::bms_state, [](const S& s, V<uint8_t>& v) { v.push_back(static_cast<uint8_t>(s.out.state)); }},
   {"names", [](const Recording&) { return enumNames(&bms::stateName, bms::kStateCount); }}},
  {"/bms/fault_active", nullptr, A::None, P::Always, "active fault bits (see /bms fault_bits)",
   Column<uint32_t>{&Recording::fault_active, [](const S& s, V<uint32_t>& v) { v.push_back(s.out.faultActive); }}, kNoAttr},
  {"/bms/fault_latched", nullptr, A::None, P::Always, "latched fault bits (see /bms fault_bits)",
   Column<uint32_t>{&Recording::fault_latched, [](const S& s, V<uint32_t>& v) { v.push_back(s.out.faultLatched); }}, kNoAttr},
  {"/bms/relay_closed", nullptr, A::None, P::Always, "main relay commanded closed by the firmware",
   Column<uint8_t>{&Recording::relay_closed, [](const S& s, V<uint8_t>& v) { v.push_back(flag(s.out.relayClose)); }}, kNoAttr},
  {"/bms/discharge_fet_on", nullptr, A::None, P::Always, "discharge FET commanded on by the firmware",
   Column<uint8_t>{&Recording::discharge_fet_on, [](const S& s, V<uint8_t>& v) { v.push_back(flag(s.out.dischargeFetOn)); }}, kNoAttr},
  {"/bms/charge_fet_on", nullptr, A::None, P::Always, "charge FET commanded on by the firmware",
   Column<uint8_t>{&Recording::charge_fet_on, [](const S& s, V<uint8_t>& v) { v.push_back(flag(s.out.chargeFetOn)); }}, kNoAttr},
  {"/bms/precharge_closed", nullptr, A::None, P::Always, "precharge relay commanded closed by the firmware",
   Column<uint8_t>{&Recording::precharge_closed, [](const S& s, V<uint8_t>& v) { v.push_back(flag(s.out.prechargeClose)); }}, kNoAttr},
  {"/bms/precharge_phase", nullptr, A::None, P::Always, "precharge sequence phase (see names)",
   Column<uint8_t>{&Recording::precharge_phase, [](const S& s, V<uint8_t>& v) { v.push_back(s.out.telemetry.prechargePhase); }},
   {"names", [](const Recording&) { return enumNames(&bms::prechargePhaseName, bms::kPrechargePhaseCount); }}},
  {"/bms/soc_estimate_permille", "0.1 %", A::None, P::Always, "pack state of charge estimated by the firmware",
   Column<uint16_t>{&Recording::soc_estimate_permille, [](const S& s, V<uint16_t>& v) { v.push_back(s.out.telemetry.soc_permille); }}, kNoAttr},
  {"/bms/monitor_fault", nullptr, A::None, P::Always, "monitor IC fault seen by the firmware",
   Column<uint8_t>{&Recording::monitor_fault, [](const S& s, V<uint8_t>& v) { v.push_back(flag(s.out.telemetry.monitorFault)); }}, kNoAttr},
  {"/bms/comm_bad", "replies", A::Device, P::Always, "consecutive bad replies per monitor IC",
   Column<uint8_t>{&Recording::comm_bad, [](const S& s, V<uint8_t>& v) {
     for (int d = 0; d < s.rec.devices; ++d) v.push_back(s.out.telemetry.commBad[d]); }}, kNoAttr},
  {"/bms/telemetry", "bytes", A::TelemetryByte, P::Always, "telemetry frame bytes (see layout)",
   Column<uint8_t>{&Recording::telemetry, [](const S& s, V<uint8_t>& v) {
     uint8_t frame[bms::kTelemetryFrameBytes];
     bms::telemetryEncode(s.out, frame);
     v.insert(v.end(), frame, frame + bms::kTelemetryFrameBytes); }},
   {"layout", [](const Recording&) {
     return std::string("bms/bms_telemetry.hpp: A5,len,state,precharge,bits,active u32,latched u32,"
                        "soc u16,current_mA i32,pack_mV u32,min_mV u16,max_mV u16,maxT_dC i16,"
                        "minT_dC i16,lost,crc8 (little-endian)"); }}},
  {"/measured/bus_voltage_mV", "mV", A::None, P::Always, "bus (load side) voltage as read by the BMS",
   Column<uint32_t>{&Recording::meas_bus_voltage_mV, [](const S& s, V<uint32_t>& v) { v.push_back(s.out.telemetry.busVoltage_mV); }}, kNoAttr},
  // --- hardware: what the relay, FETs, fuse and monitor ICs actually did
  {"/hardware/relay_closed", nullptr, A::None, P::Hardware, "main relay contact closed (hardware)",
   Column<uint8_t>{&Recording::hw_relay_closed, [](const S& s, V<uint8_t>& v) { v.push_back(flag(hwStatus(s).relay_closed)); }}, kNoAttr},
  {"/hardware/precharge_closed", nullptr, A::None, P::Hardware, "precharge relay contact closed (hardware)",
   Column<uint8_t>{&Recording::hw_precharge_closed, [](const S& s, V<uint8_t>& v) { v.push_back(flag(hwStatus(s).precharge_closed)); }}, kNoAttr},
  {"/hardware/fuse_blown", nullptr, A::None, P::Hardware, "fuse blown (hardware)",
   Column<uint8_t>{&Recording::hw_fuse_blown, [](const S& s, V<uint8_t>& v) { v.push_back(flag(hwStatus(s).fuse_blown)); }}, kNoAttr},
  {"/hardware/discharge_fet_on", nullptr, A::None, P::Hardware, "discharge FET conducting (hardware)",
   Column<uint8_t>{&Recording::hw_discharge_fet_on, [](const S& s, V<uint8_t>& v) { v.push_back(flag(hwStatus(s).discharge_fet_on)); }}, kNoAttr},
  {"/hardware/charge_fet_on", nullptr, A::None, P::Hardware, "charge FET conducting (hardware)",
   Column<uint8_t>{&Recording::hw_charge_fet_on, [](const S& s, V<uint8_t>& v) { v.push_back(flag(hwStatus(s).charge_fet_on)); }}, kNoAttr},
  {"/hardware/monitor_fault_line", nullptr, A::None, P::Hardware, "monitor IC FAULT line asserted (hardware)",
   Column<uint8_t>{&Recording::hw_fault_line, [](const S& s, V<uint8_t>& v) { v.push_back(flag(hwStatus(s).fault_line)); }}, kNoAttr},
  {"/hardware/bus_voltage_V", "V", A::None, P::Hardware, "bus (load side) voltage (hardware)",
   Column<double>{&Recording::hw_bus_voltage_V, [](const S& s, V<double>& v) { v.push_back(hwStatus(s).bus_V); }}, kNoAttr},
  {"/hardware/fet_loss_W", "W", A::None, P::Hardware, "power dissipated in the FETs (hardware)",
   Column<double>{&Recording::hw_fet_loss_W, [](const S& s, V<double>& v) { v.push_back(hwStatus(s).fet_loss_W); }}, kNoAttr},
  // --- balancing and charging: only with that hardware
  {"/truth/balance_current_A", "A", A::Series, P::Balancing, "balancing current per series cell (simulated truth)",
   Column<double>{&Recording::balance_current_A, [](const S& s, V<double>& v) {
     perGroup(s, v, [&](int g) { return s.sig.balance_current_A[static_cast<size_t>(g)]; }); }},
   {"meaning", [](const Recording& rec) {
     return std::string(rec.has_active_balancer ? "active balancer converter current, + drawn from the module"
                                                : "passive balancing resistor current per series cell"); }}},
  {"/bms/balance_mask", nullptr, A::Series, P::Balancing, "balancing switches commanded per series cell",
   Column<uint8_t>{&Recording::balance_mask, [](const S& s, V<uint8_t>& v) {
     perGroup(s, v, [&](int g) { return flag(bms::balanceBit(s.out.balanceMask, static_cast<uint16_t>(g))); }); }}, kNoAttr},
  {"/bms/balance_status", nullptr, A::None, P::Balancing, "balancing status (see names)",
   Column<uint8_t>{&Recording::balance_status, [](const S& s, V<uint8_t>& v) { v.push_back(s.out.balanceStatus); }},
   {"names", [](const Recording&) { return enumNames(&bms::balanceStatusName, bms::kBalanceStatusCount); }}},
  {"/hardware/balancing", nullptr, A::Series, P::BalancingHardware, "balancing switch conducting per series cell (hardware)",
   Column<uint8_t>{&Recording::hw_balancing, [](const S& s, V<uint8_t>& v) {
     perGroup(s, v, [&](int g) { return flag(s.hw->balancing(g)); }); }}, kNoAttr},
  {"/truth/board_temp_C", "degC", A::None, P::Board, "BMS board temperature (simulated truth)",
   Column<double>{&Recording::board_temp_C, [](const S& s, V<double>& v) { v.push_back(s.x[s.plant.tempIndex(s.plant.boardNode())]); }}, kNoAttr},
  {"/truth/balancer_bus_V", "V", A::None, P::ActiveBalancer, "active balancer bus voltage (simulated truth)",
   Column<double>{&Recording::balancer_bus_V, [](const S& s, V<double>& v) { v.push_back(s.sig.bus_V); }}, kNoAttr},
  {"/truth/charger_current_A", "A", A::None, P::Charger, "charger output current (simulated truth)",
   Column<double>{&Recording::charger_current_A, [](const S& s, V<double>& v) { v.push_back(s.sig.charger_A); }}, kNoAttr},
  {"/bms/charger_enable", nullptr, A::None, P::Charger, "charger enable commanded by the firmware",
   Column<uint8_t>{&Recording::charger_enable, [](const S& s, V<uint8_t>& v) { v.push_back(flag(s.out.chargerEnable)); }}, kNoAttr},
  {"/bms/charger_request_mA", "mA", A::None, P::Charger, "charge current requested by the firmware",
   Column<int32_t>{&Recording::charger_request_mA, [](const S& s, V<int32_t>& v) { v.push_back(s.out.chargerCurrentRequest_mA); }}, kNoAttr},
  // --- state estimation (docs/state-estimation.md)
  {"/truth/soc_mean", "1", A::None, P::Always, "soc mean (truth)",
   Column<double>{&Recording::soc_truth_mean, [](const S& s, V<double>& v) { v.push_back(trueMeanSoc(s)); }}, kNoAttr},
  {"/truth/soc_display_bars", "bars", A::None, P::Always, "soc display bars (truth)",
   Column<uint8_t>{&Recording::soc_display_bars_truth, [](const S& s, V<uint8_t>& v) { v.push_back(trueDisplayBars(s.cfg, s.sig)); }},
   {"meaning", [](const Recording&) { return std::string("the SOC display's table applied to the true mean cell OCV"); }}},
  {"/bms/soc_coulomb", "1", A::None, P::Always, "soc coulomb (bms)",
   Column<double>{&Recording::soc_coulomb, [](const S& s, V<double>& v) { v.push_back(s.out.telemetry.socCoulomb); }}, kNoAttr},
  {"/bms/soc_ekf", "1", A::None, P::Always, "soc ekf (bms)",
   Column<double>{&Recording::soc_ekf, [](const S& s, V<double>& v) { v.push_back(s.out.telemetry.socEkf); }}, kNoAttr},
  {"/bms/soc_ekf_group_permille", "0.1 %", A::Series, P::Always, "soc ekf group permille (bms)",
   Column<uint16_t>{&Recording::soc_ekf_group_permille, [](const S& s, V<uint16_t>& v) {
     perGroup(s, v, [&](int g) { return s.out.telemetry.socGroup_permille[g]; }); }}, kNoAttr},
  {"/bms/capacity_estimate_Ah", "Ah", A::None, P::Always, "capacity estimate (bms)",
   Column<double>{&Recording::capacity_estimate_Ah, [](const S& s, V<double>& v) { v.push_back(s.out.telemetry.capacityEstimate_mAh * 1e-3); }},
   {"meaning", [](const Recording&) { return std::string("series-group capacity between two rested OCV points; 0 = none yet"); }}},
  {"/bms/soc_display_bars", "bars", A::None, P::Always, "soc display bars (bms)",
   Column<uint8_t>{&Recording::soc_display_bars, [](const S& s, V<uint8_t>& v) { v.push_back(s.out.telemetry.socDisplayBars); }}, kNoAttr},
  // a vehicle on its route (core/sim/vehicle_run.hpp)
  // (CF `coordinates`: xarray makes distance_m a coordinate of the vehicle's series)
  {"/vehicle/distance_m", "m", A::None, P::Vehicle, "distance driven",
   Column<double>{&Recording::vehicle_distance_m, [](const S& s, V<double>& v) { v.push_back(s.vehicle->distance_m); }}, kNoAttr},
  {"/vehicle/speed_m_per_s", "m/s", A::None, P::Vehicle, "vehicle speed",
   Column<double>{&Recording::vehicle_speed_m_per_s, [](const S& s, V<double>& v) { v.push_back(s.vehicle->speed_m_per_s); }}, kAtDistance},
  {"/vehicle/pack_request_W", "W", A::None, P::Vehicle, "pack power the vehicle asks for over the next tick",
   Column<double>{&Recording::vehicle_pack_request_W, [](const S& s, V<double>& v) { v.push_back(s.vehicle->pack_request_W); }}, kAtDistance},
  {"/vehicle/array_W", "W", A::None, P::Vehicle, "solar array power taken into the bus, the mean over the recording interval ending at the sample",
   Column<double>{&Recording::vehicle_array_W, [](const S& s, V<double>& v) { v.push_back(s.vehicle->array_W); }}, kAtDistance},
  {"/vehicle/array_available_W", "W", A::None, P::Vehicle, "solar array power the MPPT had (taken or not), the mean over the recording interval ending at the sample",
   Column<double>{&Recording::vehicle_array_available_W, [](const S& s, V<double>& v) { v.push_back(s.vehicle->array_available_W); }}, kAtDistance},
  {"/vehicle/limit", nullptr, A::None, P::Vehicle, "what limited the drive over the last tick",
   Column<uint8_t>{&Recording::vehicle_limit, [](const S& s, V<uint8_t>& v) { v.push_back(s.vehicle->limit); }},
   {"names", [](const Recording&) { return enumNames(&driveLimitName, static_cast<uint8_t>(DriveLimit::PackShortfall) + 1); }}},
  };
  // clang-format on
}

}  // namespace

uint16_t trueDisplay_mV(const PlantSignals& sig) {
  double sum = 0.0;
  for (double v : sig.cell_ocv_V) sum += v;
  const double mean_mV = sum / static_cast<double>(sig.cell_ocv_V.size()) * 1e3;
  // std::lround's value, inline (the libm call cost a quarter of this function, every tick)
  return static_cast<uint16_t>(std::clamp<long long>(roundHalfAway(mean_mV), 0, 65535));
}

uint8_t trueDisplayBars(const bms::Config& cfg, const PlantSignals& sig) {
  return bms::socDisplayBars(cfg.soc, trueDisplay_mV(sig));
}

const std::vector<ResultChannel>& resultChannels() {
  static const std::vector<ResultChannel> channels = makeChannels();
  return channels;
}

const ResultChannel* findResultChannel(const std::string& path) {
  for (const ResultChannel& c : resultChannels())
    if (path == c.path) return &c;
  return nullptr;
}

bool isRecorded(const ResultChannel& c, const Recording& rec) {
  const bool balancing = rec.has_balancing || rec.has_active_balancer;
  switch (c.presence) {
    case Presence::Always: return true;
    case Presence::Hardware: return rec.has_hardware;
    case Presence::Balancing: return balancing;
    case Presence::BalancingHardware: return balancing && rec.has_hardware;
    case Presence::Board: return rec.has_board;
    case Presence::ActiveBalancer: return rec.has_active_balancer;
    case Presence::Charger: return rec.has_charger;
    case Presence::Vehicle: return rec.has_vehicle;
  }
  return false;
}

size_t axisLength(Axis axis, const Recording& rec) {
  switch (axis) {
    case Axis::None: return 0;
    case Axis::Cell: return static_cast<size_t>(rec.cells);
    case Axis::Series: return static_cast<size_t>(rec.groups);
    case Axis::Thermistor: return static_cast<size_t>(rec.thermistors);
    case Axis::Device: return static_cast<size_t>(rec.devices);
    case Axis::TelemetryByte: return bms::kTelemetryFrameBytes;
  }
  return 0;
}

const char* axisName(Axis axis) {
  switch (axis) {
    case Axis::None: return "";
    case Axis::Cell: return "cell";
    case Axis::Series: return "series";
    case Axis::Thermistor: return "thermistor";
    case Axis::Device: return "device";
    case Axis::TelemetryByte: return "telemetry_byte";
  }
  return "";
}

const char* dtypeName(const ResultChannel& c) {
  static const char* const kNames[] = {"float64", "uint8", "int16", "uint16", "int32", "uint32"};
  static_assert(std::variant_size_v<AnyColumn> == sizeof(kNames) / sizeof(kNames[0]), "a dtype name per column type");
  return kNames[c.column.index()];
}

void recordSample(const ChannelSample& s, Recording& rec) {
  for (const ResultChannel& c : resultChannels()) {
    if (!isRecorded(c, rec)) continue;
    std::visit([&](const auto& col) { col.fill(s, rec.*(col.data)); }, c.column);
  }
}

int storedDecimals(const ResultChannel& c) {
  if (!std::holds_alternative<Column<double>>(c.column) || c.units == nullptr) return -1;
  const std::string u = c.units;
  if (u == "V" || u == "W") return 6;
  if (u == "A") return 5;
  if (u == "degC") return 4;
  if (u == "1" || u == "Ah") return 8;
  return -1;
}

}  // namespace packsim
