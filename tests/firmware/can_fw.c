/* A test firmware for a board alone's CAN bus (hardware.can; tests/core), built as a
 * host library and, unchanged, for the virtual Cortex-M4 (build-cm4.sh).
 *
 *   receive  every frame that arrives is reported ("rx 0x123 [2] 11 22 at 500129 us",
 *            the clock when the firmware read it) and echoed with id + 1 ("tx ...");
 *            read by a 1 ms task, or (config use_irq = 1, target mode) by the CAN
 *            receive interrupt's handler
 *   status   every 100 ms a frame 0x180 with a counter ("tx 0x180 [2] ...")
 *
 * Configuration (int32): use_irq.
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "packsim_fw.h"
#if defined(__arm__)
#include "psbsp.h"
#endif

typedef struct can_ram {
  int32_t use_irq;
  uint32_t counter;
} can_ram;

static void can_note(psfw_board* b, const psfw_board_api* api, const char* dir, uint32_t id, const uint8_t* d, int n) {
  char text[100];
  int k = snprintf(text, sizeof text, "%s 0x%03lX [%d]", dir, (unsigned long)id, n);
  for (int i = 0; i < n; ++i) k += snprintf(text + k, sizeof text - (size_t)k, " %02X", d[i]);
  if (dir[0] == 'r') snprintf(text + k, sizeof text - (size_t)k, " at %lu us", (unsigned long)api->now_us(b));
  api->event(b, text);
}

static void can_send(psfw_board* b, const psfw_board_api* api, uint32_t id, const uint8_t* d, uint8_t n) {
  if (api->can_send(b, 0, id, d, n) == 0) can_note(b, api, "tx", id, d, n);
}

static void can_drain(psfw_board* b, const psfw_board_api* api) {
  uint32_t id;
  uint8_t d[8];
  int32_t n;
  while ((n = api->can_receive(b, 0, &id, d)) >= 0) {
    can_note(b, api, "rx", id, d, (int)n);
    can_send(b, api, id + 1u, d, (uint8_t)n);
  }
}

#if defined(__arm__)
void PSBSP_CAN_RX_IRQHandler(void) { can_drain(PSBSP_BOARD, &psbsp_api); }
#endif

static void can_task_rx(void* ram, psfw_board* b, const psfw_board_api* api) {
  if (!((can_ram*)ram)->use_irq) can_drain(b, api);
}

static void can_task_status(void* ram, psfw_board* b, const psfw_board_api* api) {
  can_ram* r = (can_ram*)ram;
  const uint8_t d[2] = {(uint8_t)(r->counter >> 8), (uint8_t)r->counter};
  ++r->counter;
  can_send(b, api, 0x180u, d, 2);
}

static int32_t can_init(void* ram, psfw_board* b, const psfw_board_api* api, const uint8_t* config, uint32_t len) {
  can_ram* r = (can_ram*)ram;
  (void)b;
  (void)api;
  if (len != sizeof(int32_t)) return 1;
  memcpy(&r->use_irq, config, sizeof(int32_t));
#if defined(__arm__)
  if (r->use_irq) {
    PSBSP_CAN_IER = 1u;
    psbsp_irq_enable(PSBSP_CAN_RX_IRQn);
  }
#endif
  return 0;
}

static const psfw_firmware can_firmware = {
    PSFW_ABI_VERSION, "can_test", sizeof(can_ram), can_init, 2, {{1, 0, can_task_rx}, {100, 0, can_task_status}},
};

const psfw_firmware* psfw_firmware_entry(void) { return &can_firmware; }
