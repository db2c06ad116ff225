/* A firmware that only declares a configuration schema (bms/packsim_fw.h), for the
 * loader's tests (tests/core/firmware_config_schema_test.cpp): a float, a list and an
 * int32 field; built with SCHEMA_BAD, a field whose min is above its max. Its init
 * accepts any blob and it has no task. */
#include "packsim_fw.h"

static const psfw_config_field fields[] = {
    PSFW_CONFIG_FIELD("gain", PSFW_CONFIG_FLOAT32, 1u, -2.5, 2.5, 1.25, "", "current-sense gain"),
    PSFW_CONFIG_FIELD("limits_mV", PSFW_CONFIG_INT32, 3u, 0, 5000, 3300, "mV", "three limits"),
#ifdef SCHEMA_BAD
    PSFW_CONFIG_FIELD("delay_ms", PSFW_CONFIG_INT32, 1u, 100, 10, 50, "ms", "min above max"),
#else
    PSFW_CONFIG_FIELD("delay_ms", PSFW_CONFIG_INT32, 1u, 0, 60000, 50, "ms", "a debounce"),
#endif
};

__attribute__((visibility("default"))) const psfw_config_schema psfw_firmware_config_schema = {
    PSFW_CONFIG_SCHEMA_VERSION, sizeof fields / sizeof fields[0], fields};

static int32_t schema_init(void* ram, psfw_board* b, const psfw_board_api* api, const uint8_t* config, uint32_t len) {
  (void)ram, (void)b, (void)api, (void)config, (void)len;
  return 0;
}

static const psfw_firmware firmware = {PSFW_ABI_VERSION, "schema_fw", 8, schema_init, 0, {{0, 0, 0}}};

__attribute__((visibility("default"))) const psfw_firmware* psfw_firmware_entry(void) { return &firmware; }
