#include "models/afe/cell_conversion.hpp"

#include <algorithm>

namespace packsim {

CellChannelErrors::CellChannelErrors(int cells, double gain_sd, double offset_sd_V, uint64_t seed)
    : gain_(static_cast<size_t>(std::max(cells, 0)), 0.0), offset_(gain_.size(), 0.0) {
  Rng rng(deriveSeed(seed, RngStream::MonitorChannelErrors));
  for (size_t c = 0; c < gain_.size(); ++c) {
    if (gain_sd > 0.0) gain_[c] = gain_sd * standardNormal(rng);
    if (offset_sd_V > 0.0) offset_[c] = offset_sd_V * standardNormal(rng);
  }
}

double moduleVoltage(const std::vector<double>& cell_V, double noise_V, Rng& noise) {
  double v = 0.0;
  for (double c : cell_V) v += c;
  if (noise_V > 0.0) v += noise_V * standardNormal(noise);
  return v;
}

int64_t ThermistorCodeCache::convert(const Thermistor& ntc, double temp_C, Rng& noise) {
  const int64_t c = ntc.codeOf(ideal(ntc, temp_C), noise);
  if (ntc.noise_codes_rms == 0.0) range_ = ThermistorCodeRange::around(ntc, temp_C, c);  // (noise: no draw skipped)
  return c;
}

int64_t thermistorCode(const Thermistor& ntc, ThermistorFault fault, double temp_C, Rng& noise) {
  if (fault == ThermistorFault::Open) return ntc.fullScaleCode();
  if (fault == ThermistorFault::Short) return 0;
  return ntc.code(temp_C, noise);
}

}  // namespace packsim
