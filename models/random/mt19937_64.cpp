#include "models/random/mt19937_64.hpp"

#include <cstring>

namespace packsim {

namespace {

// The parameters of std::mt19937_64 ([rand.predef]).
constexpr size_t kN = Mt19937_64::kN, kM = 156;
constexpr uint64_t kMatrixA = 0xB5026F5AA96619E9ull;
constexpr uint64_t kUpper = ~uint64_t{0} << 31, kLower = ~kUpper;
constexpr uint64_t kInitMultiplier = 6364136223846793005ull;
constexpr unsigned kU = 29, kS = 17, kT = 37, kL = 43;
constexpr uint64_t kD = 0x5555555555555555ull, kB = 0x71D67FFFEDA60000ull, kC = 0xFFF7EEE000000000ull;

// Words side by side: two (one SSE2 register, x86-64's baseline) or four (one AVX2
// register); on a machine without them the compiler splits the operations.
typedef uint64_t Words2 __attribute__((vector_size(16)));
typedef uint64_t Words4 __attribute__((vector_size(32)));

#define PACKSIM_INLINE inline __attribute__((always_inline))

// (Words4 by value outside an AVX2 function: a -Wpsabi note, given at the end of the
// file, about an ABI no call here uses, every helper being inlined into the function of
// its width.)
#pragma GCC diagnostic ignored "-Wpsabi"

template <typename W>
PACKSIM_INLINE W load(const uint64_t* p) {  // unaligned
  W v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <typename W>
PACKSIM_INLINE void store(uint64_t* p, W v) {
  std::memcpy(p, &v, sizeof v);
}

// One step of the recurrence: the new word k from words k, k + 1 and the one m away.
// (-(y & 1) & a: a where y is odd, the standard's (y & 1) ? a : 0 without a branch.)
template <typename W>
PACKSIM_INLINE W twisted(W xk, W xk1, W xkm) {
  const W y = (xk & kUpper) | (xk1 & kLower);
  return xkm ^ (y >> 1) ^ (-(y & 1) & kMatrixA);
}

template <typename W>
PACKSIM_INLINE W tempered(W z) {
  z ^= (z >> kU) & kD;
  z ^= (z << kS) & kB;
  z ^= (z << kT) & kC;
  return z ^ (z >> kL);
}

// The next state of x and its tempered outputs into out, G = sizeof(W) / 8 words a step.
// Words 0 .. n-m-1 take word k+m of the old state; n-m .. n-2 word k+m-n of the new one;
// n-1 word m-1 (new) with word 0 (new) as its next. A step loads its words before it
// stores, so word k + G is still the old one, as in the standard word-by-word loop.
template <typename W>
PACKSIM_INLINE void refillWith(uint64_t* x, uint64_t* out) {
  constexpr size_t G = sizeof(W) / sizeof(uint64_t);
  static_assert((kN - kM) % G == 0 && kN % G == 0, "whole steps in the first part and the tempering");
  size_t k = 0;
  for (; k < kN - kM; k += G) store(x + k, twisted(load<W>(x + k), load<W>(x + k + 1), load<W>(x + k + kM)));
  for (; k + G <= kN - 1; k += G)
    store(x + k, twisted(load<W>(x + k), load<W>(x + k + 1), load<W>(x + (k - (kN - kM)))));
  for (; k < kN - 1; ++k) x[k] = twisted(x[k], x[k + 1], x[k - (kN - kM)]);
  x[kN - 1] = twisted(x[kN - 1], x[0], x[kM - 1]);
  for (k = 0; k < kN; k += G) store(out + k, tempered(load<W>(x + k)));
}

void refill2(uint64_t* x, uint64_t* out) { refillWith<Words2>(x, out); }
__attribute__((target("avx2"))) void refill4(uint64_t* x, uint64_t* out) { refillWith<Words4>(x, out); }

bool gFourWide = [] {
  __builtin_cpu_init();  // may run before libgcc's own constructor
  return __builtin_cpu_supports("avx2") != 0;
}();

}  // namespace

Mt19937_64::Mt19937_64(uint64_t seed) {
  x_[0] = seed;
  for (size_t i = 1; i < kN; ++i) x_[i] = kInitMultiplier * (x_[i - 1] ^ (x_[i - 1] >> 62)) + i;
}

void Mt19937_64::refill() {
  if (gFourWide)
    refill4(x_, out_);
  else
    refill2(x_, out_);
  next_ = 0;
}

bool Mt19937_64::useFourWordSteps(bool on) {
  const bool was = gFourWide;
  gFourWide = on && __builtin_cpu_supports("avx2") != 0;
  return was;
}

}  // namespace packsim
