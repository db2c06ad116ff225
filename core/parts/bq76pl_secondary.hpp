// The secondary protection of the TI bq76pl5xx family (bq76pl536a, bq76pl455a):
// comparators independent of the ADC, read from hardware.afe.secondary in the ranges
// and steps the parts hold.
#pragma once
#include "models/afe/monitor_config.hpp"

namespace packsim {

class YamlMap;

// supervisesLink: the part has a communication timeout (comm_timeout_ms).
void readSecondaryProtection(YamlMap& m, SecondaryProtection& p, bool supervisesLink);

}  // namespace packsim
