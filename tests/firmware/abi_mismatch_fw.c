/* A test firmware built against a contract version this host does not implement. */
#include "packsim_fw.h"

static const psfw_firmware future_firmware = {PSFW_ABI_VERSION + 1u, "from the future", 16, 0, 0, {{0, 0, 0}}};

const psfw_firmware* psfw_firmware_entry(void) { return &future_firmware; }
