# packsim_cm4_elf(OUT SOURCES file... [ARGS arg...] [INCLUDE_DIR dir] [DEPENDS file...]
# [COMMENT text]): a Cortex-M4 ELF for packsim's target mode (bms.firmware.target:
# cortex-m4), built by this folder's build-cm4.sh with its board-support layer and linker
# script. Included by packsim's own build and by a copy of examples/firmware built on its
# own, so both build the ELF the same way. Sets PACKSIM_ARM_CC (arm-none-eabi-gcc, empty
# when not installed); the callers check it.
find_program(PACKSIM_ARM_CC arm-none-eabi-gcc)
set(PACKSIM_CM4_TARGET_DIR ${CMAKE_CURRENT_LIST_DIR})
function(packsim_cm4_elf out)
  cmake_parse_arguments(E "" "INCLUDE_DIR;COMMENT" "SOURCES;ARGS;DEPENDS" ${ARGN})
  set(tgt ${PACKSIM_CM4_TARGET_DIR})
  set(env ARM_CC=${PACKSIM_ARM_CC})
  if(E_INCLUDE_DIR)
    list(APPEND env PACKSIM_INCLUDE_DIR=${E_INCLUDE_DIR})
  endif()
  add_custom_command(OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -E env ${env} ${tgt}/build-cm4.sh ${out} ${E_SOURCES} ${E_ARGS}
    DEPENDS ${E_SOURCES} ${E_DEPENDS} ${tgt}/build-cm4.sh ${tgt}/psbsp_board.c ${tgt}/psbsp.h ${tgt}/psbsp_cm4.ld
    COMMENT "${E_COMMENT}"
    VERBATIM)
endfunction()
