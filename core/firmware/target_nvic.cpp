#include "core/firmware/target_nvic.hpp"

#include <algorithm>

namespace packsim {

namespace {

constexpr uint32_t kIser = 0x100, kIcer = 0x180, kIspr = 0x200, kIcpr = 0x280, kIabr = 0x300, kIpr = 0x400;
constexpr uint32_t kIcsr = 0xD04, kVtor = 0xD08, kAircr = 0xD0C, kStir = 0xF00;
constexpr uint32_t kIcsrRetToBase = 1u << 11, kIcsrIsrPending = 1u << 22;
constexpr uint8_t kPriorityBits = 0xF0;  // the implemented bits of a priority byte

}  // namespace

void TargetNvic::reset() {
  enabled_.fill(false);
  pending_.fill(false);
  active_.fill(false);
  priority_.fill(0);
  vtor_ = vtorReset_;
  prigroup_ = 0;
}

int TargetNvic::groupPriority(uint8_t p) const {
  // PRIGROUP n: bits [7:n+1] are the group priority, [n:0] the subpriority.
  const uint32_t subMask = (2u << prigroup_) - 1u;
  return static_cast<int>(p & ~subMask & 0xFFu);
}

int TargetNvic::executionPriority(uint32_t primask, uint32_t faultmask, uint32_t basepri) const {
  int prio = kThreadPriority;
  for (int i = 0; i < kTargetIrqLines; ++i)
    if (active_[static_cast<size_t>(i)]) prio = std::min(prio, groupPriority(priority_[static_cast<size_t>(i)]));
  if ((basepri & 0xFFu) != 0) prio = std::min(prio, groupPriority(static_cast<uint8_t>(basepri & kPriorityBits)));
  if (primask & 1u) prio = std::min(prio, 0);
  if (faultmask & 1u) prio = std::min(prio, -1);
  return prio;
}

int TargetNvic::next(int executionPriority) const {
  int best = -1;
  for (int i = 0; i < kTargetIrqLines; ++i) {
    const size_t k = static_cast<size_t>(i);
    if (!pending_[k] || !enabled_[k] || active_[k]) continue;
    if (groupPriority(priority_[k]) >= executionPriority) continue;
    if (best < 0 || priority_[k] < priority_[static_cast<size_t>(best)]) best = i;
  }
  return best;
}

bool TargetNvic::anyPendingEnabled() const {
  for (int i = 0; i < kTargetIrqLines; ++i)
    if (pending_[static_cast<size_t>(i)] && enabled_[static_cast<size_t>(i)]) return true;
  return false;
}

bool TargetNvic::anyActive() const {
  return std::any_of(active_.begin(), active_.end(), [](bool a) { return a; });
}

void TargetNvic::activate(int irq) {
  pending_[static_cast<size_t>(irq)] = false;
  active_[static_cast<size_t>(irq)] = true;
}

uint32_t TargetNvic::read(uint32_t offset, uint32_t ipsr) const {
  const auto bits = [](const std::array<bool, kTargetIrqLines>& a) {
    uint32_t v = 0;
    for (int i = 0; i < kTargetIrqLines; ++i)
      if (a[static_cast<size_t>(i)]) v |= 1u << i;
    return v;
  };
  if (offset == kIser || offset == kIcer) return bits(enabled_);
  if (offset == kIspr || offset == kIcpr) return bits(pending_);
  if (offset == kIabr) return bits(active_);
  if (offset >= kIpr && offset < kIpr + 4 * ((kTargetIrqLines + 3) / 4)) {
    uint32_t v = 0;
    for (uint32_t b = 0; b < 4; ++b) {
      const uint32_t irq = offset - kIpr + b;
      if (irq < kTargetIrqLines) v |= uint32_t{priority_[irq]} << (8 * b);
    }
    return v;
  }
  if (offset == kIcsr) {
    uint32_t v = ipsr & 0x1FFu;
    int pend = -1;
    for (int i = 0; i < kTargetIrqLines; ++i)
      if (pending_[static_cast<size_t>(i)] && enabled_[static_cast<size_t>(i)] && pend < 0) pend = i;
    if (pend >= 0) v |= static_cast<uint32_t>(16 + pend) << 12;
    if (std::any_of(pending_.begin(), pending_.end(), [](bool p) { return p; })) v |= kIcsrIsrPending;
    int activeCount = 0;
    for (bool a : active_) activeCount += a ? 1 : 0;
    if (activeCount <= 1) v |= kIcsrRetToBase;
    return v;
  }
  if (offset == kVtor) return vtor_;
  if (offset == kAircr) return 0xFA050000u | (prigroup_ << 8);
  return 0;
}

void TargetNvic::write(uint32_t offset, uint32_t value, unsigned size) {
  const auto each = [&](std::array<bool, kTargetIrqLines>& a, bool to) {
    for (int i = 0; i < kTargetIrqLines; ++i)
      if (value & (1u << i)) a[static_cast<size_t>(i)] = to;
  };
  if (offset == kIser) return each(enabled_, true);
  if (offset == kIcer) return each(enabled_, false);
  if (offset == kIspr) return each(pending_, true);
  if (offset == kIcpr) return each(pending_, false);
  if (offset >= kIpr && offset < kIpr + 4 * ((kTargetIrqLines + 3) / 4)) {
    for (uint32_t b = 0; b < size; ++b) {
      const uint32_t irq = offset - kIpr + b;
      if (irq < kTargetIrqLines) priority_[irq] = static_cast<uint8_t>((value >> (8 * b)) & kPriorityBits);
    }
    return;
  }
  if (offset == kVtor) {
    vtor_ = value & ~0x7Fu;
    return;
  }
  if (offset == kAircr) {
    if ((value >> 16) == 0x05FAu) prigroup_ = (value >> 8) & 7u;
    return;
  }
  if (offset == kStir) {
    if ((value & 0x1FFu) < kTargetIrqLines) pending_[value & 0x1FFu] = true;
    return;
  }
}

}  // namespace packsim
