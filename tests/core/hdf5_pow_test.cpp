// core/io/hdf5_pow.cpp: the packsim program's pow (linked with --wrap=pow, as this test
// is) gives the bits of libm's pow for every argument, from its table or not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

extern "C" double __real_pow(double x, double y);

namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Through a volatile: the compiler may not fold the call at build time.
double wrappedPow(double x, double y) {
  volatile double vx = x, vy = y;
  return std::pow(static_cast<double>(vx), static_cast<double>(vy));
}

TEST(Hdf5Pow, PowersOfTenFromTheTableAreLibmsBits) {
  for (int e = -40; e <= 40; ++e) {
    EXPECT_TRUE(sameBits(wrappedPow(10.0, e), __real_pow(10.0, e))) << e;
    EXPECT_TRUE(sameBits(wrappedPow(10.0, -0.0), __real_pow(10.0, -0.0)));
  }
}

TEST(Hdf5Pow, EveryOtherArgumentIsLibmsPow) {
  const double xs[] = {10.0, 9.999999999999998, 2.0, 0.5, -10.0, 0.0, 1e300, NAN, INFINITY};
  const double ys[] = {0.5, -1.5, 3.0000000000000004, 1e10, -1e10, 33.0, -33.0, NAN, INFINITY, -INFINITY, 2.0};
  for (double x : xs)
    for (double y : ys) EXPECT_TRUE(sameBits(wrappedPow(x, y), __real_pow(x, y))) << x << " " << y;
}

}  // namespace
