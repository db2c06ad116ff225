/* A test firmware for the host's tests (tests/core/firmware_host_test.cpp,
 * firmware_run_test.cpp): what it does is chosen by the first int32 of its
 * configuration blob, the time it misbehaves by the second (ms, 0 = at once).
 *
 *   PROBE      three tasks (10, 20, 15 ms) each report "task<i> <now_us>"
 *   BUS        task 0 reports the clock around one bus transfer:
 *              "bus <before_us> <after_us> <received>"
 *   CRASH      task 0 writes through a null pointer           (SIGSEGV)
 *   HANG       task 0 never returns                            (watchdog)
 *   ABORT      init calls abort()                              (SIGABRT)
 *   DIV0       task 0 divides by zero                          (SIGFPE)
 *   INIT_FAIL  init returns 7
 *   BAD_BUS    task 0 transfers on bus 9
 *   BIG_RX     task 0 asks for more than PSFW_BUS_MAX_FRAME bytes
 *   BUS_LOOP   task 0 keeps transferring (its budget runs out in simulated time)
 *   TRIP       task 0 reports "trip: overcurrent_discharge" once
 *   RETIME     init sets task 0 to 30 ms and switches task 2 off (set_task_period);
 *              task 0 reports "retime <now_us> <result of set_task_period now>"
 *   CODES      task 0 reports once what a missing channel and a silent bus return:
 *              "codes <adc_read 99> <gpio_read 99> <can_receive> <can_send> <bus_transfer>"
 *   NVM        init reads the page's first word, writes 12 bytes at offset 4 and reports
 *              "nvm <word> <us before the write> <us after> <write result> <read past the end>"
 *   PIN_TIMING init transfers 4 + 8 bytes, then closes the relay and the FETs; task 0
 *              at at_ms transfers 4 + 8 bytes twice, then opens them (the outputs' instants)
 *   BOOTS      init counts its boots in the NVM page's first word and in a static
 *              variable, and reports "boot <NVM count before> static <static count before>
 *              ram <task runs in RAM>"; task 0 counts its runs in the instance RAM and
 *              reports "ram <runs>" (what an MCU reset clears and what it keeps)
 *   TRIP_TEXTS task 0 reports, once, texts that read as trips but are not "trip: "
 *              ("TRIP cell_overvoltage", "trip:estop"), one that is another word
 *              ("tripped count 0") and the real "trip: comm_loss"
 *   WIRING     task 0, at every run, reads ADC channels 17 and 18 and input pin 9,
 *              writes output pin 7 and DAC channel 3, and reports once
 *              "wiring <adc 17> <adc 18> <gpio_read 9>" (on a board with two MCU
 *              thermistors, channel 17 is wired and 18 is not)
 * Built as probe_fw (contract version 3) and probe_fw_v2 (PROBE_ABI=2: the same code
 * declaring version 2).
 * Every mode but PROBE closes the relay and the FETs at init, so a dead MCU leaves
 * them closed.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "packsim_fw.h"

#ifndef PROBE_ABI
#define PROBE_ABI PSFW_ABI_VERSION
#endif
#define PROBE_NO_CHANNEL (PROBE_ABI >= 3u ? PSFW_NO_CHANNEL : PSFW_NO_CHANNEL_V2)

enum { PROBE, BUS, CRASH, HANG, ABORT, DIV0, INIT_FAIL, BAD_BUS, BIG_RX, BUS_LOOP, TRIP, RETIME, CODES, PIN_TIMING, NVM, BOOTS, TRIP_TEXTS, WIRING };

typedef struct probe_ram {
  int32_t mode, at_ms;
  int32_t tripped;
} probe_ram;

static volatile int32_t probe_zero = 0;
static uint32_t probe_static_boots = 0; /* BOOTS: a writable global, which the contract asks firmwares not to keep */

static void report(psfw_board* b, const psfw_board_api* api, int task) {
  char text[48];
  snprintf(text, sizeof text, "task%d %lu", task, (unsigned long)api->now_us(b));
  api->event(b, text);
}

static void task0(void* ram, psfw_board* b, const psfw_board_api* api) {
  probe_ram* r = (probe_ram*)ram;
  uint8_t tx[4] = {1, 2, 3, 4}, rx[8];
  if (r->mode == PROBE) return report(b, api, 0);
  if (r->mode == RETIME) {
    char text[48];
    snprintf(text, sizeof text, "retime %lu %ld", (unsigned long)api->now_us(b), (long)api->set_task_period(b, 0, 10, 0));
    return api->event(b, text);
  }
  if ((int32_t)api->now_ms(b) < r->at_ms) return;
  switch (r->mode) {
    case BUS: {
      char text[64];
      const uint32_t before = api->now_us(b);
      const int32_t got = api->bus_transfer(b, PSFW_BUS_MONITOR(0), tx, 4, rx, 8);
      snprintf(text, sizeof text, "bus %lu %lu %ld", (unsigned long)before, (unsigned long)api->now_us(b), (long)got);
      api->event(b, text);
      break;
    }
    case CRASH: *(volatile int32_t*)(uintptr_t)probe_zero = 1; break;
    case HANG:
      for (;;) {
      }
    case DIV0: r->tripped = 10 / probe_zero; break;
    case BAD_BUS: api->bus_transfer(b, 9, tx, 4, rx, 8); break;
    case BIG_RX: api->bus_transfer(b, PSFW_BUS_MONITOR(0), tx, 4, rx, PSFW_BUS_MAX_FRAME + 1u); break;
    case BUS_LOOP:
      for (;;) api->bus_transfer(b, PSFW_BUS_MONITOR(0), tx, 4, rx, 8);
    case TRIP:
      if (!r->tripped) api->event(b, "trip: overcurrent_discharge");
      r->tripped = 1;
      break;
    case CODES: {
      char text[80];
      uint32_t id = 0;
      if (r->tripped) break;
      r->tripped = 1;
      const long adc = api->adc_read(b, 99), pin = api->gpio_read(b, 99), rcv = api->can_receive(b, 0, &id, rx);
      const long snd = api->can_send(b, 0, 0x100, tx, 4), bus = api->bus_transfer(b, PSFW_BUS_MONITOR(0), tx, 4, rx, 8);
      snprintf(text, sizeof text, "codes %ld %ld %ld %ld %ld", adc, pin, rcv, snd, bus);
      api->event(b, text);
      break;
    }
    case WIRING: {
      char text[64];
      const long a17 = api->adc_read(b, 17), a18 = api->adc_read(b, 18), pin = api->gpio_read(b, 9);
      api->gpio_write(b, 7, 1);
      api->dac_write(b, 3, 500);
      if (r->tripped) break;
      r->tripped = 1;
      snprintf(text, sizeof text, "wiring %ld %ld %ld", a17, a18, pin);
      api->event(b, text);
      break;
    }
    case TRIP_TEXTS:
      if (r->tripped) break;
      r->tripped = 1;
      api->event(b, "TRIP cell_overvoltage");
      api->event(b, "trip:estop");
      api->event(b, "tripped count 0");
      api->event(b, "trip: comm_loss");
      break;
    case BOOTS: {
      char text[32];
      snprintf(text, sizeof text, "ram %ld", (long)++r->tripped);
      api->event(b, text);
      break;
    }
    case PIN_TIMING:
      if (r->tripped) break;
      r->tripped = 1;
      api->bus_transfer(b, PSFW_BUS_MONITOR(0), tx, 4, rx, 8);
      api->bus_transfer(b, PSFW_BUS_MONITOR(0), tx, 4, rx, 8);
      api->gpio_write(b, PSFW_OUT_RELAY, 0);
      api->gpio_write(b, PSFW_OUT_DISCHARGE_FET, 0);
      api->gpio_write(b, PSFW_OUT_CHARGE_FET, 0);
      break;
    default: break;
  }
}

static void task1(void* ram, psfw_board* b, const psfw_board_api* api) {
  if (((probe_ram*)ram)->mode == PROBE) report(b, api, 1);
}

static void task2(void* ram, psfw_board* b, const psfw_board_api* api) {
  if (((probe_ram*)ram)->mode == PROBE) report(b, api, 2);
}

static int32_t probe_init(void* ram, psfw_board* b, const psfw_board_api* api, const uint8_t* config, uint32_t len) {
  probe_ram* r = (probe_ram*)ram;
  if (len < 8) return 1;
  memcpy(&r->mode, config, 4);
  memcpy(&r->at_ms, config + 4, 4);
  if (r->mode == ABORT) abort();
  if (r->mode == INIT_FAIL) return 7;
  if (r->mode == RETIME && (api->set_task_period(b, 0, 30, 0) != 0 || api->set_task_period(b, 2, 0, 0) != 0 ||
                            api->set_task_period(b, 5, 10, 0) != PROBE_NO_CHANNEL))
    return 9;
  if (r->mode == NVM) {
    char text[96];
    uint8_t word[4], rec[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    uint32_t w;
    api->nvm_read(b, 0, word, 4);
    memcpy(&w, word, 4);
    const uint32_t before = api->now_us(b);
    const long wrote = api->nvm_write(b, 4, rec, sizeof rec);
    const uint32_t after = api->now_us(b);
    const long past = api->nvm_read(b, 250, word, 8);
    snprintf(text, sizeof text, "nvm %lu %lu %lu %ld %ld", (unsigned long)w, (unsigned long)before, (unsigned long)after,
             wrote, past);
    api->event(b, text);
  }
  if (r->mode == BOOTS) {
    char text[64];
    uint8_t word[4];
    uint32_t boots;
    api->nvm_read(b, 0, word, 4);
    memcpy(&boots, word, 4);
    if (boots == 0xFFFFFFFFu) boots = 0; /* erased */
    snprintf(text, sizeof text, "boot %lu static %lu ram %ld", (unsigned long)boots, (unsigned long)probe_static_boots++,
             (long)r->tripped);
    ++boots;
    memcpy(word, &boots, 4);
    api->nvm_write(b, 0, word, 4);
    api->event(b, text);
  }
  if (r->mode == PIN_TIMING) {
    uint8_t tx[4] = {1, 2, 3, 4}, rx[8];
    api->bus_transfer(b, PSFW_BUS_MONITOR(0), tx, 4, rx, 8);
  }
  if (r->mode != PROBE) {
    api->gpio_write(b, PSFW_OUT_RELAY, 1);
    api->gpio_write(b, PSFW_OUT_DISCHARGE_FET, 1);
    api->gpio_write(b, PSFW_OUT_CHARGE_FET, 1);
  }
  return 0;
}

static const psfw_firmware probe_firmware = {
    PROBE_ABI, "probe", sizeof(probe_ram), probe_init, 3,
    {{10, 0, task0}, {20, 0, task1}, {15, 0, task2}},
};

const psfw_firmware* psfw_firmware_entry(void) { return &probe_firmware; }
