/* packsim firmware contract, version 3: the board as a BMS firmware sees it.
 *
 * A firmware is code that runs on the BMS microcontroller. On the bench it is
 * linked with a board-support layer that implements the services below on real
 * peripherals; in packsim the simulator implements them on a simulated pack. The
 * firmware cannot tell the difference: it only ever calls the services it is given
 * and never sees simulator memory (`psfw_board` is an opaque handle it passes back).
 *
 *   entry:     a firmware library exports `psfw_firmware_entry`, which returns its
 *              description: name, RAM it needs, init, and its periodic tasks
 *   clock:     now_ms / now_us advance with simulated time; bus transactions and
 *              delay_us take the time they take on real hardware
 *   buses:     byte transactions with the monitor ICs, in their own frame formats
 *              and CRCs (SPI for the BQ76PL536A class, UART for the BQ76PL455A
 *              class, I2C for the BQ76952 class)
 *   CAN:       classic frames to the other boards' MCUs of the pack (version 2)
 *   results:   distinct codes for "no such channel" and "nothing answered" (version 3)
 *   NVM:       a 256-byte page that keeps its bytes across MCU resets (version 3)
 *   ADC:       current sense, load-bus voltage, thermistors on the MCU's own ADC
 *   GPIO:      E-switches, relay auxiliary contact, monitor FAULT line, charger
 *              present, run and reset requests in; relay, precharge, FETs, charger
 *              enable out
 *   DAC:       the charger current request
 *   telemetry: bytes out to the data-acquisition unit
 *   events:    a short text the firmware wants in the run's event log
 *   config:    the blob init receives, optionally described by an exported schema
 *
 * No allocation: the host hands the firmware `instance_bytes` of zeroed RAM
 * (8-byte aligned) at init, as a linker would place its static RAM. Plain C99 so a
 * firmware written in C or C++ builds against it with any compiler, including
 * arm-none-eabi-gcc.
 */
#ifndef PACKSIM_FW_H
#define PACKSIM_FW_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PSFW_ABI_VERSION 3u
/* The oldest contract version this header's hosts still run: a version-1 firmware
 * never calls what version 2 added (set_task_period), a version-2 firmware is given
 * the codes it was built with (PSFW_NO_CHANNEL_V2 below). */
#define PSFW_ABI_VERSION_MIN 1u
#define PSFW_MAX_TASKS 8u

typedef struct psfw_board psfw_board; /* opaque: the firmware passes it back, never dereferences it */

/* Buses. A pack with several monitor chains numbers them from 0. */
#define PSFW_BUS_MONITOR(n) ((uint8_t)(n))

/* bus_transfer results (>= 0: bytes received) */
#define PSFW_BUS_TIMEOUT (-1) /* nothing answered within the timeout */
#define PSFW_BUS_ERROR (-2)   /* arguments the bus cannot carry (a frame the part does not accept) */
/* Longest frame one transaction may carry either way; more, a bus id the board does
 * not have, or a null buffer with a non-zero length is a contract break: the host
 * stops the firmware (firmware_fault). */
#define PSFW_BUS_MAX_FRAME 1024u

/* A channel, pin, task or bus the board does not have (adc_read, gpio_read,
 * set_task_period, can_send, can_receive). Version 3: its own code, so a firmware tells
 * "this board has no CAN" from "nothing arrived" (PSFW_BUS_TIMEOUT). A firmware whose
 * descriptor declares version 1 or 2 is given PSFW_NO_CHANNEL_V2 instead, the value
 * those versions shared with PSFW_BUS_TIMEOUT, so it runs unchanged. */
#define PSFW_NO_CHANNEL (-3)
#define PSFW_NO_CHANNEL_V2 (-1)

/* NVM (version 3): one page of PSFW_NVM_BYTES, erased (0xFF) when the run starts, kept
 * across every MCU reset (watchdog, brown-out); an external I2C EEPROM of the 24LC02
 * class: a write programs PSFW_NVM_WRITE_PAGE_BYTES-byte pages, each taking
 * PSFW_NVM_WRITE_US of the write cycle (the datasheet's maximum), during which the
 * call does not return. */
#define PSFW_NVM_BYTES 256u
#define PSFW_NVM_WRITE_PAGE_BYTES 8u
#define PSFW_NVM_WRITE_US 5000u

/* ADC channels */
enum psfw_adc_channel {
  PSFW_ADC_CURRENT = 0,     /* current-sense amplifier, signed code */
  PSFW_ADC_BUS_VOLTAGE = 1, /* load-bus divider (precharge), unsigned code */
  PSFW_ADC_THERMISTOR0 = 16 /* + n: thermistor n on the MCU's own ADC, ratiometric code */
};

/* GPIO inputs (1 = asserted) */
enum psfw_gpio_in {
  PSFW_IN_ESWITCH_INTERNAL = 0, /* latching E-switch inside the vehicle: 1 = pulled */
  PSFW_IN_ESWITCH_EXTERNAL = 1,
  PSFW_IN_RELAY_AUX = 2,        /* main relay auxiliary contact: 1 = closed */
  PSFW_IN_MONITOR_FAULT = 3,    /* FAULT / ALERT line of the monitor ICs */
  PSFW_IN_CHARGER_PRESENT = 4,
  PSFW_IN_RUN_REQUEST = 5,      /* key / drive enable */
  PSFW_IN_RESET_REQUEST = 6     /* operator reset of latched faults */
};

/* GPIO outputs (1 = on) */
enum psfw_gpio_out {
  PSFW_OUT_RELAY = 0,           /* main relay coil (normally open) */
  PSFW_OUT_PRECHARGE = 1,
  PSFW_OUT_DISCHARGE_FET = 2,
  PSFW_OUT_CHARGE_FET = 3,
  PSFW_OUT_CHARGER_ENABLE = 4
};

/* DAC / analog outputs */
enum psfw_dac_channel {
  PSFW_DAC_CHARGER_CURRENT_MA = 0 /* charger current limit request, mA */
};

typedef struct psfw_board_api {
  uint32_t abi_version; /* PSFW_ABI_VERSION of the host */
  uint32_t (*now_ms)(psfw_board* b);
  uint32_t (*now_us)(psfw_board* b);
  void (*delay_us)(psfw_board* b, uint32_t us);
  /* One transaction on a bus: tx_len bytes out, then up to rx_len bytes in (SPI:
   * clocked after the command; UART: the reply frame; I2C: a write, then a read
   * after a repeated start when rx_len > 0). Returns the bytes received or
   * PSFW_BUS_TIMEOUT / PSFW_BUS_ERROR; the clock advances by the transaction time. */
  int32_t (*bus_transfer)(psfw_board* b, uint8_t bus, const uint8_t* tx, uint16_t tx_len, uint8_t* rx,
                          uint16_t rx_len);
  int32_t (*adc_read)(psfw_board* b, uint8_t channel);
  int32_t (*gpio_read)(psfw_board* b, uint8_t pin);
  void (*gpio_write)(psfw_board* b, uint8_t pin, int32_t level);
  void (*dac_write)(psfw_board* b, uint8_t channel, int32_t value);
  void (*telemetry_send)(psfw_board* b, const uint8_t* bytes, uint16_t len);
  void (*event)(psfw_board* b, const char* text); /* NUL-terminated, at most 120 characters kept */
  /* Version 2. During init only: the period (0: the task never runs) and budget (0: the
   * period) of task `task`, replacing the descriptor's, e.g. read-out rates from the
   * firmware's configuration. Returns 0, or PSFW_NO_CHANNEL for a task the descriptor
   * does not have or a call outside init. */
  int32_t (*set_task_period)(psfw_board* b, uint32_t task, uint32_t period_ms, uint32_t budget_us);
  /* Version 2. CAN: one classic data frame (11-bit id, 0..8 bytes) queued on CAN bus
   * `can`: returns 0, PSFW_BUS_TIMEOUT when the transmit queue is full, PSFW_NO_CHANNEL
   * when the board has no such bus (a board alone has one with hardware.can only). The frame reaches every
   * other node after arbitration (lowest id first) and its transmission time at the
   * bus's bit rate. */
  int32_t (*can_send)(psfw_board* b, uint8_t can, uint32_t id, const uint8_t* data, uint8_t len);
  /* The oldest frame that has arrived by now: returns its length (0..8) and fills id and
   * data (8 bytes of room), or PSFW_BUS_TIMEOUT when none is waiting, PSFW_NO_CHANNEL
   * when the board has no such bus. */
  int32_t (*can_receive)(psfw_board* b, uint8_t can, uint32_t* id, uint8_t* data);
  /* Version 3. NVM: copies len bytes of the page from offset into data; returns len, or
   * PSFW_NO_CHANNEL when [offset, offset + len) leaves the page. Takes no time. */
  int32_t (*nvm_read)(psfw_board* b, uint32_t offset, uint8_t* data, uint32_t len);
  /* Version 3. NVM: programs len bytes at offset; the clock advances by PSFW_NVM_WRITE_US
   * for every PSFW_NVM_WRITE_PAGE_BYTES-byte page the bytes touch (counted in a task's
   * budget). Returns len, or PSFW_NO_CHANNEL when the range leaves the page. */
  int32_t (*nvm_write)(psfw_board* b, uint32_t offset, const uint8_t* data, uint32_t len);
} psfw_board_api;

typedef struct psfw_task {
  uint32_t period_ms; /* run every period_ms, first at init + period_ms */
  uint32_t budget_us; /* worst-case execution budget; 0 = the period */
  void (*run)(void* ram, psfw_board* b, const psfw_board_api* api);
} psfw_task;

typedef struct psfw_firmware {
  uint32_t abi_version; /* PSFW_ABI_VERSION the firmware was built against (>= PSFW_ABI_VERSION_MIN) */
  const char* name;
  uint32_t instance_bytes; /* zeroed RAM the host provides */
  /* Called once at power-up with the firmware's own configuration blob; returns 0
   * on success. */
  int32_t (*init)(void* ram, psfw_board* b, const psfw_board_api* api, const uint8_t* config,
                  uint32_t config_len);
  uint32_t task_count;
  psfw_task tasks[PSFW_MAX_TASKS];
} psfw_firmware;

/* Configuration schema (optional, any contract version): the fields of the blob init
 * receives, as a const table the firmware exports under PSFW_CONFIG_SCHEMA_SYMBOL. The
 * loader reads it without running firmware code (from the library in host mode, from
 * the ELF's flash in target mode), checks `bms.firmware.config` against it (an unknown
 * key, a number of the wrong type or out of [min, max] is an error at its file:line)
 * and builds the blob in the table's order, each field as a little-endian int32 or
 * IEEE-754 float (count of them for a list), an omitted key taking its default. A
 * firmware without the symbol gets the blob as written (docs/firmware.md). */
#define PSFW_CONFIG_SCHEMA_VERSION 1u
#define PSFW_CONFIG_SCHEMA_SYMBOL "psfw_firmware_config_schema"
#define PSFW_CONFIG_MAX_FIELDS 256u
enum psfw_config_type { PSFW_CONFIG_INT32 = 0, PSFW_CONFIG_FLOAT32 = 1 };

typedef struct psfw_config_field {
  double min, max;   /* allowed values, both included (an INT32 field's: whole numbers) */
  double def;        /* the value of an omitted key */
  const char* name;  /* its key under bms.firmware.config: letters, digits, '_' */
  const char* unit;  /* shown with the range ("" or NULL: none) */
  const char* doc;   /* one line, shown with the range ("" or NULL: none) */
  uint32_t type;     /* enum psfw_config_type */
  uint32_t count;    /* 1: one number; n > 1: a list of exactly n numbers */
} psfw_config_field;

/* One row: PSFW_CONFIG_FIELD("cov_mV", PSFW_CONFIG_INT32, 1, 3000, 5000, 4250, "mV", "cell over-voltage trip") */
#define PSFW_CONFIG_FIELD(name, type, count, min, max, def, unit, doc) \
  { (min), (max), (def), (name), (unit), (doc), (type), (count) }

typedef struct psfw_config_schema {
  uint32_t version; /* PSFW_CONFIG_SCHEMA_VERSION */
  uint32_t field_count; /* at most PSFW_CONFIG_MAX_FIELDS */
  const psfw_config_field* fields;
} psfw_config_schema;

/* The one symbol a firmware library exports. */
typedef const psfw_firmware* (*psfw_entry_fn)(void);
#define PSFW_ENTRY_SYMBOL "psfw_firmware_entry"

#ifdef __cplusplus
}
#endif

#endif /* PACKSIM_FW_H */
