#include <bms/bms_limits.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "core/parts/monitor_parts.hpp"
#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/value_ranges.hpp"

namespace packsim {

namespace {

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

// The parts' names, "a or b" / "a, b or c".
std::string partList(const std::vector<const MonitorPart*>& parts) {
  std::string out;
  for (size_t i = 0; i < parts.size(); ++i)
    out += (i == 0 ? "" : i + 1 == parts.size() ? " or " : ", ") + std::string(parts[i]->name);
  return out;
}

// A key of hardware.afe that other parts have and this one does not.
void refuseOtherPartsKeys(YamlMap& afe, const MonitorPart& part) {
  auto owns = [](const MonitorPart& p, const std::string& key) {
    for (const PartKey& k : p.keys)
      if (key == k.key) return true;
    return false;
  };
  for (const MonitorPart* other : monitorParts())
    for (const PartKey& k : other->keys) {
      if (owns(part, k.key) || !afe.has(k.key)) continue;
      std::vector<const MonitorPart*> owners;
      for (const MonitorPart* p : monitorParts())
        if (owns(*p, k.key)) owners.push_back(p);
      throw afe.errorAt(k.key, "only a " + partList(owners) + " has `" + k.key + "` (this stack is a " + part.name +
                                   ")" + (*k.hint ? std::string("; ") + k.hint : ""));
    }
}

}  // namespace

// A CAN identifier or data byte: a whole number, decimal or 0x-hex, in [lo, hi].
uint32_t canInteger(const YamlMap& m, const YAML::Node& n, const std::string& field, unsigned long hi) {
  if (quotedScalar(n)) throw m.errorAt(n, field, quotedValueMessage(n, "expected a whole number (decimal or 0x hex)"));
  const std::string text = n.IsScalar() ? n.Scalar() : "";
  const bool hex = text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X');
  char* end = nullptr;
  errno = 0;
  const unsigned long v = text.empty() ? 0 : std::strtoul(text.c_str() + (hex ? 2 : 0), &end, hex ? 16 : 10);
  if (text.empty() || text[0] == '-' || errno != 0 || end == nullptr || *end != '\0' || (hex && text.size() == 2))
    throw m.errorAt(n, field, "expected a whole number (decimal or 0x hex), got '" + text + "'");
  if (v > hi) {
    char range[64];
    std::snprintf(range, sizeof range, "allowed [0, %lu] (0x%lX)", hi, hi);
    throw m.errorAt(n, field, text + " is out of range; " + range);
  }
  return static_cast<uint32_t>(v);
}

std::vector<ScriptedCanFrame> readCanFrames(YamlMap& can) {
  std::vector<ScriptedCanFrame> frames;
  std::vector<YamlMap> list = can.mapList("frames");
  for (size_t i = 0; i < list.size(); ++i) {
    YamlMap& f = list[i];
    ScriptedCanFrame fr;
    fr.at_s = f.number("at_s", Range::closed(0.0, limits::kMaxTime_s));
    fr.id = canInteger(f, f.node("id"), f.path() + ".id", 0x7FFu);
    const bool hasData = f.has("data");
    const YAML::Node data = hasData ? f.node("data") : YAML::Node();
    if (hasData && !data.IsSequence())
      throw f.errorAt(data, f.path() + ".data", "expected a list of 0 to 8 bytes like [0x01, 2, 255]");
    if (hasData && data.size() > 8)
      throw f.errorAt(data, f.path() + ".data",
                      std::to_string(data.size()) + " bytes: a classic CAN data frame carries at most 8");
    for (size_t k = 0; hasData && k < data.size(); ++k)
      fr.data.push_back(static_cast<uint8_t>(canInteger(f, data[k], f.path() + ".data" + "[" + std::to_string(k) + "]", 0xFFu)));
    fr.period_s = f.number("period_s", 0.0, Range::closed(0.0, limits::kMaxTime_s));
    if (f.has("period_s") && !(fr.period_s > 0.0))
      throw f.errorAt("period_s", "a period must be positive (leave it out for a single frame)");
    fr.until_s = f.number("until_s", limits::kMaxTime_s, Range::closed(fr.at_s, limits::kMaxTime_s));
    if (f.has("until_s") && !f.has("period_s")) throw f.errorAt("until_s", "until_s needs a period_s (a repeated frame)");
    f.finish();
    frames.push_back(fr);
  }
  return frames;
}

HardwareConfig readHardware(std::optional<YamlMap> hw, const PackConfig& pack) {
  HardwareConfig h;
  YAML::Node canFramesNode;  // hardware.can.frames, for an error once the boards are known
  // Defaults: a stack of the registry's first part (core/parts/monitor_parts.hpp),
  // 4 thermistors spread over the string, a 5 mΩ shunt into a gain-10 amplifier on a
  // 16-bit converter, an ideal relay, a discharge FET with its diode, no fuse.
  const int cells = pack.series;
  const MonitorPart* part = monitorParts().front();
  std::optional<YamlMap> afe = hw ? hw->optionalMap("afe") : std::nullopt;
  if (afe) {
    std::vector<std::string> names;
    for (const MonitorPart* p : monitorParts()) names.emplace_back(p->name);
    part = &monitorPart(afe->choice("model", part->name, names));
  }
  h.afe.model = part->name;
  part->defaults(h.afe, h.cell_adc);
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
      if (part->fixed_cell_codes != nullptr && (a->has("lsb_uV") || a->has("bits")))
        throw a->errorAt(a->has("lsb_uV") ? "lsb_uV" : "bits", std::string("a ") + part->name + " " +
                                                                    part->fixed_cell_codes +
                                                                    "; set only gain_error, offset_mV, noise_mV_rms");
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
    // Sections read even when absent, so that `packsim show` lists their defaults; an
    // absent section keeps the values above exactly (a unit round trip could change a bit).
    {
      YamlMap r = hw->mapOrEmpty("relay");
      RelayConfig relay = h.relay;
      readRelay(r, relay);
      r.finish();
      if (hw->has("relay")) h.relay = relay;
    }
    {
      YamlMap p = hw->mapOrEmpty("precharge");
      PrechargePathConfig pre = h.precharge;
      RelayConfig relay = h.precharge_relay;
      pre.r_ohm = p.number("r_ohm", pre.r_ohm, Range::positive(1.0e6));
      pre.bus_capacitance_F = p.number("bus_capacitance_uF", pre.bus_capacitance_F * 1e6, Range::positive(1.0e6)) * 1e-6;
      pre.bus_leak_ohm = p.number("bus_leak_ohm", 0.0, Range::nonNegative(limits::kMaxResistor_ohm));
      readRelay(p, relay);
      p.finish();
      if (hw->has("precharge")) {
        h.precharge = pre;
        h.precharge_relay = relay;
      }
    }
    if (auto f = hw->optionalMap("discharge_fet")) readFet(*f, h.discharge_fet);
    if (auto f = hw->optionalMap("charge_fet")) readFet(*f, h.charge_fet);
    if (hw->choice("fet_paths", "series", {"series", "separate"}) == "separate") {
      if (!h.charge_fet.present) throw hw->errorAt("fet_paths", "separate paths need a charge_fet as well");
      h.fet_paths = FetPaths::Separate;
    }
    // Who switches the gates: a part with FET drivers of its own drives them itself.
    const bool partFets = afe && part->driver->api->writeFets != nullptr;
    const std::string control = hw->choice("fet_control", partFets ? "afe" : "mcu", {"afe", "mcu", "afe_and_mcu"});
    if (control != "mcu" && !partFets) {
      std::string owners;
      for (const MonitorPart* p : monitorParts())
        if (p->driver->api->writeFets != nullptr) owners += std::string(owners.empty() ? "" : " or ") + p->name;
      throw hw->errorAt("fet_control", "`" + control + "` needs a monitor part that drives FETs of its own (" + owners +
                                           "; this board's is " + (afe ? "a " + std::string(part->name) : std::string("none")) +
                                           "); allowed here: mcu");
    }
    h.fet_control = control == "afe" ? FetControl::Afe : control == "afe_and_mcu" ? FetControl::AfeAndMcu : FetControl::Mcu;
    if (auto f = hw->optionalMap("fuse")) {
      h.fuse.present = f->boolean("present", true);
      h.fuse.rated_A = f->number("rated_A", h.fuse.rated_A, Range::positive(limits::kMaxCurrent_A));
      h.fuse.i2t_A2s = f->number("i2t_A2s", h.fuse.i2t_A2s, Range::positive(1.0e10));  // 100 kA for 1 s
      h.fuse.hold_ratio = f->number("hold_ratio", h.fuse.hold_ratio, Range::closed(1.0, 3.0));
      f->finish();
    }
    if (auto b = hw->optionalMap("balancing")) h.balancing = readPassiveBalancer(*b);
    if (auto c = hw->optionalMap("can")) {  // between the monitor boards' MCUs, or a board alone's to the vehicle
      h.can_bitrate_bps = c->number("bitrate_kbps", h.can_bitrate_bps * 1e-3, Range::closed(10.0, 1000.0)) * 1e3;
      h.can_alone = true;  // judged against the boards below
      if (c->has("frames")) {
        canFramesNode = c->node("frames");
        h.can_frames = readCanFrames(*c);
      }
      c->finish();
    }
    if (auto m = hw->optionalMap("mcu_supply")) {  // the BMS board's rail and the MCU's brown-out level on it
      h.supply_nominal_V = m->number("nominal_V", h.supply_nominal_V, Range::closed(3.0, 60.0));
      h.supply_brownout_V = m->number("brownout_V", h.supply_brownout_V, Range::closed(0.5, 60.0));
      if (!(h.supply_brownout_V < h.supply_nominal_V)) {
        char why[120];
        std::snprintf(why, sizeof why, "the brown-out threshold must lie below nominal_V (%g V); allowed [0.5, %g)",
                      h.supply_nominal_V, h.supply_nominal_V);
        throw m->errorAt("brownout_V", why);
      }
      m->finish();
    }
    if (auto b = hw->optionalMap("active_balancer")) h.active_balancer = readActiveBalancer(*b);
    {
      YamlMap b = hw->mapOrEmpty("bus_adc");
      const double fs = b.number("full_scale_V", h.bus_adc.lsb * 4095.0, Range::positive(2000.0));  // the charger's voltage range
      const long bits = b.integer("bits", 12, 8, 16);
      const double noise_V = b.number("noise_mV_rms", 0.0, Range::closed(0.0, 10000.0)) * 1e-3;
      b.finish();
      if (hw->has("bus_adc")) {
        h.bus_adc.code_max = (int64_t{1} << bits) - 1;
        h.bus_adc.lsb = fs / static_cast<double>(h.bus_adc.code_max);
        h.bus_adc.noise_rms = noise_V;
      }
    }
  }

  // The monitor stack: cells split over devices, thermistors over their inputs.
  MonitorConfig& a = h.afe;
  a.cell_adc = h.cell_adc;
  a.thermistor = h.thermistor;
  a.shunt_ohm = h.current_sense.shunt_ohm;
  a.cells_per_device = std::min(part->max_cells, cells);
  if (afe) {
    a.cells_per_device = static_cast<int>(afe->integer("cells_per_device", a.cells_per_device, 1, part->max_cells));
    const int needed = (cells + a.cells_per_device - 1) / a.cells_per_device;
    if (!part->stacked && needed > 1) {  // one device alone on its bus: the pack must fit it
      std::vector<const MonitorPart*> stacked;
      for (const MonitorPart* p : monitorParts())
        if (p->stacked) stacked.push_back(p);
      throw afe->errorAt("model", std::string("a ") + part->name + " monitors one stack of up to " +
                                      std::to_string(part->max_cells) + " series cells; this pack has " +
                                      std::to_string(cells) + " (pack.series): use a stacked part (" +
                                      partList(stacked) + ")");
    }
    a.devices = static_cast<int>(afe->integer("devices", needed, 1, bms::kMaxDevices));
    if (a.devices != needed) {
      std::ostringstream os;
      os << pack.series << " series cells at " << a.cells_per_device << " per device need " << needed << " devices";
      throw afe->errorAt("devices", os.str());
    }
    a.thermistors_per_device =
        static_cast<int>(afe->integer("thermistors_per_device", a.thermistors_per_device, 1, part->max_thermistors));
    if (afe->has("devices_per_board")) {  // several monitor boards, each with its own host MCU
      if (!part->stacked) {
        std::vector<const MonitorPart*> stacked;
        for (const MonitorPart* p : monitorParts())
          if (p->stacked) stacked.push_back(p);
        throw afe->errorAt("devices_per_board", std::string("a ") + part->name + " sits alone on its bus: boards are "
                                                "for stacked parts (" + partList(stacked) + ")");
      }
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
    refuseOtherPartsKeys(*afe, *part);
    part->read_keys(*afe, a);
    h.fault_line_opens_relay = afe->boolean("fault_line_opens_relay", true);
    afe->finish();
  } else {
    // Without an `afe` section the stack is the plain cell ADC of earlier versions:
    // no secondary protection of its own.
    a.devices = (cells + a.cells_per_device - 1) / a.cells_per_device;
    a.secondary.enabled = false;
  }
  // Which of each device's inputs sit on the FETs (MonitorConfig::fet_inputs).
  a.fet_inputs = 0;
  const size_t onInputs = std::min(h.thermistor_sites.size(), static_cast<size_t>(a.devices * a.thermistors_per_device));
  for (size_t k = 0; k < onInputs; ++k)
    if (!h.thermistor_sites[k].onCell()) a.fet_inputs |= 1u << (k % static_cast<size_t>(a.thermistors_per_device));
  if (h.afe.devices_per_board > 0) {
    h.can_alone = false;  // the bus links the boards' MCUs (packsim's core on each)
    if (!h.can_frames.empty())
      throw hw->errorAt(canFramesNode, "hardware.can.frames",
                        "scripted frames need a board alone: with hardware.afe.devices_per_board the bus carries "
                        "packsim's core's own frames between the boards");
  }
  if (hw) hw->finish();
  return h;
}

}  // namespace packsim
