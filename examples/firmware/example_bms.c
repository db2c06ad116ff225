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
 *   SOC          coulomb counting on the 10 ms current reading; at power-up from the
 *                NVM record (contract v3) when it holds a valid one, else from the
 *                open-circuit voltage of the first read-out (before the relay closes)
 *   NVM          one 8-byte record (one EEPROM page, 5 ms to write): a boot counter and
 *                the SOC, written at every boot, every soc_save_period_ms while the SOC
 *                moves, and after a trip; checked by magic, version and CRC-8, so an
 *                erased page (0xFF) or a torn write is refused
 *
 * Configuration blob (bms.firmware.config in the scenario): int32 fields in the order
 * of struct ex_config, little-endian, as the exported schema (ex_config_fields) declares
 * them: packsim checks the scenario's keys and ranges against it and builds the blob.
 */
#include <math.h>
#include <stddef.h>
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
  int32_t capacity_mAh;       /* for the coulomb count */
  int32_t soc_save_period_ms; /* the NVM record at most this often while the SOC moves (and after a trip); 0: never */
  int32_t ocv_mV[11];         /* open-circuit cell voltage at SOC 0, 10, ..., 100 %: the SOC without an NVM record */
} ex_config;

/* The NVM record: one 8-byte page at offset 0. */
#define EX_NVM_MAGIC 0xB5u
#define EX_NVM_VERSION 1u
#define EX_NVM_NO_SOC 0xFFFFu /* a record written before the SOC was known */
#define EX_SOC_FULL 65000.0   /* the record's SOC: 0..65000 = 0..1 */

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
  double soc0;             /* the SOC (0..1) where the count started, valid once soc_known */
  int64_t used_mAms;       /* charge out since then (mA x ms; integer: cheap in the 10 ms task) */
  uint8_t soc_known;       /* from NVM at init, or from OCV at the first read-out */
  uint8_t save_pending;    /* a trip: save at the next read-out (the 10 ms task has no time for 5 ms) */
  uint16_t boots;          /* this boot's number, from the NVM record (0: no valid record) */
  uint16_t saved_soc;      /* the SOC in the last record written */
  uint32_t soc_last_ms, saved_ms;
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
  r->save_pending = 1;
  snprintf(text, sizeof text, "trip: %s", reason);
  api->event(b, text);
}

/* ---- SOC and its NVM record ------------------------------------------------ */

static uint16_t ex_soc16(double soc) {
  return (uint16_t)(soc <= 0.0 ? 0.0 : soc >= 1.0 ? EX_SOC_FULL : soc * EX_SOC_FULL + 0.5);
}

/* "71.23" (no floating-point printf in a small C library) */
static void ex_percent(char* text, size_t n, double soc) {
  const uint32_t c = (uint32_t)(soc * 10000.0 + 0.5);
  snprintf(text, n, "%lu.%02lu", (unsigned long)(c / 100u), (unsigned long)(c % 100u));
}

/* The SOC now: where the count started less the charge out since, within 0..1. */
static double ex_soc(const ex_ram* r) {
  const double soc = r->soc0 - (double)r->used_mAms / (3600000.0 * r->cfg.capacity_mAh);
  return soc < 0.0 ? 0.0 : soc > 1.0 ? 1.0 : soc;
}

/* Writes the record (boot counter, SOC or EX_NVM_NO_SOC): one page, 5 ms of the clock. */
static void ex_nvm_save(ex_ram* r, psfw_board* b, const psfw_board_api* api) {
  uint8_t rec[8];
  const uint16_t soc = r->soc_known ? ex_soc16(ex_soc(r)) : (uint16_t)EX_NVM_NO_SOC;
  rec[0] = EX_NVM_MAGIC;
  rec[1] = EX_NVM_VERSION;
  rec[2] = (uint8_t)r->boots;
  rec[3] = (uint8_t)(r->boots >> 8);
  rec[4] = (uint8_t)soc;
  rec[5] = (uint8_t)(soc >> 8);
  rec[6] = 0;
  rec[7] = ex_crc8(rec, 7);
  api->nvm_write(b, 0, rec, sizeof rec);
  r->saved_soc = soc;
  r->saved_ms = api->now_ms(b);
  r->save_pending = 0;
}

/* At init: the record's boot counter and SOC when it is valid. */
static void ex_nvm_resume(ex_ram* r, psfw_board* b, const psfw_board_api* api) {
  uint8_t rec[8];
  char text[96], pct[16];
  const int valid = api->nvm_read(b, 0, rec, sizeof rec) == (int32_t)sizeof rec && rec[0] == EX_NVM_MAGIC &&
                    rec[1] == EX_NVM_VERSION && ex_crc8(rec, 7) == rec[7];
  if (!valid) {
    r->boots = 0;
    api->event(b, "boot 0: no valid NVM record; SOC from the first reading's OCV");
  } else {
    const uint16_t soc = (uint16_t)(rec[4] | (rec[5] << 8));
    r->boots = (uint16_t)((rec[2] | (rec[3] << 8)) + 1u);
    if (soc == EX_NVM_NO_SOC) {
      snprintf(text, sizeof text, "boot %u: the NVM record holds no SOC; SOC from the first reading's OCV", r->boots);
    } else {
      r->soc0 = soc / EX_SOC_FULL;
      r->used_mAms = 0;
      r->soc_known = 1;
      ex_percent(pct, sizeof pct, ex_soc(r));
      snprintf(text, sizeof text, "boot %u: SOC %s %% resumed from NVM", r->boots, pct);
    }
    api->event(b, text);
  }
  ex_nvm_save(r, b, api); /* counts this boot */
}

/* The SOC at the OCV table's mean cell voltage (linear between its 10 % points). */
static double ex_soc_from_ocv(const ex_ram* r, uint32_t mean_mV) {
  const int32_t* v = r->cfg.ocv_mV;
  if ((int32_t)mean_mV <= v[0]) return 0.0;
  for (int i = 1; i < 11; ++i)
    if ((int32_t)mean_mV < v[i]) return 0.1 * (i - 1) + 0.1 * (double)((int32_t)mean_mV - v[i - 1]) / (v[i] - v[i - 1]);
  return 1.0;
}

/* Coulomb count over the 10 ms task's current (mA, + discharging): integer only. */
static void ex_soc_count(ex_ram* r, uint32_t now_ms) {
  const uint32_t dt_ms = now_ms - r->soc_last_ms;
  r->soc_last_ms = now_ms;
  if (!r->soc_known) return;
  r->used_mAms += (int64_t)r->current_mA * dt_ms;
}

/* After a read-out: the SOC from OCV if it is not known yet; the record when due. */
static void ex_soc_readout(ex_ram* r, psfw_board* b, const psfw_board_api* api, uint32_t now_ms) {
  if (!r->soc_known) {
    uint32_t sum = 0;
    char text[96], pct[16];
    for (int c = 0; c < r->cfg.cell_count; ++c) sum += r->cell_mV[c];
    const uint32_t mean = (sum + (uint32_t)r->cfg.cell_count / 2u) / (uint32_t)r->cfg.cell_count;
    r->soc0 = ex_soc_from_ocv(r, mean);
    r->used_mAms = 0;
    r->soc_known = 1;
    ex_percent(pct, sizeof pct, ex_soc(r));
    snprintf(text, sizeof text, "SOC %s %% from OCV (mean cell %lu mV)", pct, (unsigned long)mean);
    api->event(b, text);
    r->save_pending = 1;
  }
  if (r->cfg.soc_save_period_ms <= 0) return;
  if (r->save_pending || ((int32_t)(now_ms - r->saved_ms) >= r->cfg.soc_save_period_ms && ex_soc16(ex_soc(r)) != r->saved_soc))
    ex_nvm_save(r, b, api);
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
  ex_soc_count(r, now); /* last: its cycles delay no output (target mode) */
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
  ex_soc_readout(r, b, api, now); /* last: a 5 ms NVM write delays nothing above */
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
      r->cfg.ntc_bits < 8 || r->cfg.ntc_bits > 16 || r->cfg.capacity_mAh < 1)
    return 2;
  for (int i = 1; i < 11; ++i)
    if (r->cfg.ocv_mV[i] <= r->cfg.ocv_mV[i - 1]) return 4; /* the OCV table must rise */
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
  r->soc_last_ms = api->now_ms(b);
  ex_nvm_resume(r, b, api);
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
    EX_FIELD("capacity_mAh", 1, 10000000, 3100, "mAh", "cell capacity, for the coulomb count"),
    EX_FIELD("soc_save_period_ms", 0, 86400000, 30000, "ms",
             "the SOC to NVM at most this often while it moves, and after a trip; 0: never"),
    PSFW_CONFIG_FIELD("ocv_mV", PSFW_CONFIG_INT32, 11u, 0, 5000, 0, "mV",
                      "open-circuit cell voltage at SOC 0, 10, ..., 100 % (11 values, rising: required, "
                      "init refuses a table that does not rise)"),
};
/* every field of struct ex_config has its row, the one-number fields before the OCV
 * table (C99: a negative array size fails the build) */
typedef char ex_schema_covers_config[(sizeof ex_config_fields / sizeof ex_config_fields[0] - 1) * 4 ==
                                             offsetof(ex_config, ocv_mV) &&
                                         sizeof(ex_config) == offsetof(ex_config, ocv_mV) + 11 * sizeof(int32_t)
                                     ? 1
                                     : -1];

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
