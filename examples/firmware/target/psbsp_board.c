/* The board-support layer of packsim's virtual Cortex-M4 (bms.firmware.target:
 * cortex-m4): the firmware contract's services (packsim_fw.h) as supervisor calls. Each
 * service is a two-instruction stub, `svc #n; bx lr`, with its arguments where the
 * AAPCS puts them (r0-r3, then the stack); packsim traps the SVC, serves it with the
 * same host code as host mode, and puts the result in r0. On a real board this file is
 * replaced by one implementing the same table on the MCU's SPI, ADC and GPIO.
 *
 * packsim calls into the firmware through the three functions at the end (the entry,
 * init and one task), each from a fresh stack, as a SysTick-driven scheduler would.
 */
#include "packsim_fw.h"
#include "psbsp.h"

/* The service numbers packsim decodes from the SVC instruction (core/firmware/target_firmware.hpp: TargetService). */
#define SVC_STUB(name, n)                                                          \
  __attribute__((naked, noinline)) static void name(void) {                        \
    __asm volatile("svc #" #n "\n\tbx lr");                                      \
  }
SVC_STUB(svc_now_ms, 1)
SVC_STUB(svc_now_us, 2)
SVC_STUB(svc_delay_us, 3)
SVC_STUB(svc_bus_transfer, 4)
SVC_STUB(svc_adc_read, 5)
SVC_STUB(svc_gpio_read, 6)
SVC_STUB(svc_gpio_write, 7)
SVC_STUB(svc_dac_write, 8)
SVC_STUB(svc_telemetry_send, 9)
SVC_STUB(svc_event, 10)
SVC_STUB(svc_set_task_period, 11)
SVC_STUB(svc_can_send, 12)
SVC_STUB(svc_can_receive, 13)
SVC_STUB(svc_nvm_read, 14)
SVC_STUB(svc_nvm_write, 15)

/* Cast through a generic function pointer: each stub has the table entry's signature
 * at the ABI level (the arguments stay in r0-r3 and on the stack, the result in r0). */
typedef void (*psbsp_fn)(void);
#define ENTRY(type, f) ((type)(psbsp_fn)(f))

const psfw_board_api psbsp_api = {
    PSFW_ABI_VERSION,
    ENTRY(uint32_t(*)(psfw_board*), svc_now_ms),
    ENTRY(uint32_t(*)(psfw_board*), svc_now_us),
    ENTRY(void (*)(psfw_board*, uint32_t), svc_delay_us),
    ENTRY(int32_t(*)(psfw_board*, uint8_t, const uint8_t*, uint16_t, uint8_t*, uint16_t), svc_bus_transfer),
    ENTRY(int32_t(*)(psfw_board*, uint8_t), svc_adc_read),
    ENTRY(int32_t(*)(psfw_board*, uint8_t), svc_gpio_read),
    ENTRY(void (*)(psfw_board*, uint8_t, int32_t), svc_gpio_write),
    ENTRY(void (*)(psfw_board*, uint8_t, int32_t), svc_dac_write),
    ENTRY(void (*)(psfw_board*, const uint8_t*, uint16_t), svc_telemetry_send),
    ENTRY(void (*)(psfw_board*, const char*), svc_event),
    ENTRY(int32_t(*)(psfw_board*, uint32_t, uint32_t, uint32_t), svc_set_task_period),
    ENTRY(int32_t(*)(psfw_board*, uint8_t, uint32_t, const uint8_t*, uint8_t), svc_can_send),
    ENTRY(int32_t(*)(psfw_board*, uint8_t, uint32_t*, uint8_t*), svc_can_receive),
    ENTRY(int32_t(*)(psfw_board*, uint32_t, uint8_t*, uint32_t), svc_nvm_read),
    ENTRY(int32_t(*)(psfw_board*, uint32_t, const uint8_t*, uint32_t), svc_nvm_write),
};

const psfw_firmware* psfw_firmware_entry(void);

/* packsim's calls. The board handle (PSBSP_BOARD, psbsp.h) is a token the stubs pass back
 * unread; the firmware's RAM, which init and the tasks are given, is also a register of
 * the board (for handlers). */
void* psbsp_ram(void) { return (void*)PSBSP_INSTANCE_RAM; }

const psfw_firmware* psbsp_entry(void) { return psfw_firmware_entry(); }

int32_t psbsp_init(const psfw_firmware* fw, void* ram, const uint8_t* config, uint32_t config_len) {
  return fw->init ? fw->init(ram, PSBSP_BOARD, &psbsp_api, config, config_len) : 0;
}

/* One task, then the watchdog kick of a scheduler whose task returned. */
void psbsp_task(const psfw_firmware* fw, uint32_t task, void* ram) {
  fw->tasks[task].run(ram, PSBSP_BOARD, &psbsp_api);
  psbsp_watchdog_kick();
}

/* The vector table (ARMv7-M: the initial stack pointer, then a handler per exception
 * number; the external interrupts from 16), where VTOR points at reset: the start of
 * flash (.isr_vector first in psbsp_cm4.ld). An interrupt line without a handler of the
 * firmware's keeps the default one, which packsim reports as a fault if it is ever
 * taken. The system exceptions' entries are unused: packsim ends the run with a
 * firmware_fault where the chip would enter a fault handler. */
void psbsp_default_handler(void);
void psbsp_default_handler(void) {
  for (;;) {
  }
}
void PSBSP_ALERT_IRQHandler(void) __attribute__((weak, alias("psbsp_default_handler")));
void PSBSP_CAN_RX_IRQHandler(void) __attribute__((weak, alias("psbsp_default_handler")));
void PSBSP_TIMER_IRQHandler(void) __attribute__((weak, alias("psbsp_default_handler")));
extern uint32_t __psbsp_stack_top;
typedef void (*psbsp_vector)(void);
__attribute__((section(".isr_vector"), used)) const psbsp_vector psbsp_vectors[16 + 3] = {
    (psbsp_vector)(uintptr_t)&__psbsp_stack_top,
    psbsp_default_handler, psbsp_default_handler, psbsp_default_handler, psbsp_default_handler,  /* reset, NMI, HardFault, MemManage */
    psbsp_default_handler, psbsp_default_handler, 0, 0, 0, 0,                                    /* BusFault, UsageFault, reserved */
    psbsp_default_handler, psbsp_default_handler, 0, psbsp_default_handler, psbsp_default_handler, /* SVCall, DebugMon, -, PendSV, SysTick */
    PSBSP_ALERT_IRQHandler, PSBSP_CAN_RX_IRQHandler, PSBSP_TIMER_IRQHandler,
};

/* No heap (the contract allocates nothing): the C library's allocator, should
 * anything call it (newlib's stdio on a first use), gets none. */
void* _sbrk(int increment);
void* _sbrk(int increment) {
  (void)increment;
  return (void*)-1;
}
