/* packsim's virtual Cortex-M4 board (bms.firmware.target: cortex-m4): what a firmware
 * built for the target may use beyond the firmware contract (packsim_fw.h). Everything
 * here is memory-mapped on the virtual MCU (docs/firmware.md, "Target mode").
 *
 *   watchdog  an independent watchdog: psbsp_watchdog_start(timeout_us) starts it (it
 *             cannot be stopped again, as on the chip); the board-support layer kicks
 *             it after every task call that returns, and a firmware may kick it itself
 *             with psbsp_watchdog_kick(). A missed kick resets the MCU: RAM reloaded
 *             from the ELF, the outputs low, the entry and init called again.
 *   no-init   variables declared PSBSP_NOINIT keep their value across such a reset
 *             (zero at power-up): a reset counter, an SOC to resume from.
 */
#ifndef PSBSP_H
#define PSBSP_H

#include <stdint.h>

#define PSBSP_WDG_BASE 0x40003000u
#define PSBSP_WDG_KR (*(volatile uint32_t*)(PSBSP_WDG_BASE + 0x0u))      /* key register */
#define PSBSP_WDG_TIMEOUT_US (*(volatile uint32_t*)(PSBSP_WDG_BASE + 0x4u)) /* written before the start */
#define PSBSP_WDG_RESETS (*(volatile const uint32_t*)(PSBSP_WDG_BASE + 0x8u)) /* watchdog resets so far */
#define PSBSP_WDG_KEY_START 0xCCCCu
#define PSBSP_WDG_KEY_KICK 0xAAAAu

#define PSBSP_NOINIT __attribute__((section(".noinit")))

static inline void psbsp_watchdog_start(uint32_t timeout_us) {
  PSBSP_WDG_TIMEOUT_US = timeout_us;
  PSBSP_WDG_KR = PSBSP_WDG_KEY_START;
}
static inline void psbsp_watchdog_kick(void) { PSBSP_WDG_KR = PSBSP_WDG_KEY_KICK; }

#endif /* PSBSP_H */
