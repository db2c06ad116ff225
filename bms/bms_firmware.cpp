#include "bms_firmware.hpp"

#include <cstring>

namespace bms {

namespace {

CoreFirmwareRam& ramOf(void* ram) { return *static_cast<CoreFirmwareRam*>(ram); }

uint8_t mcuThermistors(const Config& c) { return static_cast<uint8_t>(c.thermistorCount - afeThermistorChannels(c)); }

// The pins and ADC channels the core reads each control tick.
void readPins(const Config& c, Inputs& in, psfw_board* b, const psfw_board_api* api) {
  in.now_ms = api->now_ms(b);
  in.currentCode = api->adc_read(b, PSFW_ADC_CURRENT);
  in.busVoltageCode = static_cast<uint16_t>(api->adc_read(b, PSFW_ADC_BUS_VOLTAGE));
  for (uint8_t k = 0; k < mcuThermistors(c); ++k)
    in.mcuThermistorCode[k] = static_cast<uint16_t>(api->adc_read(b, static_cast<uint8_t>(PSFW_ADC_THERMISTOR0 + k)));
  in.eSwitchInternal = api->gpio_read(b, PSFW_IN_ESWITCH_INTERNAL) == 1;
  in.eSwitchExternal = api->gpio_read(b, PSFW_IN_ESWITCH_EXTERNAL) == 1;
  in.relayAux = api->gpio_read(b, PSFW_IN_RELAY_AUX) == 1;
  in.monitorFaultPin = api->gpio_read(b, PSFW_IN_MONITOR_FAULT) == 1;
  in.chargerPresent = api->gpio_read(b, PSFW_IN_CHARGER_PRESENT) == 1;
  in.runRequest = api->gpio_read(b, PSFW_IN_RUN_REQUEST) == 1;
  in.resetRequest = api->gpio_read(b, PSFW_IN_RESET_REQUEST) == 1;
}

void writePins(const Outputs& out, psfw_board* b, const psfw_board_api* api) {
  api->gpio_write(b, PSFW_OUT_RELAY, out.relayClose ? 1 : 0);
  api->gpio_write(b, PSFW_OUT_PRECHARGE, out.prechargeClose ? 1 : 0);
  api->gpio_write(b, PSFW_OUT_DISCHARGE_FET, out.dischargeFetOn ? 1 : 0);
  api->gpio_write(b, PSFW_OUT_CHARGE_FET, out.chargeFetOn ? 1 : 0);
  api->gpio_write(b, PSFW_OUT_CHARGER_ENABLE, out.chargerEnable ? 1 : 0);
  api->dac_write(b, PSFW_DAC_CHARGER_CURRENT_MA, out.chargerCurrentRequest_mA);
}

// Monitor writes the tick's decisions need: only what changed goes on the bus.
void writeMonitors(CoreFirmwareRam& r, psfw_board* b, const psfw_board_api* api) {
  const Outputs& out = r.out;
  if (out.afeClearFaults) monitorClearFaults(r.cfg, r.monitors, b, api);
  uint32_t maskDiff = 0;  // every word's difference ORed: no branch per word
  for (uint8_t w = 0; w < kBalanceWords; ++w) maskDiff |= out.balanceMask[w] ^ r.writtenMask[w];
  if (maskDiff != 0 || out.balanceArmCount != r.writtenArm) {
    monitorWriteBalance(r.cfg, r.monitors, b, api, out.balanceMask, out.balanceTime_s);
    for (uint8_t w = 0; w < kBalanceWords; ++w) r.writtenMask[w] = out.balanceMask[w];
    r.writtenArm = out.balanceArmCount;
  }
  if (monitorHasFets(r.cfg) &&
      (!r.fetsWritten || out.chargeFetOn != r.writtenChg || out.dischargeFetOn != r.writtenDsg)) {
    monitorWriteFets(r.cfg, r.monitors, b, api, out.chargeFetOn, out.dischargeFetOn);
    r.fetsWritten = true;
    r.writtenChg = out.chargeFetOn;
    r.writtenDsg = out.dischargeFetOn;
  }
}

void readoutTask(void* ram, psfw_board* b, const psfw_board_api* api) {
  CoreFirmwareRam& r = ramOf(ram);
  r.readoutDue_ms = api->now_ms(b);
  monitorReadAll(r.cfg, r.monitors, r.core.acq, b, api);
}

// A poll due with a read-out (which has just read the same flags) is skipped.
void alertTask(void* ram, psfw_board* b, const psfw_board_api* api) {
  CoreFirmwareRam& r = ramOf(ram);
  if (r.core.acq.readOut && api->now_ms(b) - r.readoutDue_ms < r.cfg.readout.alertPeriod_ms) return;
  monitorPollAlerts(r.cfg, r.monitors, r.core.acq, b, api);
}

void controlTask(void* ram, psfw_board* b, const psfw_board_api* api) {
  CoreFirmwareRam& r = ramOf(ram);
  readPins(r.cfg, r.in, b, api);
  // Only a pack of several boards has frames to exchange (bms_pack.hpp): a board alone
  // skips the calls, which would return at once (their arguments cost some 70
  // instructions a tick).
  const bool severalBoards = r.cfg.pack.boards > 1;
  if (severalBoards) packReceive(r.cfg, r.core.pack, r.in.now_ms, b, api);
  const bool readOut = r.core.acq.readOut;  // a member reports each read-out, good or bad
  step(r.cfg, r.core, r.in, r.out);
  if (severalBoards) {
    uint16_t range[2];
    balanceRange(r.cfg, r.core.balance, r.out.telemetry, range[0], range[1]);
    packSend(r.cfg, r.core.pack, r.out, r.core.balancePermitted, r.out.state == State::Charge, readOut, r.core.quantity,
             range, b, api);
  }
  writePins(r.out, b, api);
  writeMonitors(r, b, api);
  api->telemetry_send(b, r.telemetry, telemetryEncode(r.out, r.telemetry));
}

int32_t coreInit(void* ram, psfw_board* b, const psfw_board_api* api, const uint8_t* config, uint32_t len) {
  CoreFirmwareRam& r = ramOf(ram);
  if (config == nullptr || len != sizeof(CoreImage)) return 1;
  uint32_t head[2];
  std::memcpy(head, config, sizeof head);
  if (head[0] != kCoreImageTag || head[1] != sizeof(CoreImage)) return 2;
  std::memcpy(&r.cfg, config + offsetof(CoreImage, cfg), sizeof r.cfg);
  const Config& c = r.cfg;
  if (!monitorPartKnown(c)) return 5;  // an image for a monitor part this build does not drive
  if (api->abi_version < 2u) return 3;  // needs set_task_period
  if (api->set_task_period(b, kTaskReadout, c.readout.period_ms, 0) != 0 ||
      api->set_task_period(b, kTaskAlerts, c.readout.alertPeriod_ms, 0) != 0 ||
      api->set_task_period(b, kTaskControl, c.tickPeriod_ms, 0) != 0)
    return 4;
  init(r.core);
  if (!monitorInit(c, r.monitors, r.core.acq, b, api))
    api->event(b, "monitor stack: not every device took its address and configuration at init");
  controlTask(ram, b, api);  // the outputs of power-up: every pin decided (open) from the first reading
  return 0;
}

// Periods until init sets the configured ones (set_task_period).
const psfw_firmware kDescriptor = {
    PSFW_ABI_VERSION,
    "packsim core",
    sizeof(CoreFirmwareRam),
    coreInit,
    3,
    {{10, 0, readoutTask}, {10, 0, alertTask}, {10, 0, controlTask}},
};

}  // namespace

const psfw_firmware* coreFirmware() { return &kDescriptor; }

const Outputs& coreFirmwareOutputs(const void* ram) { return static_cast<const CoreFirmwareRam*>(ram)->out; }

}  // namespace bms
