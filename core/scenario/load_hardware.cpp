#include <bms/bms_limits.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/value_ranges.hpp"
#include "models/afe/bq76pl455a.hpp"

namespace packsim {

namespace {

struct AfeModelInfo {
  const char* name;
  bms::AfeModel model;
  int max_cells;        // per device
  int max_thermistors;  // inputs per device
};

constexpr AfeModelInfo kAfeModels[] = {
    {"bq76pl536a", bms::AfeModel::Bq76pl536a, 6, 2},
    {"bq76pl455a", bms::AfeModel::Bq76pl455a, 16, 8},
    {"bq76952", bms::AfeModel::Bq76952, 16, 3},
};

// The cell channel of each monitor class (the parts' datasheets).
void afeDefaults(const AfeModelInfo& m, MonitorConfig& a, AdcChannel& adc) {
  a.model = m.model;
  switch (m.model) {
    case bms::AfeModel::Bq76pl536a:
      adc.lsb = 6.25 / 16383.0;
      adc.code_max = (1 << 14) - 1;
      adc.noise_rms = 0.5e-3;
      a.thermistors_per_device = 2;
      a.baud = 1e6;  // SPI
      a.measurement_period_s = 0.0;
      break;
    case bms::AfeModel::Bq76pl455a:
      adc.lsb = 5.0 / 65535.0;
      adc.code_max = 65535;
      adc.noise_rms = 0.3e-3;
      a.thermistors_per_device = 2;
      a.baud = 250000.0;
      a.conversion_s_per_channel = 100e-6;
      a.measurement_period_s = 0.0;
      break;
    case bms::AfeModel::Bq76952:
      adc.lsb = 1e-3;  // reports mV
      adc.code_max = 32767;
      adc.noise_rms = 1.0e-3;
      a.thermistors_per_device = 3;
      a.baud = 400000.0;  // I2C fast mode
      a.conversion_s_per_channel = 3e-3;
      a.measurement_period_s = 0.06;
      break;
  }
}

void readRelay(YamlMap& m, RelayConfig& r) {
  r.close_delay_s = m.number("close_delay_ms", r.close_delay_s * 1e3, Range::closed(0.0, 1000.0)) * 1e-3;
  r.open_delay_s = m.number("open_delay_ms", r.open_delay_s * 1e3, Range::closed(0.0, 1000.0)) * 1e-3;
}

void readFet(YamlMap& m, MosfetConfig& f) {
  f.present = m.boolean("present", true);
  f.rds_on_ohm = m.number("rds_on_ohm", f.rds_on_ohm, Range::nonNegative(10.0));  // 10 ohm carries no pack current
  f.diode_vf_V = m.number("diode_vf_V", f.diode_vf_V, Range::closed(0.0, 2.0));
  f.diode_r_ohm = m.number("diode_r_ohm", f.diode_r_ohm, Range::nonNegative(10.0));
  f.thermal_node = m.string("thermal_node", f.thermal_node);
  m.finish();
}

// The BQ76952's autonomous balancing, in the ranges its data memory holds.
void readBq952Balancing(YamlMap& m, Bq952AutoBalance& b) {
  const std::string when = m.choice("when", "charging", {"charging", "rest", "charging_or_rest"});
  b.charging = when != "rest";
  b.relax = when != "charging";
  b.min_cell_V = m.number("min_cell_V", b.min_cell_V, Range::closed(0.0, 5.0));
  b.start_delta_mV = m.number("start_delta_mV", b.start_delta_mV, Range::closed(0.0, 255.0));
  b.stop_delta_mV = m.number("stop_delta_mV", b.stop_delta_mV, Range::closed(0.0, 255.0));
  if (!(b.stop_delta_mV <= b.start_delta_mV)) throw m.errorAt("stop_delta_mV", "must not exceed start_delta_mV");
  b.max_cells = static_cast<int>(m.integer("max_cells", b.max_cells, 1, 16));
  const Range temp = Range::closed(-40.0, 120.0);
  b.min_cell_temp_C = m.number("min_cell_temp_C", b.min_cell_temp_C, temp);
  b.max_cell_temp_C = m.number("max_cell_temp_C", b.max_cell_temp_C, temp);
  if (!(b.min_cell_temp_C < b.max_cell_temp_C)) throw m.errorAt("max_cell_temp_C", "must be above min_cell_temp_C");
  b.max_internal_C = m.number("max_internal_C", b.max_internal_C, temp);
  m.finish();
}

void readSecondary(YamlMap& m, SecondaryProtection& p, bool pl455) {
  p.enabled = m.boolean("enabled", p.enabled);
  p.cov_V = m.number("cov_V", p.cov_V, Range::closed(2.0, 5.0));
  p.cov_delay_s = m.number("cov_delay_ms", p.cov_delay_s * 1e3, Range::closed(0.0, 3100.0)) * 1e-3;
  p.cuv_V = m.number("cuv_V", p.cuv_V, Range::closed(0.7, 3.3));
  p.cuv_delay_s = m.number("cuv_delay_ms", p.cuv_delay_s * 1e3, Range::closed(0.0, 3100.0)) * 1e-3;
  p.ot_C = m.number("ot_C", p.ot_C, Range::closed(40.0, 90.0));
  p.ot_delay_s = m.number("ot_delay_ms", p.ot_delay_s * 1e3, Range::closed(0.0, 2550.0)) * 1e-3;
  if (m.has("comm_timeout_ms")) {
    if (!pl455) throw m.errorAt("comm_timeout_ms", "only a bq76pl455a supervises its link (a communication timeout)");
    p.comm_timeout_s = m.number("comm_timeout_ms", 0.0, Range::nonNegative(600000.0)) * 1e-3;
    if (pl455CommTimeoutCode(p.comm_timeout_s) < 0)
      throw m.errorAt("comm_timeout_ms", "the part's timer steps are 0 (off), 100, 2000, 10000, 60000, 600000, "
                                         "1800000 or 7200000 ms");
  }
  m.finish();
}

// The part's own protections, in the ranges and steps its data memory holds (the
// register-level model refuses a value between steps' ends; these ranges catch the rest
// with the scenario's file and line).
void readBq952(YamlMap& m, Bq952Protection& p) {
  const Range temp = Range::closed(-40.0, 120.0);
  const Range seconds = Range::closed(0.0, 255000.0);        // U1, 1 s steps
  const Range voltageDelay = Range::closed(3.3, 6755.1);     // U2 1..2047 x 3.3 ms
  const Range currentDelay = Range::closed(9.9, 425.7);      // U1 1..127: (n + 2) x 3.3 ms
  p.cov_V = m.number("cov_V", p.cov_V, Range::closed(1.012, 5.566));
  p.cov_delay_s = m.number("cov_delay_ms", p.cov_delay_s * 1e3, voltageDelay) * 1e-3;
  p.cov_recovery_V = m.number("cov_recovery_V", p.cov_recovery_V, Range::closed(0.0, 1.012));
  p.cuv_V = m.number("cuv_V", p.cuv_V, Range::closed(1.012, 4.554));
  p.cuv_delay_s = m.number("cuv_delay_ms", p.cuv_delay_s * 1e3, voltageDelay) * 1e-3;
  p.cuv_recovery_V = m.number("cuv_recovery_V", p.cuv_recovery_V, Range::closed(0.0, 1.012));
  p.occ_mV = m.number("occ_mV", p.occ_mV, Range::closed(4.0, 124.0));
  p.occ_delay_s = m.number("occ_delay_ms", p.occ_delay_s * 1e3, currentDelay) * 1e-3;
  p.ocd1_mV = m.number("ocd1_mV", p.ocd1_mV, Range::closed(4.0, 200.0));
  p.ocd1_delay_s = m.number("ocd1_delay_ms", p.ocd1_delay_s * 1e3, currentDelay) * 1e-3;
  p.scd_mV = m.number("scd_mV", p.scd_mV, Range::closed(10.0, 500.0));
  // USER_AMPS: the unit of the part's current readings and of OCD3's threshold.
  const std::string ua = m.choice("user_amps_mA", "1", {"0.1", "1", "10", "100"});
  p.user_amps_A = std::stod(ua) * 1e-3;
  p.ocd3_A = m.number("ocd3_A", p.ocd3_A, Range::closed(0.0, 32767.0 * p.user_amps_A));
  p.ocd3_delay_s = m.number("ocd3_delay_ms", p.ocd3_delay_s * 1e3, seconds) * 1e-3;
  p.current_recovery_s = m.number("current_recovery_ms", p.current_recovery_s * 1e3, seconds) * 1e-3;
  p.otc_C = m.number("otc_C", p.otc_C, temp);
  p.otd_C = m.number("otd_C", p.otd_C, temp);
  p.otf_C = m.number("otf_C", p.otf_C, temp);
  p.ot_delay_s = m.number("ot_delay_ms", p.ot_delay_s * 1e3, seconds) * 1e-3;
  p.utc_C = m.number("utc_C", p.utc_C, temp);
  p.utd_C = m.number("utd_C", p.utd_C, temp);
  p.ut_delay_s = m.number("ut_delay_ms", p.ut_delay_s * 1e3, seconds) * 1e-3;
  p.temp_recovery_C = m.number("temp_recovery_C", p.temp_recovery_C, Range::closed(0.0, 50.0));
  m.finish();
}

}  // namespace

HardwareConfig readHardware(std::optional<YamlMap> hw, const PackConfig& pack) {
  HardwareConfig h;
  // Defaults: a BQ76PL536A-class stack (14-bit cell ADC, up to 6 cells per device),
  // 4 thermistors spread over the string, a 5 mΩ shunt into a gain-10 amplifier on a
  // 16-bit converter, an ideal relay, a discharge FET with its diode, no fuse.
  const int cells = pack.series;
  const AfeModelInfo* model = &kAfeModels[0];
  std::optional<YamlMap> afe = hw ? hw->optionalMap("afe") : std::nullopt;
  if (afe) {
    std::vector<std::string> names;
    for (const auto& m : kAfeModels) names.emplace_back(m.name);
    const std::string name = afe->choice("model", "bq76pl536a", names);
    for (const auto& m : kAfeModels)
      if (name == m.name) model = &m;
  }
  afeDefaults(*model, h.afe, h.cell_adc);
  h.current_sense.amp_gain = 10.0;
  h.current_sense.noise_A_rms = 0.02;
  for (int k = 0; k < std::min(4, cells); ++k) h.thermistor_sites.push_back({k * cells / std::min(4, cells), ""});
  h.charge_fet.present = false;
  h.charge_fet.diode_passes_charge = false;  // a charge FET's diode passes discharge current
  h.fuse.present = false;
  const double busFullScale_V = std::max(5.0, 1.25 * cells * pack.cell.v_max_V);
  h.bus_adc.lsb = busFullScale_V / 4095.0;
  h.bus_adc.code_max = 4095;

  if (hw) {
    if (auto a = hw->optionalMap("cell_adc")) {
      // 100 mV: a coarser converter reads no cell.
      h.cell_adc.lsb = a->number("lsb_uV", h.cell_adc.lsb * 1e6, Range::positive(100000.0)) * 1e-6;
      const long defaultBits = std::lround(std::log2(static_cast<double>(h.cell_adc.code_max + 1)));
      const long bits = a->integer("bits", defaultBits, 8, 24);
      h.cell_adc.code_max = (int64_t{1} << bits) - 1;
      h.cell_adc.gain_error = a->number("gain_error", 0.0, Range::closed(-0.5, 0.5));
      h.cell_adc.offset = a->number("offset_mV", 0.0, Range::closed(-500.0, 500.0)) * 1e-3;
      h.cell_adc.noise_rms = a->number("noise_mV_rms", h.cell_adc.noise_rms * 1e3, Range::closed(0.0, 500.0)) * 1e-3;
      if (h.cell_adc.code_max > 65535) throw a->errorAt("bits", "the monitor frames carry 16-bit cell codes; allowed 8..16");
      if (model->model == bms::AfeModel::Bq76952 && (a->has("lsb_uV") || a->has("bits")))
        throw a->errorAt(a->has("lsb_uV") ? "lsb_uV" : "bits", "a bq76952 reports cells in mV; set only gain_error, offset_mV, noise_mV_rms");
      a->finish();
    }
    if (auto t = hw->optionalMap("thermistors")) {
      // Thermistors count series groups (1..series), each on its group's first cell; the
      // old key at_cells counted groups too and is refused rather than reinterpreted.
      const std::string groupsText = "1.." + std::to_string(cells) + " series groups";
      if (t->has("at_cells"))
        throw t->errorAt("at_cells", "thermistors sit on series groups: write at_groups: [...] (" + groupsText +
                                         ", each on its group's first cell); at_cells was renamed because a pack's "
                                         "cells count 1..series*parallel");
      if (t->has("at_groups") && t->has("channels"))
        throw t->errorAt("channels", "give either at_groups (every thermistor on a series group) or channels, not both");
      if (t->has("at_groups")) {
        h.thermistor_sites.clear();
        for (long c : t->integers("at_groups", 1, cells)) h.thermistor_sites.push_back({static_cast<int>(c - 1), ""});
        if (h.thermistor_sites.size() > bms::kMaxThermistors)
          throw t->errorAt("at_groups", "at most " + std::to_string(bms::kMaxThermistors) + " thermistors");
      }
      if (t->has("channels")) {  // in wiring order, each {group: N} or {node: NAME}
        h.thermistor_sites.clear();
        for (YamlMap c : t->mapList("channels")) {
          if (c.has("cell"))
            throw c.errorAt("cell", "a thermistor channel sits on a series group: write {group: N} (" + groupsText + ")");
          if (c.has("group") == c.has("node")) throw c.error("a thermistor channel is either {group: N} or {node: NAME}");
          if (c.has("group"))
            h.thermistor_sites.push_back({static_cast<int>(c.integer("group", 1, cells) - 1), ""});
          else
            h.thermistor_sites.push_back({-1, c.string("node")});
          c.finish();
        }
        if (h.thermistor_sites.empty() || h.thermistor_sites.size() > bms::kMaxThermistors)
          throw t->errorAt("channels", "1.." + std::to_string(bms::kMaxThermistors) + " thermistors");
      }
      h.thermistor.r25_ohm = t->number("r25_ohm", h.thermistor.r25_ohm, Range::positive(1.0e7));
      h.thermistor.beta_K = t->number("beta_K", h.thermistor.beta_K, Range::closed(1000.0, 10000.0));
      h.thermistor.pullup_ohm = t->number("pullup_ohm", h.thermistor.pullup_ohm, Range::positive(1.0e7));
      h.thermistor.bits = static_cast<int>(t->integer("bits", 12, 8, 16));
      h.thermistor.noise_codes_rms = t->number("noise_codes_rms", 0.0, Range::closed(0.0, 100.0));
      t->finish();
    }
    if (auto c = hw->optionalMap("current_sense")) {
      CurrentSense& s = h.current_sense;
      s.shunt_ohm = c->number("shunt_ohm", s.shunt_ohm, Range::positive(1.0));  // a shunt, not a load
      s.amp_gain = c->number("amp_gain", s.amp_gain, Range::positive(10000.0));
      s.amp_offset_V = c->number("amp_offset_mV", 0.0, Range::closed(-1000.0, 1000.0)) * 1e-3;
      s.gain_error = c->number("gain_error", 0.0, Range::closed(-0.5, 0.5));
      s.noise_A_rms = c->number("noise_A_rms", s.noise_A_rms, Range::nonNegative(1000.0));
      s.vref_V = c->number("vref_V", s.vref_V, Range::closed(0.5, 10.0));
      s.bits = static_cast<int>(c->integer("bits", 16, 8, 24));
      c->finish();
    }
    if (auto r = hw->optionalMap("relay")) {
      readRelay(*r, h.relay);
      r->finish();
    }
    if (auto p = hw->optionalMap("precharge")) {
      h.precharge.r_ohm = p->number("r_ohm", h.precharge.r_ohm, Range::positive(1.0e6));
      h.precharge.bus_capacitance_F =
          p->number("bus_capacitance_uF", h.precharge.bus_capacitance_F * 1e6, Range::positive(1.0e6)) * 1e-6;
      h.precharge.bus_leak_ohm = p->number("bus_leak_ohm", 0.0, Range::nonNegative(limits::kMaxResistor_ohm));
      readRelay(*p, h.precharge_relay);
      p->finish();
    }
    if (auto f = hw->optionalMap("discharge_fet")) readFet(*f, h.discharge_fet);
    if (auto f = hw->optionalMap("charge_fet")) readFet(*f, h.charge_fet);
    if (hw->choice("fet_paths", "series", {"series", "separate"}) == "separate") {
      if (!h.charge_fet.present) throw hw->errorAt("fet_paths", "separate paths need a charge_fet as well");
      h.fet_paths = FetPaths::Separate;
    }
    if (auto f = hw->optionalMap("fuse")) {
      h.fuse.present = f->boolean("present", true);
      h.fuse.rated_A = f->number("rated_A", h.fuse.rated_A, Range::positive(limits::kMaxCurrent_A));
      h.fuse.i2t_A2s = f->number("i2t_A2s", h.fuse.i2t_A2s, Range::positive(1.0e10));  // 100 kA for 1 s
      h.fuse.hold_ratio = f->number("hold_ratio", h.fuse.hold_ratio, Range::closed(1.0, 3.0));
      f->finish();
    }
    if (auto b = hw->optionalMap("balancing")) h.balancing = readPassiveBalancer(*b);
    if (auto c = hw->optionalMap("can")) {  // between the monitor boards' MCUs
      h.can_bitrate_bps = c->number("bitrate_kbps", h.can_bitrate_bps * 1e-3, Range::closed(10.0, 1000.0)) * 1e3;
      c->finish();
    }
    if (auto b = hw->optionalMap("active_balancer")) h.active_balancer = readActiveBalancer(*b);
    if (auto b = hw->optionalMap("bus_adc")) {
      const double fs = b->number("full_scale_V", h.bus_adc.lsb * 4095.0, Range::positive(2000.0));  // the charger's voltage range
      const long bits = b->integer("bits", 12, 8, 16);
      h.bus_adc.code_max = (int64_t{1} << bits) - 1;
      h.bus_adc.lsb = fs / static_cast<double>(h.bus_adc.code_max);
      h.bus_adc.noise_rms = b->number("noise_mV_rms", 0.0, Range::closed(0.0, 10000.0)) * 1e-3;
      b->finish();
    }
  }

  // The monitor stack: cells split over devices, thermistors over their inputs.
  MonitorConfig& a = h.afe;
  a.cell_adc = h.cell_adc;
  a.thermistor = h.thermistor;
  a.shunt_ohm = h.current_sense.shunt_ohm;
  a.cells_per_device = std::min(model->max_cells, cells);
  if (afe) {
    a.cells_per_device = static_cast<int>(afe->integer("cells_per_device", a.cells_per_device, 1, model->max_cells));
    const int needed = (cells + a.cells_per_device - 1) / a.cells_per_device;
    a.devices = static_cast<int>(afe->integer("devices", needed, 1, bms::kMaxDevices));
    if (a.devices != needed) {
      std::ostringstream os;
      os << pack.series << " series cells at " << a.cells_per_device << " per device need " << needed << " devices";
      throw afe->errorAt("devices", os.str());
    }
    a.thermistors_per_device =
        static_cast<int>(afe->integer("thermistors_per_device", a.thermistors_per_device, 1, model->max_thermistors));
    if (afe->has("devices_per_board")) {  // several monitor boards, each with its own host MCU
      if (a.model == bms::AfeModel::Bq76952)
        throw afe->errorAt("devices_per_board", "a bq76952 sits alone on its bus: boards are for stacked parts "
                                                "(bq76pl536a, bq76pl455a)");
      a.devices_per_board = static_cast<int>(afe->integer("devices_per_board", 1, a.devices));
      const int boards = (a.devices + a.devices_per_board - 1) / a.devices_per_board;
      if (boards > bms::kMaxBoards)
        throw afe->errorAt("devices_per_board", std::to_string(a.devices) + " devices at " +
                                                    std::to_string(a.devices_per_board) + " per board make " +
                                                    std::to_string(boards) + " boards; at most " +
                                                    std::to_string(bms::kMaxBoards));
    }
    a.channel_gain_sd = afe->number("channel_gain_sd", 0.0, Range::closed(0.0, 0.2));
    a.channel_offset_sd_V = afe->number("channel_offset_sd_mV", 0.0, Range::closed(0.0, 100.0)) * 1e-3;
    a.module_noise_V = afe->number("module_noise_mV_rms", 0.0, Range::closed(0.0, 1000.0)) * 1e-3;
    a.die_rise_C = afe->number("die_rise_C", a.die_rise_C, Range::closed(0.0, 100.0));
    a.thermistor_bias_A = afe->number("thermistor_bias_mA", 0.0, Range::closed(0.0, 100.0)) * 1e-3;
    a.measurement_period_s =
        afe->number("measurement_period_ms", a.measurement_period_s * 1e3, Range::closed(0.0, 10000.0)) * 1e-3;
    a.baud = afe->number("baud", a.baud, Range::closed(9600.0, 1e7));
    if (afe->has("crc")) {
      if (a.model != bms::AfeModel::Bq76952) throw afe->errorAt("crc", "only a bq76952 has an optional CRC");
      a.crc = afe->boolean("crc", true);
    }
    if (afe->has("oversampling")) {  // the one monitor class here that averages in hardware
      if (a.model != bms::AfeModel::Bq76pl455a)
        throw afe->errorAt("oversampling", "only a bq76pl455a averages conversions in hardware; average in firmware "
                                           "with bms.balancing.average_readings");
      a.oversampling = static_cast<int>(afe->integer("oversampling", 1, 1, 32));
      if ((a.oversampling & (a.oversampling - 1)) != 0)
        throw afe->errorAt("oversampling", "must be 1, 2, 4, 8, 16 or 32 samples");
      a.cell_adc.noise_rms /= std::sqrt(static_cast<double>(a.oversampling));
    }
    if (auto s = afe->optionalMap("secondary")) {
      if (a.model == bms::AfeModel::Bq76952) throw afe->errorAt("secondary", "a bq76952 uses `protection`, not `secondary`");
      readSecondary(*s, a.secondary, a.model == bms::AfeModel::Bq76pl455a);
    }
    if (auto p = afe->optionalMap("protection")) {
      if (a.model != bms::AfeModel::Bq76952) throw afe->errorAt("protection", "only a bq76952 has `protection`; use `secondary`");
      readBq952(*p, a.bq);
    }
    if (auto b = afe->optionalMap("autonomous_balancing")) {
      if (a.model != bms::AfeModel::Bq76952)
        throw afe->errorAt("autonomous_balancing", "only a bq76952 balances on its own; use bms.balancing");
      readBq952Balancing(*b, a.bq_balance);
    }
    h.fault_line_opens_relay = afe->boolean("fault_line_opens_relay", true);
    afe->finish();
  } else {
    // Without an `afe` section the stack is the plain cell ADC of earlier versions:
    // no secondary protection of its own.
    a.devices = (cells + a.cells_per_device - 1) / a.cells_per_device;
    a.secondary.enabled = false;
  }
  // Which of each device's inputs sit on the FETs (a bq76952 judges those by OTF).
  a.fet_inputs = 0;
  const size_t onInputs = std::min(h.thermistor_sites.size(), static_cast<size_t>(a.devices * a.thermistors_per_device));
  for (size_t k = 0; k < onInputs; ++k)
    if (!h.thermistor_sites[k].onCell()) a.fet_inputs |= 1u << (k % static_cast<size_t>(a.thermistors_per_device));
  if (hw) hw->finish();
  return h;
}

}  // namespace packsim
