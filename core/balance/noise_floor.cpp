#include "core/balance/noise_floor.hpp"

#include <bms/bms_limits.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace packsim {

double expectedRangeOfNormals(int n) {
  if (n < 2) return 0.0;
  // Midpoint rule over ±10 σ: the integrand is smooth and vanishes in the tails.
  const double dx = 1e-3;
  double sum = 0.0;
  for (double x = -10.0 + 0.5 * dx; x < 10.0; x += dx) {
    const double phi = 0.5 * std::erfc(-x / std::sqrt(2.0));
    sum += 1.0 - std::pow(phi, n) - std::pow(1.0 - phi, n);
  }
  return sum * dx;
}

namespace {

double readingSigma_V(const Scenario& s, int averaged) {
  const AdcChannel& a = s.hardware.afe.cell_adc;
  const MonitorConfig& m = s.hardware.afe;
  const double random2 = (a.noise_rms * a.noise_rms + a.lsb * a.lsb / 12.0) / averaged;
  const double gain_V = m.channel_gain_sd * s.pack.cell.v_max_V;
  return std::sqrt(random2 + m.channel_offset_sd_V * m.channel_offset_sd_V + gain_V * gain_V);
}

double stopDelta_V(const Scenario& s) { return s.bms.image.balance.stopDelta_mV * 1e-3; }

}  // namespace

BalanceNoiseFloor balanceNoiseFloor(const Scenario& s) {
  BalanceNoiseFloor f;
  f.channels = s.pack.series;
  const double d2 = expectedRangeOfNormals(f.channels);
  const int m = s.bms.image.balance.averageReadings;
  f.sigma_V = readingSigma_V(s, m);
  f.expected_spread_V = d2 * f.sigma_V;
  for (int k = 1; k <= bms::kMaxBalanceAverage && f.readings_needed == 0; ++k)
    if (d2 * readingSigma_V(s, k) < stopDelta_V(s)) f.readings_needed = k;
  return f;
}

std::string balanceNoiseWarning(const Scenario& s) {
  if (!s.bms.image.balance.enabled || !s.hardware.balancing.present || s.pack.series < 2) return "";
  const BalanceNoiseFloor f = balanceNoiseFloor(s);
  if (stopDelta_V(s) >= f.expected_spread_V) return "";
  char text[400];
  const int n = std::snprintf(
      text, sizeof text,
      "bms.balancing.stop_delta_mV %.1f is below the spread %d balanced cells read with: E[max-min] = d2(%d) x sigma "
      "= %.2f x %.2f mV = %.2f mV (sigma of one compared reading, %d averaged); the firmware may never declare "
      "balanced and bleeds balanced cells. ",
      stopDelta_V(s) * 1e3, f.channels, f.channels, expectedRangeOfNormals(f.channels), f.sigma_V * 1e3,
      f.expected_spread_V * 1e3, static_cast<int>(s.bms.image.balance.averageReadings));
  std::string out(text, static_cast<size_t>(std::max(0, std::min(n, static_cast<int>(sizeof text) - 1))));
  if (f.readings_needed > 0)
    out += "Set bms.balancing.average_readings >= " + std::to_string(f.readings_needed) + " or raise stop_delta_mV";
  else
    out += "Averaging cannot fix it (per-channel errors): raise stop_delta_mV";
  return out;
}

}  // namespace packsim
