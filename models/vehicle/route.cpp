#include "models/vehicle/route.hpp"

#include <algorithm>
#include <cmath>

namespace packsim {

double Route::lap_m() const {
  double l = 0.0;
  for (const RouteSegment& g : segments) l += g.length_m;
  return l;
}

int Route::lapAt(double s) const {
  const double lap = lap_m();
  return std::clamp(static_cast<int>(std::floor(s / lap)), 0, laps);
}

int Route::segmentAt(double s) const {
  const double lap = lap_m();
  const int n = static_cast<int>(segments.size());
  if (s >= total_m()) return n - 1;
  double x = s - std::floor(s / lap) * lap;
  for (int i = 0; i < n; ++i) {
    if (x < segments[static_cast<size_t>(i)].length_m) return i;
    x -= segments[static_cast<size_t>(i)].length_m;
  }
  return n - 1;
}

double Route::targetSpeed_m_per_s(double s, double b) const {
  const double lap = lap_m();
  const int n = static_cast<int>(segments.size());
  const int k = segmentAt(s);
  double v = segments[static_cast<size_t>(k)].speed_m_per_s;
  // Start of segment k in absolute distance.
  double start = std::floor(std::min(s, total_m() - 1e-9) / lap) * lap;
  for (int i = 0; i < k; ++i) start += segments[static_cast<size_t>(i)].length_m;
  double next = start + segments[static_cast<size_t>(k)].length_m;
  for (int j = 1; j <= n && next < total_m(); ++j) {
    const RouteSegment& g = segments[static_cast<size_t>((k + j) % n)];
    v = std::min(v, std::sqrt(g.speed_m_per_s * g.speed_m_per_s + 2.0 * b * std::max(0.0, next - s)));
    next += g.length_m;
  }
  return v;
}

}  // namespace packsim
