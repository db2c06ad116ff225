/* A small, independent BMS firmware for packsim's firmware contract (bms/packsim_fw.h):
 * a template to copy. Plain C99, no heap, no globals that change: every variable
 * lives in the instance RAM the board hands over (struct ex_ram).
 *
 *   driver       its own BQ76PL536A-class stack driver over SPI frames: reset,
 *                auto-addressing, ADC set-up, convert + read-out with CRC-8 checks
 *                (register layout from bq76pl536a_regs.h, part of the contract)
 *   protections  cell over-/under-voltage, discharge/charge over-current,
 *                over-temperature (thermistors on the monitor ICs), comm loss after
 *                N consecutive bad replies of one device, E-switch, monitor FAULT line;
 *                each debounced in milliseconds, latched until an operator reset
 *   contactors   precharge for a fixed time, then the main relay, then precharge off
 *   tasks        10 ms: current, E-switch, FAULT line, contactor state machine
 *                100 ms: stack read-out, voltage and temperature protections, telemetry
 *   trips        reported as the event "trip: <reason>" with packsim's fault names,
 *                so a scenario's expect: blocks judge them
 *
 * Configuration blob (bms.firmware.config in the scenario): int32 fields in the order
 * of struct ex_config, little-endian, as the exported schema (ex_config_fields) declares
 * them: packsim checks the scenario's keys and ranges against it and builds the blob.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "afe/bq76pl536a_regs.h"
#include "packsim_fw.h"

#define EX_MAX_DEVICES 32
#define EX_MAX_CELLS (EX_MAX_DEVICES * BQ536_CELLS_MAX)
#define EX_BUS PSFW_BUS_MONITOR(0)

/* The configuration blob, field by field (int32, little-endian, this order). */
typedef struct ex_config {
  int32_t cell_count;         /* series cells */
  int32_t cells_per_device;   /* 3..6 */
  int32_t therm_per_device;   /* thermistors biased and read per device: 0..2 */
  int32_t cov_mV, cuv_mV, voltage_delay_ms;
  int32_t ocd_mA, occ_mA, current_delay_ms;
  int32_t ot_dC, temp_delay_ms;              /* over-temperature, 0.1 degC */
  int32_t comm_loss_count;                   /* consecutive bad replies of one device */
  int32_t current_zero_code, current_lsb_nA; /* current-sense ADC: mA = (code - zero) * lsb / 1e6 */
  int32_t ntc_r25_ohm, ntc_beta_K, ntc_pullup_ohm, ntc_bits;
  int32_t precharge_ms;
} ex_config;

enum ex_state { EX_STANDBY = 0, EX_PRECHARGE = 1, EX_NORMAL = 2, EX_FAULT = 3 };

/* Debounce: a condition must hold for delay_ms before it trips. */
typedef struct ex_timer {
  uint32_t since_ms;
  uint8_t running;
} ex_timer;

typedef struct ex_ram {
  ex_config cfg;
  int devices;
  uint16_t ot_code; /* thermistor code at the over-temperature threshold (NTC: hotter = lower) */
  uint16_t cell_mV[EX_MAX_CELLS];
  uint16_t therm_code[EX_MAX_DEVICES][BQ536_TEMPS_MAX];
  uint8_t bad_replies[EX_MAX_DEVICES];
  uint8_t have_readings;
  int32_t current_mA;
  ex_timer ov, uv, ocd, occ, ot;
  uint8_t state;
  uint32_t state_since_ms;
  uint32_t readouts;
} ex_ram;

/* ---- BQ76PL536A-class driver ---------------------------------------------- */

static uint8_t ex_crc8(const uint8_t* p, uint32_t n) {
  uint8_t crc = BQ536_CRC8_INIT;
  for (uint32_t i = 0; i < n; ++i) {
    crc ^= p[i];
    for (int b = 0; b < 8; ++b) crc = (uint8_t)((crc & 0x80u) ? ((unsigned)crc << 1) ^ BQ536_CRC8_POLY : (unsigned)crc << 1);
  }
  return crc;
}

static void ex_write(psfw_board* b, const psfw_board_api* api, uint8_t addr, uint8_t reg, uint8_t value) {
  uint8_t f[BQ536_WRITE_FRAME_LEN];
  f[0] = BQ536_FRAME_WRITE(addr);
  f[1] = reg;
  f[2] = value;
  f[3] = ex_crc8(f, 3);
  api->bus_transfer(b, EX_BUS, f, BQ536_WRITE_FRAME_LEN, NULL, 0);
}

/* Reads count registers; 1 = good reply (length and CRC), 0 = bad or none. */
static int ex_read(psfw_board* b, const psfw_board_api* api, uint8_t addr, uint8_t reg, uint8_t count, uint8_t* data) {
  uint8_t f[BQ536_READ_REQUEST_LEN + 32 + 1];
  if (count > 32) return 0;
  f[0] = BQ536_FRAME_READ(addr);
  f[1] = reg;
  f[2] = count;
  if (api->bus_transfer(b, EX_BUS, f, BQ536_READ_REQUEST_LEN, f + BQ536_READ_REQUEST_LEN, (uint16_t)(count + 1u)) !=
      count + 1)
    return 0;
  if (ex_crc8(f, BQ536_READ_REQUEST_LEN + count) != f[BQ536_READ_REQUEST_LEN + count]) return 0;
  memcpy(data, f + BQ536_READ_REQUEST_LEN, count);
  return 1;
}

static int ex_cells_of(const ex_ram* r, int d) {
  const int left = r->cfg.cell_count - d * r->cfg.cells_per_device;
  return left <= 0 ? 0 : left < r->cfg.cells_per_device ? left : r->cfg.cells_per_device;
}

/* Reset, address bottom-up, clear the reset latches, set up the ADC. Returns the
 * devices that took their address. */
static int ex_stack_init(ex_ram* r, psfw_board* b, const psfw_board_api* api) {
  int addressed = 0;
  ex_write(b, api, BQ536_ADDR_BROADCAST, BQ536_RESET, BQ536_RESET_KEY);
  for (int d = 0; d < r->devices; ++d) {
    uint8_t got = 0;
    ex_write(b, api, BQ536_ADDR_DISCOVERY, BQ536_ADDRESS_CONTROL, (uint8_t)(d + 1));
    if (!ex_read(b, api, (uint8_t)(d + 1), BQ536_ADDRESS_CONTROL, 1, &got)) break;
    if (got != (uint8_t)((d + 1) | BQ536_ADDR_ASSIGNED)) break;
    ++addressed;
  }
  ex_write(b, api, BQ536_ADDR_BROADCAST, BQ536_FAULT_STATUS, BQ536_FS_POR | BQ536_FS_CRC);
  ex_write(b, api, BQ536_ADDR_BROADCAST, BQ536_FAULT_STATUS, 0);
  ex_write(b, api, BQ536_ADDR_BROADCAST, BQ536_ALERT_STATUS, BQ536_AS_AR);
  ex_write(b, api, BQ536_ADDR_BROADCAST, BQ536_ALERT_STATUS, 0);
  const int nt = r->cfg.therm_per_device;
  ex_write(b, api, BQ536_ADDR_BROADCAST, BQ536_IO_CONTROL,
           (uint8_t)((nt >= 1 ? BQ536_IO_TS1 : 0u) | (nt >= 2 ? BQ536_IO_TS2 : 0u)));
  for (int d = 0; d < addressed; ++d) {
    const int cells = ex_cells_of(r, d);
    ex_write(b, api, (uint8_t)(d + 1), BQ536_ADC_CONTROL,
             (uint8_t)(BQ536_AC_ADC_ON | (nt >= 1 ? BQ536_AC_TS1 : 0u) | (nt >= 2 ? BQ536_AC_TS2 : 0u) |
                       ((uint8_t)(cells - 1) & BQ536_AC_CELL_SEL_MASK)));
  }
  return addressed;
}

/* One read-out: convert every device, wait, read each one's results. */
static void ex_stack_read(ex_ram* r, psfw_board* b, const psfw_board_api* api) {
  const int channels = r->cfg.cells_per_device + r->cfg.therm_per_device;
  ex_write(b, api, BQ536_ADDR_BROADCAST, BQ536_ADC_CONVERT, BQ536_CONV_START);
  api->delay_us(b, (uint32_t)(channels + 1) * BQ536_CONV_US_PER_CHANNEL * 2u);
  for (int d = 0; d < r->devices; ++d) {
    uint8_t v[BQ536_RESULTS_LEN];
    const int ok = ex_read(b, api, (uint8_t)(d + 1), BQ536_RESULTS_FIRST, BQ536_RESULTS_LEN, v) &&
                   (v[0] & BQ536_DS_DRDY) && (v[0] & BQ536_DS_ADDR_RQST);
    if (!ok) {
      if (r->bad_replies[d] < 255) ++r->bad_replies[d];
      continue;
    }
    r->bad_replies[d] = 0;
    for (int i = 0; i < ex_cells_of(r, d); ++i) {
      const uint32_t code = ((uint32_t)v[BQ536_VCELL(i)] << 8) | v[BQ536_VCELL(i) + 1];
      r->cell_mV[d * r->cfg.cells_per_device + i] =
          (uint16_t)((code * BQ536_CELL_FULL_SCALE_MV + BQ536_CELL_FULL_SCALE_CODE / 2u) / BQ536_CELL_FULL_SCALE_CODE);
    }
    r->therm_code[d][0] = (uint16_t)((v[BQ536_TEMPERATURE1] << 8) | v[BQ536_TEMPERATURE1 + 1]);
    r->therm_code[d][1] = (uint16_t)((v[BQ536_TEMPERATURE2] << 8) | v[BQ536_TEMPERATURE2 + 1]);
  }
  r->have_readings = 1;
  ++r->readouts;
}

/* ---- protections and contactors ------------------------------------------- */

static int ex_debounce(ex_timer* t, int condition, uint32_t now_ms, int32_t delay_ms) {
  if (!condition) {
    t->running = 0;
    return 0;
  }
  if (!t->running) {
    t->running = 1;
    t->since_ms = now_ms;
  }
  return (int32_t)(now_ms - t->since_ms) >= delay_ms;
}

/* Contactors, and the FETs (where the board has them) conducting while the pack is connected. */
static void ex_outputs(psfw_board* b, const psfw_board_api* api, int relay, int precharge) {
  api->gpio_write(b, PSFW_OUT_RELAY, relay);
  api->gpio_write(b, PSFW_OUT_PRECHARGE, precharge);
  api->gpio_write(b, PSFW_OUT_DISCHARGE_FET, relay || precharge);
  api->gpio_write(b, PSFW_OUT_CHARGE_FET, relay || precharge);
}

static void ex_trip(ex_ram* r, psfw_board* b, const psfw_board_api* api, const char* reason) {
  char text[64];
  if (r->state == EX_FAULT) return;
  ex_outputs(b, api, 0, 0);
  r->state = EX_FAULT;
  r->state_since_ms = api->now_ms(b);
  snprintf(text, sizeof text, "trip: %s", reason);
  api->event(b, text);
}

/* 10 ms: current, E-switch, FAULT line, contactor sequencing. */
static void ex_task_fast(void* ram, psfw_board* b, const psfw_board_api* api) {
  ex_ram* r = (ex_ram*)ram;
  const uint32_t now = api->now_ms(b);
  const int64_t code = api->adc_read(b, PSFW_ADC_CURRENT);
  r->current_mA = (int32_t)(((code - r->cfg.current_zero_code) * (int64_t)r->cfg.current_lsb_nA) / 1000000);

  if (api->gpio_read(b, PSFW_IN_ESWITCH_INTERNAL) == 1 || api->gpio_read(b, PSFW_IN_ESWITCH_EXTERNAL) == 1)
    ex_trip(r, b, api, "estop");
  if (api->gpio_read(b, PSFW_IN_MONITOR_FAULT) == 1) ex_trip(r, b, api, "monitor_fault");
  if (ex_debounce(&r->ocd, r->current_mA > r->cfg.ocd_mA, now, r->cfg.current_delay_ms))
    ex_trip(r, b, api, "overcurrent_discharge");
  if (ex_debounce(&r->occ, r->current_mA < -r->cfg.occ_mA, now, r->cfg.current_delay_ms))
    ex_trip(r, b, api, "overcurrent_charge");

  switch (r->state) {
    case EX_STANDBY:
      if (r->have_readings && api->gpio_read(b, PSFW_IN_RUN_REQUEST) == 1) {
        ex_outputs(b, api, 0, 1);
        r->state = EX_PRECHARGE;
        r->state_since_ms = now;
        api->event(b, "precharge");
      }
      break;
    case EX_PRECHARGE:
      if ((int32_t)(now - r->state_since_ms) >= r->cfg.precharge_ms) {
        ex_outputs(b, api, 1, 1);
        r->state = EX_NORMAL;
        r->state_since_ms = now;
        api->event(b, "relay closed");
      }
      break;
    case EX_NORMAL:
      if ((int32_t)(now - r->state_since_ms) >= 20) ex_outputs(b, api, 1, 0);
      if (api->gpio_read(b, PSFW_IN_RUN_REQUEST) == 0) {
        ex_outputs(b, api, 0, 0);
        r->state = EX_STANDBY;
      }
      break;
    default:  /* EX_FAULT: latched until the operator reset, with every condition gone */
      ex_outputs(b, api, 0, 0);
      if (api->gpio_read(b, PSFW_IN_RESET_REQUEST) == 1 && api->gpio_read(b, PSFW_IN_MONITOR_FAULT) == 0) {
        r->state = EX_STANDBY;
        api->event(b, "fault reset");
      }
      break;
  }
}

/* 100 ms: read-out, voltage and temperature protections, comm loss, telemetry. */
static void ex_task_measure(void* ram, psfw_board* b, const psfw_board_api* api) {
  ex_ram* r = (ex_ram*)ram;
  uint16_t lo = 0xFFFF, hi = 0;
  int hot = 0;
  ex_stack_read(r, b, api);
  const uint32_t now = api->now_ms(b);
  for (int d = 0; d < r->devices; ++d)
    if (r->bad_replies[d] >= r->cfg.comm_loss_count) ex_trip(r, b, api, "comm_loss");
  for (int c = 0; c < r->cfg.cell_count; ++c) {
    if (r->cell_mV[c] < lo) lo = r->cell_mV[c];
    if (r->cell_mV[c] > hi) hi = r->cell_mV[c];
  }
  for (int d = 0; d < r->devices; ++d)
    for (int k = 0; k < r->cfg.therm_per_device; ++k) hot = hot || r->therm_code[d][k] < r->ot_code;
  if (ex_debounce(&r->ov, hi > r->cfg.cov_mV, now, r->cfg.voltage_delay_ms)) ex_trip(r, b, api, "cell_overvoltage");
  if (ex_debounce(&r->uv, lo < r->cfg.cuv_mV, now, r->cfg.voltage_delay_ms)) ex_trip(r, b, api, "cell_undervoltage");
  if (ex_debounce(&r->ot, hot, now, r->cfg.temp_delay_ms)) ex_trip(r, b, api, "overtemperature");

  /* telemetry frame: state, min and max cell mV, current mA (little-endian) */
  uint8_t frame[9];
  frame[0] = r->state;
  frame[1] = (uint8_t)lo;
  frame[2] = (uint8_t)(lo >> 8);
  frame[3] = (uint8_t)hi;
  frame[4] = (uint8_t)(hi >> 8);
  for (int i = 0; i < 4; ++i) frame[5 + i] = (uint8_t)((uint32_t)r->current_mA >> (8 * i));
  api->telemetry_send(b, frame, sizeof frame);
}

static int32_t ex_init(void* ram, psfw_board* b, const psfw_board_api* api, const uint8_t* config, uint32_t len) {
  ex_ram* r = (ex_ram*)ram;
  if (len != sizeof(ex_config)) {
    api->event(b, "configuration blob has the wrong size");
    return 1;
  }
  memcpy(&r->cfg, config, sizeof r->cfg); /* little-endian int32 fields, as the host packs them */
  if (r->cfg.cells_per_device < 1 || r->cfg.cells_per_device > (int32_t)BQ536_CELLS_MAX || r->cfg.cell_count < 1 ||
      r->cfg.cell_count > (int32_t)EX_MAX_CELLS || r->cfg.therm_per_device < 0 || r->cfg.therm_per_device > 2 ||
      r->cfg.ntc_bits < 8 || r->cfg.ntc_bits > 16)
    return 2;
  r->devices = (r->cfg.cell_count + r->cfg.cells_per_device - 1) / r->cfg.cells_per_device;
  if (r->devices > EX_MAX_DEVICES) return 3;
  /* The over-temperature threshold as a ratiometric code: R(T) = R25 exp(B (1/T - 1/T25)). */
  const double t_K = r->cfg.ot_dC / 10.0 + 273.15;
  const double r_ohm = r->cfg.ntc_r25_ohm * exp(r->cfg.ntc_beta_K * (1.0 / t_K - 1.0 / 298.15));
  r->ot_code = (uint16_t)(((1u << r->cfg.ntc_bits) - 1u) * r_ohm / (r->cfg.ntc_pullup_ohm + r_ohm));
  const int addressed = ex_stack_init(r, b, api);
  if (addressed < r->devices) {
    char text[64];
    snprintf(text, sizeof text, "only %d of %d monitor devices answered", addressed, r->devices);
    api->event(b, text);
  }
  r->state = EX_STANDBY;
  return 0;
}

/* The configuration schema: one row per field of struct ex_config, in its order. The
 * loader checks bms.firmware.config against it (names, ranges) and fills an omitted
 * key with its default; the ranges are those ex_init accepts and its types can hold. */
#define EX_FIELD(name, min, max, def, unit, doc) PSFW_CONFIG_FIELD(name, PSFW_CONFIG_INT32, 1u, min, max, def, unit, doc)
static const psfw_config_field ex_config_fields[] = {
    EX_FIELD("cell_count", 1, EX_MAX_CELLS, 6, "", "series cells"),
    EX_FIELD("cells_per_device", 1, BQ536_CELLS_MAX, 6, "", "cells on each monitor device"),
    EX_FIELD("therm_per_device", 0, 2, 2, "", "thermistors biased and read per device"),
    EX_FIELD("cov_mV", 1000, 5000, 4250, "mV", "cell over-voltage trip"),
    EX_FIELD("cuv_mV", 500, 4500, 2500, "mV", "cell under-voltage trip"),
    EX_FIELD("voltage_delay_ms", 0, 60000, 500, "ms", "cell voltage debounce"),
    EX_FIELD("ocd_mA", 0, 2000000, 10000, "mA", "discharge over-current trip"),
    EX_FIELD("occ_mA", 0, 2000000, 2000, "mA", "charge over-current trip"),
    EX_FIELD("current_delay_ms", 0, 60000, 200, "ms", "over-current debounce"),
    EX_FIELD("ot_dC", -400, 1500, 600, "0.1 degC", "over-temperature trip"),
    EX_FIELD("temp_delay_ms", 0, 60000, 1000, "ms", "over-temperature debounce"),
    EX_FIELD("comm_loss_count", 1, 255, 5, "", "consecutive bad replies of one device that trip"),
    EX_FIELD("current_zero_code", 0, 65535, 32768, "", "current-sense ADC code at 0 A"),
    EX_FIELD("current_lsb_nA", 1, 2147483647, 503540, "nA", "current per ADC code"),
    EX_FIELD("ntc_r25_ohm", 100, 1000000, 10000, "ohm", "thermistor resistance at 25 degC"),
    EX_FIELD("ntc_beta_K", 1000, 10000, 3435, "K", "thermistor beta"),
    EX_FIELD("ntc_pullup_ohm", 100, 1000000, 10000, "ohm", "thermistor pull-up"),
    EX_FIELD("ntc_bits", 8, 16, 12, "", "thermistor ADC resolution"),
    EX_FIELD("precharge_ms", 0, 60000, 300, "ms", "precharge time before the main relay closes"),
};
/* every field of struct ex_config has its row (C99: a negative array size fails the build) */
typedef char ex_schema_covers_config[sizeof ex_config_fields / sizeof ex_config_fields[0] * 4 == sizeof(ex_config) ? 1 : -1];

#if defined(__GNUC__)
__attribute__((visibility("default")))
#endif
const psfw_config_schema psfw_firmware_config_schema = {
    PSFW_CONFIG_SCHEMA_VERSION,
    sizeof ex_config_fields / sizeof ex_config_fields[0],
    ex_config_fields,
};

static const psfw_firmware ex_firmware = {
    PSFW_ABI_VERSION,
    "example_bms 1.0",
    sizeof(ex_ram),
    ex_init,
    2,
    {{10, 2000, ex_task_fast}, {100, 20000, ex_task_measure}},
};

#if defined(__GNUC__)
__attribute__((visibility("default")))
#endif
const psfw_firmware* psfw_firmware_entry(void) {
  return &ex_firmware;
}
