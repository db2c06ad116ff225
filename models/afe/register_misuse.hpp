// Writes a monitor IC ignores, as the real part does -- a read-only or reserved
// register, a frame with a bad CRC or PEC, a protected write without its key or mode --
// noted so the engineer sees them: one entry per distinct (device, register, reason),
// with how often and when. The part still ignores the write; the note changes nothing
// it does. The run turns each entry into one `register_misuse` event (core/sim/run_tracker.cpp).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace packsim {

struct RegisterMisuse {
  int device = 0;      // in the chain, 0-based; -1: every device that heard the frame
  std::string what;    // the register or command, by its data-sheet name where it has one
  std::string why;     // why the part ignored it
  double first_s = 0.0, last_s = 0.0;
  long count = 0;
};

class RegisterMisuseLog {
 public:
  void note(double t, int device, const std::string& what, const std::string& why) {
    for (RegisterMisuse& m : entries_)
      if (m.device == device && m.what == what && m.why == why) {
        ++m.count;
        m.last_s = t;
        return;
      }
    entries_.push_back({device, what, why, t, t, 1});
  }
  const std::vector<RegisterMisuse>& entries() const { return entries_; }

 private:
  std::vector<RegisterMisuse> entries_;  // in order of first occurrence
};

// "0x3A" style hex for register and command names without one.
inline std::string hexByte(unsigned v, int digits = 2) {
  static const char* d = "0123456789ABCDEF";
  std::string s = "0x";
  for (int i = digits - 1; i >= 0; --i) s += d[(v >> (4 * i)) & 0xF];
  return s;
}

// The reason a device ignores balancing bits: they name cells it does not have (a device
// of a stack with fewer cells than its inputs, e.g. the top one of a 14s pack on 6-cell
// devices, or reserved bits past its inputs). `bits`: those bits alone (bit i: the
// device's cell i + 1); `cells`: the cells it has; `digits`: the register's hex width.
inline std::string balanceBitsPastCells(uint32_t bits, int cells, int digits) {
  std::string named;
  int count = 0;
  for (int i = 0; i < 32; ++i) {
    if (!((bits >> i) & 1u)) continue;
    int j = i;
    while (j + 1 < 32 && ((bits >> (j + 1)) & 1u)) ++j;
    named += (named.empty() ? "" : ", ") + std::to_string(i + 1) + (j > i ? "-" + std::to_string(j + 1) : "");
    count += j - i + 1;
    i = j;
  }
  return "balancing bits " + hexByte(bits, digits) + " (cell" + (count > 1 ? "s " : " ") + named +
         ") for cells the device does not have (it has " + std::to_string(cells) + "): ignored, those switches stay off";
}

}  // namespace packsim
