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
 *   interrupts  the NVIC at its architectural address (CMSIS's NVIC_EnableIRQ and
 *             NVIC_SetPriority work unchanged) with three lines: the monitor ALERT /
 *             FAULT line (its assertion, an EXTI rising edge), the CAN receive FIFO and
 *             the board's timer. A handler is a function named as below (the vector
 *             table in psbsp_board.c has weak defaults); it reaches the board through
 *             psbsp_api and PSBSP_BOARD and the firmware's RAM through psbsp_ram().
 *             Priorities: the upper 4 bits of the byte (0 highest), PRIMASK and
 *             BASEPRI mask as on the chip.
 *   timer     PSBSP_TIMER_PERIOD_US, then PSBSP_TIMER_CTRL = 1 starts it: an interrupt
 *             every period from the instant of the write.
 *   CAN       PSBSP_CAN_IER = 1: the CAN receive interrupt pends while a frame waits in
 *             the receive FIFO (a level, as a bxCAN's FMP): the handler reads with
 *             can_receive until PSFW_BUS_TIMEOUT.
 */
#ifndef PSBSP_H
#define PSBSP_H

#include <stdint.h>

#include "packsim_fw.h"

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

/* Interrupt lines (IRQn: exception number - 16) and their handlers. */
typedef enum psbsp_irqn { PSBSP_ALERT_IRQn = 0, PSBSP_CAN_RX_IRQn = 1, PSBSP_TIMER_IRQn = 2 } psbsp_irqn;
void PSBSP_ALERT_IRQHandler(void);
void PSBSP_CAN_RX_IRQHandler(void);
void PSBSP_TIMER_IRQHandler(void);

#define PSBSP_NVIC_ISER (*(volatile uint32_t*)0xE000E100u)
#define PSBSP_NVIC_ICER (*(volatile uint32_t*)0xE000E180u)
#define PSBSP_NVIC_ISPR (*(volatile uint32_t*)0xE000E200u)
#define PSBSP_NVIC_ICPR (*(volatile uint32_t*)0xE000E280u)
#define PSBSP_NVIC_IPR(n) (*(volatile uint8_t*)(0xE000E400u + (uint32_t)(n)))

static inline void psbsp_irq_enable(psbsp_irqn n) { PSBSP_NVIC_ISER = 1u << (uint32_t)n; }
static inline void psbsp_irq_disable(psbsp_irqn n) { PSBSP_NVIC_ICER = 1u << (uint32_t)n; }
static inline void psbsp_irq_clear_pending(psbsp_irqn n) { PSBSP_NVIC_ICPR = 1u << (uint32_t)n; }
static inline void psbsp_irq_set_pending(psbsp_irqn n) { PSBSP_NVIC_ISPR = 1u << (uint32_t)n; }
/* priority 0 (highest) .. 15 */
static inline void psbsp_irq_set_priority(psbsp_irqn n, uint32_t priority) { PSBSP_NVIC_IPR(n) = (uint8_t)(priority << 4); }
/* PRIMASK: every interrupt masked (a critical section) / unmasked. */
static inline void psbsp_irq_lock(void) { __asm volatile("cpsid i" ::: "memory"); }
static inline void psbsp_irq_unlock(void) { __asm volatile("cpsie i" ::: "memory"); }

/* The board's timer. */
#define PSBSP_PERIPH_BASE 0x40004000u
#define PSBSP_TIMER_CTRL (*(volatile uint32_t*)(PSBSP_PERIPH_BASE + 0x000u))      /* bit 0: run */
#define PSBSP_TIMER_PERIOD_US (*(volatile uint32_t*)(PSBSP_PERIPH_BASE + 0x004u)) /* written while stopped */
#define PSBSP_TIMER_COUNT (*(volatile const uint32_t*)(PSBSP_PERIPH_BASE + 0x008u)) /* periods since the start */
#define PSBSP_CAN_IER (*(volatile uint32_t*)(PSBSP_PERIPH_BASE + 0x400u)) /* bit 0: CAN receive interrupt while a frame waits */
#define PSBSP_INSTANCE_RAM (*(volatile const uint32_t*)(PSBSP_PERIPH_BASE + 0xFF0u)) /* psbsp_ram()'s address */

/* What a handler reaches: the board's services and the firmware's RAM (the pointer
 * init and the tasks are given). */
extern const psfw_board_api psbsp_api;
#define PSBSP_BOARD ((psfw_board*)0)
void* psbsp_ram(void);

#endif /* PSBSP_H */
