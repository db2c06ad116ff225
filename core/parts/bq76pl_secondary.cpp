#include "core/parts/bq76pl_secondary.hpp"

#include "core/scenario/value_ranges.hpp"
#include "core/scenario/yaml_map.hpp"
#include "models/afe/bq76pl455a.hpp"

namespace packsim {

void readSecondaryProtection(YamlMap& m, SecondaryProtection& p, bool supervisesLink) {
  p.enabled = m.boolean("enabled", p.enabled);
  p.cov_V = m.number("cov_V", p.cov_V, Range::closed(2.0, 5.0));
  p.cov_delay_s = m.number("cov_delay_ms", p.cov_delay_s * 1e3, Range::closed(0.0, 3100.0)) * 1e-3;
  p.cuv_V = m.number("cuv_V", p.cuv_V, Range::closed(0.7, 3.3));
  p.cuv_delay_s = m.number("cuv_delay_ms", p.cuv_delay_s * 1e3, Range::closed(0.0, 3100.0)) * 1e-3;
  p.ot_C = m.number("ot_C", p.ot_C, Range::closed(40.0, 90.0));
  p.ot_delay_s = m.number("ot_delay_ms", p.ot_delay_s * 1e3, Range::closed(0.0, 2550.0)) * 1e-3;
  if (m.has("comm_timeout_ms")) {
    if (!supervisesLink)
      throw m.errorAt("comm_timeout_ms", "only a bq76pl455a supervises its link (a communication timeout)");
    p.comm_timeout_s = m.number("comm_timeout_ms", 0.0, Range::nonNegative(600000.0)) * 1e-3;
    if (pl455CommTimeoutCode(p.comm_timeout_s) < 0)
      throw m.errorAt("comm_timeout_ms", "the part's timer steps are 0 (off), 100, 2000, 10000, 60000, 600000, "
                                         "1800000 or 7200000 ms");
  }
  m.finish();
}

}  // namespace packsim
