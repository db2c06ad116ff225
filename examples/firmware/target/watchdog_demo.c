/* A small firmware for packsim's virtual Cortex-M4 that shows the watchdog
 * (scenarios/firmware/target/c_watchdog_reset_cm4.yaml): it starts the watchdog at
 * init, closes the contactors while the run request is asserted, and on its first
 * boot only it hangs in its task at hang_at_ms (a bug: a loop that never ends). The
 * watchdog, no longer kicked, resets the MCU; the boot counter in .noinit survives the
 * reset, so the second boot reports itself and runs normally: the relay closes again.
 * Each boot also counts itself in the board's NVM page (contract v3), which keeps its
 * bytes across every reset (and starts erased, 0xFF).
 *
 * Configuration (int32, this order): hang_at_ms, watchdog_timeout_us.
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "packsim_fw.h"
#include "psbsp.h"

#define WD_MAGIC 0x5744u

typedef struct wd_config {
  int32_t hang_at_ms, watchdog_timeout_us;
} wd_config;

typedef struct wd_ram {
  wd_config cfg;
  uint32_t boot;
} wd_ram;

/* Survives a watchdog reset; zero at power-up (a real chip's RAM is random there: the
 * magic word tells a warm boot from a cold one). */
PSBSP_NOINIT static struct {
  uint32_t magic, boots;
} wd_persist;

static void wd_outputs(psfw_board* b, const psfw_board_api* api, int on) {
  api->gpio_write(b, PSFW_OUT_RELAY, on);
  api->gpio_write(b, PSFW_OUT_DISCHARGE_FET, on);
  api->gpio_write(b, PSFW_OUT_CHARGE_FET, on);
}

static void wd_task(void* ram, psfw_board* b, const psfw_board_api* api) {
  wd_ram* r = (wd_ram*)ram;
  if (r->boot == 0 && (int32_t)api->now_ms(b) >= r->cfg.hang_at_ms) {
    api->event(b, "hanging (first boot only)");
    for (volatile uint32_t spin = 0;; ++spin) {
    }
  }
  wd_outputs(b, api, api->gpio_read(b, PSFW_IN_RUN_REQUEST) == 1);
}

static int32_t wd_init(void* ram, psfw_board* b, const psfw_board_api* api, const uint8_t* config, uint32_t len) {
  wd_ram* r = (wd_ram*)ram;
  char text[80];
  if (len != sizeof(wd_config)) return 1;
  memcpy(&r->cfg, config, sizeof r->cfg);
  if (wd_persist.magic != WD_MAGIC) {
    wd_persist.magic = WD_MAGIC;
    wd_persist.boots = 0;
  }
  r->boot = wd_persist.boots++;
  uint8_t nvm[4];
  uint32_t nvmBoots = 0;
  if (api->nvm_read(b, 0, nvm, 4) == 4) memcpy(&nvmBoots, nvm, 4);
  if (nvmBoots == 0xFFFFFFFFu) nvmBoots = 0; /* erased: the first boot */
  snprintf(text, sizeof text, "boot %lu after %lu watchdog resets; NVM counts %lu boots before", (unsigned long)r->boot,
           (unsigned long)PSBSP_WDG_RESETS, (unsigned long)nvmBoots);
  ++nvmBoots;
  memcpy(nvm, &nvmBoots, 4);
  api->nvm_write(b, 0, nvm, 4);
  api->event(b, text);
  psbsp_watchdog_start((uint32_t)r->cfg.watchdog_timeout_us);
  return 0;
}

static const psfw_firmware wd_firmware = {
    PSFW_ABI_VERSION, "watchdog_demo 1.0", sizeof(wd_ram), wd_init, 1,
    {{10, 100000, wd_task}},  /* a 100 ms budget: the watchdog (30 ms) catches the hang first */
};

const psfw_firmware* psfw_firmware_entry(void) { return &wd_firmware; }
