#!/usr/bin/env bash
# Compiles every bms/ source alone for a Cortex-M4 with Debian's gcc-arm-none-eabi:
# the proof that the control core is unchanged firmware. Usage: bms/cross_check.sh [OUTDIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-$(mktemp -d)}
mkdir -p "$out"
CXX=${ARM_CXX:-arm-none-eabi-g++}
flags=(-std=c++17 -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -Os
       -ffreestanding -fno-exceptions -fno-rtti -Wall -Wextra -Werror -Wdouble-promotion
       -I "$here/..")
objs=()
for src in "$here"/*.cpp "$here"/afe/*.cpp; do
  obj="$out/$(basename "${src%.cpp}").o"
  "$CXX" "${flags[@]}" -c "$src" -o "$obj"
  objs+=("$obj")
done
# The C headers a user's firmware includes (the contract, the register layouts) are C99.
for h in "$here"/packsim_fw.h "$here"/afe/*.h; do
  printf '#include "%s"\n' "$h" | "${ARM_CC:-arm-none-eabi-gcc}" -std=c99 -pedantic -Wall -Wextra -Werror -fsyntax-only -x c -
done
arm-none-eabi-ar rcs "$out/libpacksim_bms.a" "${objs[@]}"
arm-none-eabi-size -t "${objs[@]}" | tail -1 | awk '{printf "bms core for cortex-m4: text %s B, data %s B, bss %s B\n", $1, $2, $3}'
