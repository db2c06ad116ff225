#include "core/sim/bms_image.hpp"

#include <bms/bms_firmware.hpp>
#include <bms/bms_settings.hpp>

#include <cmath>
#include <cstring>

#include "core/parts/monitor_parts.hpp"

namespace packsim {

namespace {

int32_t toInt(double v) { return static_cast<int32_t>(std::lround(v)); }

void setRule(bms::ProtectionRule& r, const ProtectionConfig& p, double scale) {
  r.enabled = p.enabled;
  r.threshold = toInt(p.threshold * scale);
  r.hysteresis = toInt(p.hysteresis * scale);
  r.delay_ms = static_cast<uint32_t>(std::lround(p.delay_s * 1e3));
  if (p.opens >= 0) r.opens = static_cast<uint8_t>(p.opens);
  r.action = p.action;
}

// Rules without a threshold of their own (boolean quantities, counts).
void setFlagRule(bms::ProtectionRule& r, const ProtectionConfig& p) {
  r.enabled = p.enabled;
  r.delay_ms = static_cast<uint32_t>(std::lround(p.delay_s * 1e3));
  if (p.opens >= 0) r.opens = static_cast<uint8_t>(p.opens);
  r.action = p.action;
}

bms::ProtectionRule& rule(bms::Config& c, bms::FaultId id) { return c.rules[static_cast<int>(id)]; }

// Where the balancing policy (a settings row each) meets the hardware: the boards' shape
// (their thermistors are in Config::therm); and the charger request.
void setBalancing(bms::Config& c, const Scenario& s) {
  bms::BalanceConfig& k = c.balance;
  k.boardCount = static_cast<uint8_t>(s.hardware.balancing.boards);
  k.cellsPerBoard = static_cast<uint16_t>(s.hardware.balancing.cells_per_board);
  const double request_A = s.bms.charge_current_A > 0.0 ? s.bms.charge_current_A
                           : s.charger.present          ? s.charger.current_A
                                                        : 0.0;
  c.chargeRequest_mA = toInt(request_A * 1e3);
}

// Read-out rates and the monitor stack: its part (driver) with the scenario's settings in
// the driver's units (the part's descriptor, core/parts), the stack's shape.
void setMonitors(bms::Config& c, const Scenario& s) {
  const BmsSettings& b = s.bms;
  const MonitorConfig& a = s.hardware.afe;
  auto ms = [](double t_s) { return static_cast<uint32_t>(std::lround(t_s * 1e3)); };
  c.readout.period_ms = b.readout.period_s > 0.0 ? ms(b.readout.period_s) : c.tickPeriod_ms;
  c.readout.alertPeriod_ms = ms(b.readout.alert_period_s);
  const MonitorPart& part = monitorPart(a.model);
  bms::afeSelect(c, firmwarePartIndex(part));
  part.firmware_settings(a, c.afe.settings);
  c.afe.deviceCount = static_cast<uint8_t>(a.devices);
  c.afe.cellsPerDevice = static_cast<uint8_t>(a.cells_per_device);
  c.afe.thermistorsPerDevice = static_cast<uint8_t>(a.thermistors_per_device);
}

}  // namespace

std::vector<uint8_t> coreImage(const bms::Config& cfg) {
  bms::CoreImage image{};
  image.tag = bms::kCoreImageTag;
  image.bytes = sizeof(bms::CoreImage);
  image.cfg = cfg;
  std::vector<uint8_t> blob(sizeof image);
  std::memcpy(blob.data(), &image, sizeof image);
  return blob;
}

bms::Config makeBmsConfig(const Scenario& s) {
  const HardwareConfig& hw = s.hardware;
  const BmsSettings& b = s.bms;
  bms::Config c = bms::defaultConfig(static_cast<uint16_t>(s.pack.series), static_cast<uint8_t>(hw.thermistors.count()));
  c.tickPeriod_ms = static_cast<uint32_t>(std::lround(b.tick_s * 1e3));
  // The firmware knows the datasheet scaling, not the part's actual error.
  c.scaling.cellLsb_uV = static_cast<float>(hw.cell_adc.lsb * 1e6);
  c.scaling.currentZeroCode = static_cast<float>(hw.current_sense.zeroCode());
  c.scaling.currentLsb_mA = static_cast<float>(hw.current_sense.lsb_A() * 1e3);
  c.scaling.currentCodeMax = static_cast<int32_t>((int64_t{1} << hw.current_sense.bits) - 1);
  c.scaling.thermFullScaleCode = static_cast<float>(hw.thermistor.fullScaleCode());
  c.scaling.thermPullup_ohm = static_cast<float>(hw.thermistor.pullup_ohm);
  c.scaling.thermR25_ohm = static_cast<float>(hw.thermistor.r25_ohm);
  c.scaling.thermBeta_K = static_cast<float>(hw.thermistor.beta_K);
  c.scaling.busLsb_mV = static_cast<float>(hw.bus_adc.lsb * 1e3);

  setMonitors(c, s);
  // The scalar settings, already in firmware units (bms/bms_settings.def).
  bms::copySettings(c, b.image);
  setSocConfig(c.soc, s);  // core/sim/soc_config.cpp: the model from the pack's cell
  setBalancing(c, s);
  setThermistorMap(c.therm, hw.thermistors);  // where each channel sits, as the loader built it

  // The protection table: SI settings scaled to firmware units row by row.
  using F = bms::FaultId;
  for (const ProtectionSpec& spec : protectionSpecs()) {
    const ProtectionConfig& p = b.protection(spec.id);
    switch (spec.use) {
      case ThresholdUse::Rule: setRule(rule(c, spec.id), p, spec.scale); break;
      case ThresholdUse::None: setFlagRule(rule(c, spec.id), p); break;
      case ThresholdUse::WeldCurrent:
        setFlagRule(rule(c, spec.id), p);
        c.weldCurrent_mA = toInt(p.threshold * spec.scale);
        break;
    }
  }
  rule(c, F::CommLoss).threshold = c.afe.commLossCount - 1;  // trips at the N-th bad reply
  return c;
}

}  // namespace packsim
