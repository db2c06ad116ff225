// The virtual Cortex-M4's memory map (examples/firmware/target/psbsp_cm4.ld and psbsp.h
// say the same to the firmware): flash, RAM, the watchdog's registers, and the page
// packsim returns to when a call into the firmware ends.
#pragma once
#include <cstdint>

namespace packsim::target {

constexpr uint32_t kFlashBase = 0x08000000u, kFlashBytes = 1024u * 1024u;
constexpr uint32_t kRamBase = 0x20000000u, kRamBytes = 128u * 1024u;
constexpr uint32_t kWatchdogBase = 0x40003000u, kWatchdogBytes = 0x1000u;  // psbsp.h: KR, TIMEOUT_US, RESETS
constexpr uint32_t kPeripheralBase = 0x40004000u, kPeripheralBytes = 0x1000u;  // psbsp.h: the timer, the CAN controller
constexpr uint32_t kScsBase = 0xE000E000u, kScsBytes = 0x1000u;  // System Control Space: NVIC, SCB (target_nvic.hpp)
constexpr uint32_t kReturnPage = 0x1FFF0000u, kReturnBytes = 0x1000u;     // LR of every call: reaching it ends the call
constexpr uint32_t kStackPaint = 0xDEADBEEFu;  // the stack's fill before each call: the high-water scan's marker

}  // namespace packsim::target
