// pow for the packsim program, which links HDF5's static library: the program is linked
// with -Wl,--wrap=pow (core/cli/CMakeLists.txt), so every call of pow in it comes here.
//
// Why: HDF5's scale-offset filter (the float channels stored to their decimals) computes
// pow(10, D) once per stored value, with the same D throughout: some 125 instructions a
// value at the end of a run (1.6 % of a 12-cell run's instructions), about 20 here.
// Integral powers of ten from -32 to 32 are looked up in a table that libm's own pow
// filled (the same bits: the same function of the same arguments, in the same rounding
// mode); any other argument goes to libm's pow itself.
#include <cmath>

extern "C" double __real_pow(double x, double y);  // libm's pow (the linker's --wrap)

namespace {

constexpr int kMaxExponent = 32;
double gPowerOfTen[2 * kMaxExponent + 1];  // 10^e at [e + kMaxExponent]
bool gFilled = false;                      // constant-initialised: false until the fill below

// Filled before main (no thread yet, no guard to test on each call); a pow from another
// static initialiser that runs first goes to libm's pow.
const struct FillPowersOfTen {
  FillPowersOfTen() {
    for (int e = -kMaxExponent; e <= kMaxExponent; ++e) gPowerOfTen[e + kMaxExponent] = __real_pow(10.0, e);
    gFilled = true;
  }
} kFill;

}  // namespace

extern "C" double __wrap_pow(double x, double y) {
  if (x == 10.0 && y >= -kMaxExponent && y <= kMaxExponent) {
    const int e = static_cast<int>(y);
    if (static_cast<double>(e) == y && gFilled) return gPowerOfTen[e + kMaxExponent];
  }
  return __real_pow(x, y);
}
