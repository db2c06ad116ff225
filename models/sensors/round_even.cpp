#include "models/sensors/round_even.hpp"

namespace packsim {

namespace detail {

bool gNativeRounding = [] {
  __builtin_cpu_init();  // may run before libgcc's own constructor
  return __builtin_cpu_supports("sse4.1") != 0;
}();

}  // namespace detail

bool useNativeRounding(bool on) {
  const bool was = detail::gNativeRounding;
  detail::gNativeRounding = on && __builtin_cpu_supports("sse4.1") != 0;
  return was;
}

}  // namespace packsim
