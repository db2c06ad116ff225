/* A test firmware for target mode (tests/core/target_mode_test.cpp), built for the
 * virtual Cortex-M4 with examples/firmware/target/build-cm4.sh: task 0 does what the
 * first int32 of its configuration says once the clock reaches the second (ms).
 *
 *   0  writes through a null pointer (no memory at address 0 on the MCU)
 *   1  executes an undefined instruction (UDF)
 *   2  hands bus_transfer a receive buffer in flash
 *   3  recurses with 1 KiB on the stack per level until it runs past the stack's bottom
 *   4  fills 4 KiB on the stack, then writes through a null pointer (a call that uses
 *      its stack and never returns)
 */
#include <stdint.h>
#include <string.h>

#include "packsim_fw.h"

typedef struct tf_ram {
  int32_t mode, at_ms;
} tf_ram;

/* Deep recursion: each level keeps 1 KiB live (the sum goes back to the caller). */
static uint32_t tf_deep(uint32_t level) {
  volatile uint8_t block[1024];
  for (uint32_t i = 0; i < sizeof block; ++i) block[i] = (uint8_t)(level + i);
  return level == 0 ? block[7] : tf_deep(level - 1) + block[level % sizeof block];
}

/* 4 KiB live on the stack, then the null write (noinline: its own frame). */
static __attribute__((noinline)) void tf_deep_fault(uint32_t seed) {
  volatile uint8_t block[4096];
  for (uint32_t i = 0; i < sizeof block; ++i) block[i] = (uint8_t)(seed + i);
  *(volatile uint32_t*)0 = block[seed % sizeof block];
}

static void tf_task(void* ram, psfw_board* b, const psfw_board_api* api) {
  tf_ram* r = (tf_ram*)ram;
  static const uint8_t frame[4] = {1, 2, 3, 4};
  if ((int32_t)api->now_ms(b) < r->at_ms) return;
  switch (r->mode) {
    case 0: *(volatile uint32_t*)0 = 1u; break;
    case 1: __asm volatile("udf #0"); break;
    case 3: api->event(b, tf_deep(12) ? "deep" : "deep 0"); break;
    case 4: tf_deep_fault((uint32_t)r->at_ms); break;
    default: api->bus_transfer(b, PSFW_BUS_MONITOR(0), frame, 4, (uint8_t*)frame, 4); break;
  }
}

static int32_t tf_init(void* ram, psfw_board* b, const psfw_board_api* api, const uint8_t* config, uint32_t len) {
  (void)b;
  (void)api;
  if (len != sizeof(tf_ram)) return 1;
  memcpy(ram, config, sizeof(tf_ram));
  return 0;
}

static const psfw_firmware tf_firmware = {PSFW_ABI_VERSION, "target_fault", sizeof(tf_ram), tf_init, 1, {{10, 0, tf_task}}};

const psfw_firmware* psfw_firmware_entry(void) { return &tf_firmware; }
