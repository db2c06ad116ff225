// The simulator's engine against the standard one: the same seed gives the same words,
// bit for bit, across many regenerations of the state (Mt19937_64 regenerates and
// tempers a whole state at a time, the standard one word by word).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "models/random/mt19937_64.hpp"
#include "models/random/random.hpp"

namespace packsim {
namespace {

void expectStandardWords() {
  for (uint64_t seed : {uint64_t{0}, uint64_t{1}, uint64_t{5489}, uint64_t{42}, uint64_t{0xFFFFFFFFFFFFFFFFull},
                        deriveSeed(7, 0x536A), deriveSeed(123456789, 0x455C)}) {
    std::mt19937_64 standard(seed);
    Mt19937_64 ours(seed);
    for (int i = 0; i < 5 * 312 + 7; ++i) ASSERT_EQ(ours(), standard()) << "seed " << seed << ", word " << i;
  }
}

TEST(Mt19937_64, SameWordsAsTheStandardEngine) { expectStandardWords(); }

TEST(Mt19937_64, SameWordsTwoWordsAStep) {  // the path of a machine without AVX2
  const bool was = Mt19937_64::useFourWordSteps(false);
  expectStandardWords();
  Mt19937_64::useFourWordSteps(was);
}

TEST(Mt19937_64, DefaultSeedIsTheStandardOne) {
  std::mt19937_64 standard;
  Mt19937_64 ours;
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(ours(), standard());
}

TEST(Rng, DrawsTheStandardEngineWords) {
  std::mt19937_64 standard(99);
  Rng rng(99);
  for (int i = 0; i < 2000; ++i) ASSERT_EQ(rng(), standard());
  EXPECT_EQ(Rng::min(), std::mt19937_64::min());
  EXPECT_EQ(Rng::max(), std::mt19937_64::max());
}

}  // namespace
}  // namespace packsim
