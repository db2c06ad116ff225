#!/usr/bin/env bash
# Builds a firmware for packsim's virtual Cortex-M4 (bms.firmware.target: cortex-m4):
# your unchanged application sources, this folder's board-support layer and linker
# script, Debian's arm-none-eabi-gcc. Usage:
#   examples/firmware/target/build-cm4.sh OUT.elf SOURCE.c|SOURCE.cpp... [-I DIR]...
# e.g. examples/firmware/target/build-cm4.sh build/example_bms_cm4.elf examples/firmware/example_bms.c
# C sources build as C99; C++ sources (.cpp: packsim's own core, bms/) as freestanding
# C++17 without exceptions or RTTI, linked with arm-none-eabi-g++.
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
common=(-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os -g
        -ffunction-sections -fdata-sections -Wall -Wextra
        -I "${PACKSIM_INCLUDE_DIR:-$here/../../../bms}" -I "$here" --specs=nano.specs)
link=(--specs=nosys.specs -nostartfiles
      -Wl,--gc-sections -Wl,-T,"$here/psbsp_cm4.ld"
      -Wl,-u,psbsp_entry,-u,psbsp_init,-u,psbsp_task,-u,psbsp_api,-u,psfw_firmware_config_schema)
c_srcs=() cxx_srcs=() other=()
for a in "$@"; do
  case $a in
    *.cpp) cxx_srcs+=("$a") ;;
    *.c) c_srcs+=("$a") ;;
    *) other+=("$a") ;;
  esac
done
mkdir -p "$(dirname "$out")"
if [ ${#cxx_srcs[@]} -eq 0 ]; then
  "$CC" -std=c99 "${common[@]}" "${link[@]}" "$@" "$here/psbsp_board.c" -lm -o "$out"
  exit 0
fi
CXX=${ARM_CXX:-${CC%gcc}g++}
command -v "$CXX" >/dev/null || { echo "build-cm4.sh: $CXX not found (Debian: apt-get install gcc-arm-none-eabi)" >&2; exit 2; }
objs=$(mktemp -d)
trap 'rm -rf "$objs"' EXIT
o=()
n=0
for src in "${c_srcs[@]}" "$here/psbsp_board.c"; do
  n=$((n + 1)); o+=("$objs/$n.o")
  "$CC" -std=c99 "${common[@]}" "${other[@]}" -c "$src" -o "$objs/$n.o"
done
for src in "${cxx_srcs[@]}"; do
  n=$((n + 1)); o+=("$objs/$n.o")
  "$CXX" -std=c++17 -ffreestanding -fno-exceptions -fno-rtti "${common[@]}" "${other[@]}" -c "$src" -o "$objs/$n.o"
done
"$CXX" "${common[@]}" "${link[@]}" "${o[@]}" -lm -o "$out"
