// MT19937-64 (Matsumoto & Nishimura), the same numbers as std::mt19937_64 for the same
// seed, drawn from a buffer of tempered outputs.
//
// Why: the simulator draws a dozen normals per tick on a small pack (conversion noise
// of every monitor channel, two uniforms each pair); the standard engine tempers each
// output when it is drawn and regenerates its state one word at a time, some 38
// instructions a draw. Here both passes run over the whole state at once, two words per
// operation, four with AVX2 (GCC/Clang vector extensions: SSE2 or AVX2 on x86-64, plain
// code elsewhere), and a draw is a load and an index step. Same seeding, same recurrence, same tempering: bit
// for bit the standard sequence (tests/models/random_test.cpp compares them).
#pragma once
#include <cstddef>
#include <cstdint>

namespace packsim {

class Mt19937_64 {
 public:
  static constexpr size_t kN = 312;  // state words
  static constexpr uint64_t kDefaultSeed = 5489u;

  explicit Mt19937_64(uint64_t seed = kDefaultSeed);
  uint64_t operator()() {
    if (next_ >= kN) refill();
    return out_[next_++];
  }
  // Tests: regenerate two words a step even where AVX2 allows four (false), or four again
  // where it does (true); returns the setting before. Both give the same numbers.
  static bool useFourWordSteps(bool on);

 private:
  void refill();  // the next kN state words and their tempered outputs

  uint64_t x_[kN];    // the generator's state
  uint64_t out_[kN];  // x_ tempered: the outputs, drawn in order
  size_t next_ = kN;  // the next output to draw (kN: none left)
};

}  // namespace packsim
