#include "core/scenario/rest_noise_warning.hpp"

#include <cmath>

#include "core/scenario/provenance.hpp"
#include "core/text_fmt.hpp"

namespace packsim {

namespace {

// A rest this many times shorter than the mean time between breaks completes about
// exp(-1/10) = 90 % of the time.
constexpr double kRestsPerBreak = 10.0;

std::string minutes(double s) {
  return s < 120.0 ? fmt("%.0f s", s) : s < 7200.0 ? fmt("%.0f min", s / 60.0) : fmt("%.1f h", s / 3600.0);
}

std::string number(double v) { return fmt("%.3g", v); }

}  // namespace

double meanTimeBetweenNoiseBreaks_s(double threshold_A, double noise_A_rms, double tick_s) {
  if (!(noise_A_rms > 0.0)) return INFINITY;
  const double p = std::erfc(threshold_A / (noise_A_rms * std::sqrt(2.0)));
  return p > 0.0 ? tick_s / p : INFINITY;
}

void checkRestNoise(const Scenario& s, const Provenance& p, std::vector<std::string>& out) {
  if (s.bms.firmware.library) return;  // a library firmware's rest is its own
  const double noise = s.hardware.current_sense.noise_A_rms;
  if (!(noise > 0.0)) return;
  const bms::Config& k = s.bms.image;
  const bool balancesAtRest = k.balance.enabled && (k.balance.when == bms::BalanceWhen::Rest ||
                                                    k.balance.when == bms::BalanceWhen::ChargingOrRest);
  const struct {
    bool applies;
    const char* key;
    int32_t threshold_mA;
    uint32_t rest_ms;
    const char* waits;
  } rests[] = {{true, "bms.soc.rest_current_A", k.soc.restCurrent_mA, k.soc.rest_ms, "re-anchoring the SOC on the OCV"},
               {balancesAtRest, "bms.balancing.rest_current_A", k.balance.restCurrent_mA, k.balance.rest_ms,
                "balancing at rest"}};
  for (const auto& r : rests) {
    if (!r.applies || r.rest_ms == 0) continue;
    const double threshold_A = r.threshold_mA * 1e-3, rest_s = r.rest_ms * 1e-3;
    const double between_s = meanTimeBetweenNoiseBreaks_s(threshold_A, noise, s.bms.tick_s);
    if (between_s >= kRestsPerBreak * rest_s) continue;
    out.push_back(p.describe(r.key, number(threshold_A)) + " is " + number(threshold_A / noise) +
                  " times the current sensor's " + number(noise) +
                  " A rms noise (hardware.current_sense.noise_A_rms, " +
                  p.originOf("hardware.current_sense.noise_A_rms") + "): at the " +
                  number(s.bms.tick_s) + " s BMS tick a reading at rest passes it about every " + minutes(between_s) +
                  " on average, and each one restarts the " + minutes(rest_s) + " of rest the firmware waits for before " +
                  r.waits + " (raise the threshold to about 5 times the noise, or lower the noise)");
  }
}

}  // namespace packsim
