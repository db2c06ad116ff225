#!/usr/bin/env bash
# Builds a firmware for packsim's virtual Cortex-M4 (bms.firmware.target: cortex-m4):
# your unchanged application sources, this folder's board-support layer and linker
# script, Debian's arm-none-eabi-gcc. Usage:
#   examples/firmware/target/build-cm4.sh OUT.elf SOURCE.c... [-I DIR]...
# e.g. examples/firmware/target/build-cm4.sh build/example_bms_cm4.elf examples/firmware/example_bms.c
# The include path has packsim's bms/ folder (packsim_fw.h, afe/*.h; $PACKSIM_INCLUDE_DIR, default
# ../../../bms from here) and this folder (psbsp.h).
# -u psfw_firmware_config_schema keeps a firmware's configuration schema (packsim_fw.h), which
# nothing in the code references, through --gc-sections; a firmware without one links as before.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
[ $# -ge 2 ] || { echo "usage: $0 OUT.elf SOURCE.c... [-I DIR]..." >&2; exit 2; }
out=$1; shift
CC=${ARM_CC:-arm-none-eabi-gcc}
command -v "$CC" >/dev/null || { echo "build-cm4.sh: $CC not found (Debian: apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi)" >&2; exit 2; }
flags=(-std=c99 -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os -g
       -ffunction-sections -fdata-sections -Wall -Wextra
       -I "${PACKSIM_INCLUDE_DIR:-$here/../../../bms}" -I "$here"
       --specs=nano.specs --specs=nosys.specs -nostartfiles
       -Wl,--gc-sections -Wl,-T,"$here/psbsp_cm4.ld"
       -Wl,-u,psbsp_entry,-u,psbsp_init,-u,psbsp_task,-u,psbsp_api,-u,psfw_firmware_config_schema)
mkdir -p "$(dirname "$out")"
"$CC" "${flags[@]}" "$@" "$here/psbsp_board.c" -lm -o "$out"
