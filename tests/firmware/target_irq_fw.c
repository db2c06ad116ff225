/* A test firmware for target mode's interrupts (tests/core/target_mode_test.cpp), built
 * for the virtual Cortex-M4 with examples/firmware/target/build-cm4.sh.
 *
 * Configuration (int32, this order):
 *   alert_irq        1: the ALERT handler opens the relay at the line's edge;
 *                    0: the 100 ms task polls the line (gpio) and opens it there;
 *                    2: enables and pends the CAN receive interrupt, which has no handler
 *   timer_period_us  the board timer's period (0: off); its handler counts its calls
 *   report_at_ms     task 1 reports the timer's calls once the clock reaches it
 *   race_at_ms       task 2 runs a long read-modify-write loop on a variable the
 *                    timer's handler also increments, once (0: never)
 *   race_loops       the loop's iterations
 *   race_protect     1: each read-modify-write inside a critical section (PRIMASK)
 *
 * The relay closes at init while the run request is asserted and stays closed until
 * the ALERT line is seen (by the handler or the poll).
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "packsim_fw.h"
#include "psbsp.h"

typedef struct irq_config {
  int32_t alert_irq, timer_period_us, report_at_ms, race_at_ms, race_loops, race_protect;
} irq_config;

typedef struct irq_ram {
  irq_config cfg;
  int32_t line_seen, reported, raced;
} irq_ram;

/* Shared with the timer's handler (target mode: one MCU, one copy). */
static volatile uint32_t timer_calls, shared, progress, in_loop, first_progress;

/* The ALERT handler, in assembly so that its cycles can be counted by hand against the
 * cycle model's table (docs/firmware.md): gpio_write(PSBSP_BOARD, PSFW_OUT_RELAY, 0)
 * as a tail call into the board's supervisor-call stub, whose `bx lr` is the exception
 * return.
 *   movs r0, #0 / movs r1, #0 / movs r2, #0   3 x 1
 *   ldr r3, =psbsp_api                         2
 *   ldr r3, [r3, #28]   (api->gpio_write)      2
 *   bx r3                                      1      one block: 8 cycles
 *   svc #7   (the stub, a taken branch away)   2 + 1
 * 12 (entry) + 8 + 3 = 23 cycles from the edge to the write. */
_Static_assert(offsetof(psfw_board_api, gpio_write) == 28, "gpio_write's offset in the api table");
__attribute__((naked)) void PSBSP_ALERT_IRQHandler(void) {
  __asm volatile(
      "movs r0, #0\n\t"
      "movs r1, #0\n\t"
      "movs r2, #0\n\t"
      "ldr r3, =psbsp_api\n\t"
      "ldr r3, [r3, #28]\n\t"
      "bx r3\n\t"
      ".ltorg\n\t");
}

void PSBSP_TIMER_IRQHandler(void) {
  ++timer_calls;
  shared = shared + 1;
  if (in_loop && first_progress == 0) first_progress = progress;
}

static void irq_relay(irq_ram* r, psfw_board* b, const psfw_board_api* api) {
  if (api->gpio_read(b, PSFW_IN_MONITOR_FAULT) == 1 && !r->line_seen) {
    r->line_seen = 1;
    api->event(b, "trip: monitor_fault");
  }
  api->gpio_write(b, PSFW_OUT_RELAY, api->gpio_read(b, PSFW_IN_RUN_REQUEST) == 1 && !r->line_seen);
}

static void irq_task_poll(void* ram, psfw_board* b, const psfw_board_api* api) { irq_relay((irq_ram*)ram, b, api); }

static void irq_task_report(void* ram, psfw_board* b, const psfw_board_api* api) {
  irq_ram* r = (irq_ram*)ram;
  char text[96];
  if (r->reported || (int32_t)api->now_ms(b) < r->cfg.report_at_ms) return;
  r->reported = 1;
  snprintf(text, sizeof text, "timer %lu calls, count %lu", (unsigned long)timer_calls, (unsigned long)PSBSP_TIMER_COUNT);
  api->event(b, text);
}

static void irq_task_race(void* ram, psfw_board* b, const psfw_board_api* api) {
  irq_ram* r = (irq_ram*)ram;
  char text[120];
  if (r->raced || r->cfg.race_at_ms == 0 || (int32_t)api->now_ms(b) < r->cfg.race_at_ms) return;
  r->raced = 1;
  psbsp_irq_lock();
  const uint32_t shared0 = shared, calls0 = timer_calls;
  first_progress = 0;
  in_loop = 1;
  psbsp_irq_unlock();
  for (uint32_t i = 0; i < (uint32_t)r->cfg.race_loops; ++i) {
    progress = i;
    if (r->cfg.race_protect) psbsp_irq_lock();
    const uint32_t v = shared;
    __asm volatile(".rept 48\n\tnop\n\t.endr" ::: "memory"); /* a 48-cycle block: an interrupt lands inside it */
    shared = v + 1;
    if (r->cfg.race_protect) psbsp_irq_unlock();
  }
  psbsp_irq_lock();
  in_loop = 0;
  const uint32_t calls = timer_calls - calls0;
  const uint32_t lost = shared0 + (uint32_t)r->cfg.race_loops + calls - shared;
  const uint32_t first = first_progress;
  psbsp_irq_unlock();
  snprintf(text, sizeof text, "race: %ld loops, %lu handler calls during them, the first at loop %lu, %lu updates lost",
           (long)r->cfg.race_loops, (unsigned long)calls, (unsigned long)first, (unsigned long)lost);
  api->event(b, text);
}

static int32_t irq_init(void* ram, psfw_board* b, const psfw_board_api* api, const uint8_t* config, uint32_t len) {
  irq_ram* r = (irq_ram*)ram;
  if (len != sizeof(irq_config)) return 1;
  memcpy(&r->cfg, config, sizeof r->cfg);
  api->gpio_write(b, PSFW_OUT_RELAY, api->gpio_read(b, PSFW_IN_RUN_REQUEST) == 1);
  if (r->cfg.alert_irq == 2) {
    psbsp_irq_enable(PSBSP_CAN_RX_IRQn);
    psbsp_irq_set_pending(PSBSP_CAN_RX_IRQn);
  }
  if (r->cfg.alert_irq == 1) {
    psbsp_irq_clear_pending(PSBSP_ALERT_IRQn);
    psbsp_irq_set_priority(PSBSP_ALERT_IRQn, 0);  /* above the timer */
    psbsp_irq_enable(PSBSP_ALERT_IRQn);
  }
  if (r->cfg.timer_period_us > 0) {
    psbsp_irq_set_priority(PSBSP_TIMER_IRQn, 4);
    psbsp_irq_enable(PSBSP_TIMER_IRQn);
    PSBSP_TIMER_PERIOD_US = (uint32_t)r->cfg.timer_period_us;
    PSBSP_TIMER_CTRL = 1u;
  }
  return 0;
}

static const psfw_firmware irq_firmware = {
    PSFW_ABI_VERSION, "target_irq", sizeof(irq_ram), irq_init, 3,
    {{100, 0, irq_task_poll}, {10, 0, irq_task_report}, {10, 0, irq_task_race}},
};

const psfw_firmware* psfw_firmware_entry(void) { return &irq_firmware; }
