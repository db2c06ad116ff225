// The virtual Cortex-M4's interrupt controller (NVIC) and the System Control Block
// registers an interrupt handler needs, at their architectural addresses (ARMv7-M ARM
// B3.4, B3.2), so that CMSIS's NVIC_EnableIRQ / NVIC_SetPriority work as on the chip:
//
//   0xE000E100 ISER0   set-enable          0xE000E180 ICER0  clear-enable
//   0xE000E200 ISPR0   set-pending         0xE000E280 ICPR0  clear-pending
//   0xE000E300 IABR0   active (read-only)  0xE000E400 IPR0.. priority bytes (upper 4 bits
//                                                             implemented, as on an STM32F4)
//   0xE000ED04 ICSR    VECTACTIVE, RETTOBASE, VECTPENDING, ISRPENDING (read)
//   0xE000ED08 VTOR    vector table base (reset: the start of flash)
//   0xE000ED0C AIRCR   PRIGROUP (written with VECTKEY 0x05FA)
//   0xE000EF00 STIR    software trigger of an interrupt
//
// Other System Control Space registers read as zero and ignore writes. The board has
// PSBSP_IRQ_COUNT external interrupt lines (psbsp.h: ALERT, CAN receive, timer).
//
// Priorities: the execution priority is the highest (numerically lowest) group
// priority of the active exceptions, PRIMASK (0), FAULTMASK (-1) and BASEPRI; a pending,
// enabled interrupt pre-empts when its group priority is higher than that; among the
// pending, the lowest priority value wins, then the lowest number.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>

namespace packsim {

constexpr int kTargetIrqLines = 3;  // psbsp.h: PSBSP_ALERT_IRQn, PSBSP_CAN_RX_IRQn, PSBSP_TIMER_IRQn
constexpr int kTargetIrqAlert = 0, kTargetIrqCanRx = 1, kTargetIrqTimer = 2;
constexpr int kThreadPriority = 256;  // below every configurable priority

class TargetNvic {
 public:
  explicit TargetNvic(uint32_t vtorReset = 0) : vtorReset_(vtorReset) { reset(); }
  void reset();

  // A register of the System Control Space (offset from 0xE000E000).
  // ICSR's VECTACTIVE is `ipsr`, the running exception's number (the MCU's IPSR).
  uint32_t read(uint32_t offset, uint32_t ipsr) const;
  void write(uint32_t offset, uint32_t value, unsigned size);

  void pend(int irq) { pending_[static_cast<size_t>(irq)] = true; }
  bool pending(int irq) const { return pending_[static_cast<size_t>(irq)]; }
  bool enabled(int irq) const { return enabled_[static_cast<size_t>(irq)]; }
  bool active(int irq) const { return active_[static_cast<size_t>(irq)]; }
  uint8_t priority(int irq) const { return priority_[static_cast<size_t>(irq)]; }
  uint32_t vtor() const { return vtor_; }

  // The group priority of a priority byte under PRIGROUP.
  int groupPriority(uint8_t p) const;
  // The execution priority from the active interrupts and the masks (PRIMASK,
  // FAULTMASK: bit 0; BASEPRI: a priority byte, 0 = off).
  int executionPriority(uint32_t primask, uint32_t faultmask, uint32_t basepri) const;
  // The pending, enabled interrupt that pre-empts `executionPriority`, or -1.
  int next(int executionPriority) const;
  // Pending and enabled, whatever the masks (something may be taken once they lift).
  bool anyPendingEnabled() const;
  // Entry: pending cleared, active; the current exception becomes irq.
  void activate(int irq);
  // Return from irq's handler: no longer active.
  void deactivate(int irq) { active_[static_cast<size_t>(irq)] = false; }
  bool anyActive() const;

 private:
  uint32_t vtorReset_;
  std::array<bool, kTargetIrqLines> enabled_{}, pending_{}, active_{};
  std::array<uint8_t, kTargetIrqLines> priority_{};
  uint32_t vtor_ = 0, prigroup_ = 0;
};

}  // namespace packsim
