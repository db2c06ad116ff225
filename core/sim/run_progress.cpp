#include "core/sim/run_progress.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace packsim {

StopCondition progressCondition(double end_s, std::function<void(double, double)> report, double step_fraction) {
  const double step_s = end_s > 0.0 ? end_s * step_fraction : 1.0;
  auto next_s = std::make_shared<double>(0.0);
  return [=](double t_s, const double*, const PlantSignals&, const bms::Outputs&) {
    if (t_s >= *next_s) {
      report(t_s, end_s);
      *next_s = (std::floor(t_s / step_s) + 1.0) * step_s;
    }
    return false;
  };
}

StopCondition terminalProgressBar(double end_s, std::FILE* out) {
  return progressCondition(end_s, [out](double t_s, double end) {
    constexpr int kWidth = 30;
    const double f = end > 0.0 ? std::clamp(t_s / end, 0.0, 1.0) : 0.0;
    const int filled = static_cast<int>(f * kWidth);
    char bar[kWidth + 1];
    for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '-';
    bar[kWidth] = '\0';
    std::fprintf(out, "\r[%s] %3.0f%%  %.0f / %.0f s simulated", bar, f * 100.0, t_s, end);
    std::fflush(out);
  });
}

void terminalProgressDone(std::FILE* out) {
  std::fprintf(out, "\r\033[K");
  std::fflush(out);
}

}  // namespace packsim
