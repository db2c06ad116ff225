// The order in which a sample reply sends its result slots: the selected ones (bit b of
// a channel mask: slot b), highest first. Kept per device for the mask it was made for:
// a host selects the same channels at every sample, so the scan of the mask is done once
// per change instead of a bit scan per slot and reply (some 7 instructions a slot, 18
// slots a sample on a 12-cell PL455 device).
#pragma once
#include <array>
#include <cstdint>

namespace packsim {

class ReplySlots {
 public:
  // The slots of `mask`, highest first (slots()[0 .. count() - 1]).
  void select(uint32_t mask) {
    if (mask == mask_) return;
    mask_ = mask;
    count_ = 0;
    for (uint32_t m = mask; m != 0;) {
      const unsigned b = 31u - static_cast<unsigned>(__builtin_clz(m));
      m &= ~(1u << b);
      slot_[count_++] = static_cast<uint8_t>(b);
    }
  }
  const uint8_t* slots() const { return slot_.data(); }
  unsigned count() const { return count_; }

 private:
  uint32_t mask_ = 0;  // 0: no slot, as made
  unsigned count_ = 0;
  std::array<uint8_t, 32> slot_{};
};

}  // namespace packsim
