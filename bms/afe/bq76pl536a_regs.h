/* BQ76PL536A register layout: the one definition shared by packsim's monitor model
 * (models/afe/bq76pl536a.cpp) and its firmware driver (bms/afe/bq76pl536a_driver.cpp).
 * Plain C99, so a user's C firmware includes it too. Names and addresses follow the
 * part's datasheet; only the subset packsim models is listed (see
 * docs/firmware-bq76pl536a.md).
 *
 * Link: a stack of devices on a vertical SPI bus. The MCU talks to the bottom device,
 * which passes frames up and replies down.
 *   write frame:  [addr·2 + 1][register][data][CRC-8 over the three bytes before]
 *   read frame:   [addr·2][register][count], then count data bytes and a CRC-8 over
 *                 the whole exchange (the three request bytes and the data)
 *   CRC-8:        polynomial x^8 + x^2 + x + 1 (0x07), initial value 0, MSB first
 *   addresses:    1..62 after auto-addressing; 0 after reset (an unaddressed device
 *                 does not pass frames further up the stack); 0x3F = broadcast (writes)
 * Protected ("group 3") registers take a write only right after the shadow-control
 * key has been written to SHDW_CTRL; the key opens exactly one write.
 */
#ifndef BQ76PL536A_REGS_H
#define BQ76PL536A_REGS_H

#include <stdint.h>

/* --- frames --- */
#define BQ536_ADDR_DISCOVERY 0x00u /* every device after reset */
#define BQ536_ADDR_BROADCAST 0x3Fu /* all addressed devices (writes only) */
#define BQ536_ADDR_MAX 0x3Eu
#define BQ536_FRAME_WRITE(addr) ((uint8_t)(((addr) << 1) | 1u))
#define BQ536_FRAME_READ(addr) ((uint8_t)((addr) << 1))
#define BQ536_WRITE_FRAME_LEN 4u /* addr, register, data, CRC */
#define BQ536_READ_REQUEST_LEN 3u /* addr, register, count (then count + 1 bytes in) */
#define BQ536_CRC8_POLY 0x07u
#define BQ536_CRC8_INIT 0x00u

/* --- register addresses --- */
#define BQ536_DEVICE_STATUS 0x00u
#define BQ536_GPAI 0x01u         /* 2 bytes, big-endian: module voltage */
#define BQ536_VCELL1 0x03u       /* 2 bytes each, big-endian, VCELL1..VCELL6 */
#define BQ536_VCELL(n) ((uint8_t)(BQ536_VCELL1 + 2u * (n))) /* n = 0..5 */
#define BQ536_TEMPERATURE1 0x0Fu /* 2 bytes, big-endian: TS1 ratiometric code */
#define BQ536_TEMPERATURE2 0x11u
#define BQ536_ALERT_STATUS 0x20u
#define BQ536_FAULT_STATUS 0x21u
#define BQ536_COV_FAULT 0x22u /* cells that crossed COV, bit n = cell n+1 */
#define BQ536_CUV_FAULT 0x23u
#define BQ536_ADC_CONTROL 0x30u
#define BQ536_IO_CONTROL 0x31u
#define BQ536_CB_CTRL 0x32u /* balance switches, bit n = cell n+1 */
#define BQ536_CB_TIME 0x33u
#define BQ536_ADC_CONVERT 0x34u
#define BQ536_SHDW_CTRL 0x3Au
#define BQ536_ADDRESS_CONTROL 0x3Bu
#define BQ536_RESET 0x3Cu
/* protected (group 3) */
#define BQ536_FUNCTION_CONFIG 0x40u
#define BQ536_IO_CONFIG 0x41u
#define BQ536_CONFIG_COV 0x42u
#define BQ536_CONFIG_COVT 0x43u
#define BQ536_CONFIG_CUV 0x44u
#define BQ536_CONFIG_CUVT 0x45u
#define BQ536_CONFIG_OT 0x46u
#define BQ536_CONFIG_OTT 0x47u
#define BQ536_REGISTER_COUNT 0x50u /* registers 0x00..0x4F; others read 0 */

/* contiguous read-out blocks a driver reads in one frame each */
#define BQ536_RESULTS_FIRST BQ536_DEVICE_STATUS
#define BQ536_RESULTS_LEN (BQ536_TEMPERATURE2 + 2u - BQ536_DEVICE_STATUS) /* 0x00..0x12 */
#define BQ536_FLAGS_FIRST BQ536_ALERT_STATUS
#define BQ536_FLAGS_LEN (BQ536_CUV_FAULT + 1u - BQ536_ALERT_STATUS) /* 0x20..0x23 */

/* DEVICE_STATUS bits */
#define BQ536_DS_DRDY 0x01u      /* conversion complete, results valid */
#define BQ536_DS_CBT 0x02u       /* balancing timer running */
#define BQ536_DS_UVLO 0x04u
#define BQ536_DS_ECC_COR 0x08u
#define BQ536_DS_ALERT 0x20u     /* some ALERT_STATUS bit set */
#define BQ536_DS_FAULT 0x40u     /* some FAULT_STATUS bit set */
#define BQ536_DS_ADDR_RQST 0x80u /* an address has been assigned */

/* ALERT_STATUS bits (latched; clear by writing 1 then 0) */
#define BQ536_AS_OT1 0x01u
#define BQ536_AS_OT2 0x02u
#define BQ536_AS_SLEEP 0x04u
#define BQ536_AS_TSD 0x08u
#define BQ536_AS_FORCE 0x10u
#define BQ536_AS_ECC_ERR 0x20u
#define BQ536_AS_PARITY 0x40u
#define BQ536_AS_AR 0x80u /* address not yet assigned since reset */

/* FAULT_STATUS bits (latched; clear by writing 1 then 0) */
#define BQ536_FS_COV 0x01u
#define BQ536_FS_CUV 0x02u
#define BQ536_FS_CRC 0x04u /* a frame with a bad CRC was received */
#define BQ536_FS_POR 0x08u /* power-on / reset since last cleared */
#define BQ536_FS_FORCE 0x10u
#define BQ536_FS_I_FAULT 0x20u

/* ADC_CONTROL */
#define BQ536_AC_CELL_SEL_MASK 0x07u /* cells converted: VCELL1 .. VCELL(CELL_SEL + 1) */
#define BQ536_AC_GPAI 0x08u
#define BQ536_AC_TS1 0x10u
#define BQ536_AC_TS2 0x20u
#define BQ536_AC_ADC_ON 0x40u

/* IO_CONTROL */
#define BQ536_IO_TS1 0x01u /* thermistor divider bias on TS1 */
#define BQ536_IO_TS2 0x02u
#define BQ536_IO_SLEEP 0x04u

/* CB_TIME */
#define BQ536_CBT_TIME_MASK 0x3Fu /* 0..63 units */
#define BQ536_CBT_MINUTES 0x80u   /* units: 1 = minutes, 0 = seconds */

/* ADC_CONVERT */
#define BQ536_CONV_START 0x01u

/* ADDRESS_CONTROL (reads back the address with ADDR_RQST set once assigned) */
#define BQ536_ADDR_MASK 0x3Fu
#define BQ536_ADDR_ASSIGNED 0x80u

/* keys */
#define BQ536_RESET_KEY 0xA5u /* written to RESET */
#define BQ536_SHDW_KEY 0x35u  /* written to SHDW_CTRL: opens one protected write */

/* CONFIG_COV / CONFIG_CUV: bit 7 disables the comparator, bits 5:0 the threshold */
#define BQ536_CONFIG_DISABLE 0x80u
#define BQ536_COV_BASE_MV 2000u
#define BQ536_COV_STEP_MV 50u
#define BQ536_COV_CODE_MAX 60u /* 5.0 V */
#define BQ536_CUV_BASE_MV 700u
#define BQ536_CUV_STEP_MV 100u
#define BQ536_CUV_CODE_MAX 26u /* 3.3 V */
/* CONFIG_COVT / CONFIG_CUVT: bits 4:0 delay count, bit 7 unit (1 = 100 ms, 0 = 100 us) */
#define BQ536_DELAY_MS_UNITS 0x80u
#define BQ536_DELAY_CODE_MASK 0x1Fu
#define BQ536_DELAY_STEP_US 100u
#define BQ536_DELAY_STEP_MS 100u
/* CONFIG_OT: OT1 in bits 3:0, OT2 in bits 7:4; 0 = off, n = 1..11: 35 + 5·n degC */
#define BQ536_OT_BASE_C 35u
#define BQ536_OT_STEP_C 5u
#define BQ536_OT_CODE_MAX 11u /* 90 degC */
/* CONFIG_OTT: delay in 10 ms steps, 0..255 */
#define BQ536_OTT_STEP_MS 10u

/* --- scalings --- */
#define BQ536_CELL_FULL_SCALE_MV 6250u  /* VCELL mV = code · 6250 / 16383 */
#define BQ536_CELL_FULL_SCALE_CODE 16383u
#define BQ536_GPAI_CELL_LSBS 6u         /* GPAI mV = code · 6 · cell LSB (module input) */
#define BQ536_CELLS_MAX 6u
#define BQ536_TEMPS_MAX 2u

/* --- timing --- */
#define BQ536_CONV_US_PER_CHANNEL 6u /* default ADC timing */
#define BQ536_BALANCE_UNITS_MAX 63u

/* --- encodings (one definition for the model and every driver) --- */
static inline uint8_t bq536_clamp_code(uint32_t code, uint32_t max) { return (uint8_t)(code > max ? max : code); }
/* COV threshold: nearest step, 2.0..5.0 V */
static inline uint8_t bq536_cov_code(uint32_t mV) {
  return mV <= BQ536_COV_BASE_MV ? 0u
                                 : bq536_clamp_code((mV - BQ536_COV_BASE_MV + BQ536_COV_STEP_MV / 2u) / BQ536_COV_STEP_MV,
                                                    BQ536_COV_CODE_MAX);
}
static inline uint32_t bq536_cov_mV(uint8_t reg) {
  return BQ536_COV_BASE_MV + BQ536_COV_STEP_MV * bq536_clamp_code(reg & 0x3Fu, BQ536_COV_CODE_MAX);
}
/* CUV threshold: nearest step, 0.7..3.3 V */
static inline uint8_t bq536_cuv_code(uint32_t mV) {
  return mV <= BQ536_CUV_BASE_MV ? 0u
                                 : bq536_clamp_code((mV - BQ536_CUV_BASE_MV + BQ536_CUV_STEP_MV / 2u) / BQ536_CUV_STEP_MV,
                                                    BQ536_CUV_CODE_MAX);
}
static inline uint32_t bq536_cuv_mV(uint8_t reg) {
  return BQ536_CUV_BASE_MV + BQ536_CUV_STEP_MV * bq536_clamp_code(reg & 0x3Fu, BQ536_CUV_CODE_MAX);
}
/* COVT / CUVT: 100 us steps up to 3.1 ms, 100 ms steps beyond (to 3.1 s) */
static inline uint8_t bq536_delay_code(uint32_t delay_us) {
  const uint32_t fine = (delay_us + BQ536_DELAY_STEP_US / 2u) / BQ536_DELAY_STEP_US;
  if (fine <= BQ536_DELAY_CODE_MASK) return (uint8_t)fine;
  return (uint8_t)(BQ536_DELAY_MS_UNITS |
                   bq536_clamp_code((delay_us + 500u * BQ536_DELAY_STEP_MS) / (1000u * BQ536_DELAY_STEP_MS),
                                    BQ536_DELAY_CODE_MASK));
}
static inline uint32_t bq536_delay_us(uint8_t reg) {
  const uint32_t n = reg & BQ536_DELAY_CODE_MASK;
  return (reg & BQ536_DELAY_MS_UNITS) ? n * BQ536_DELAY_STEP_MS * 1000u : n * BQ536_DELAY_STEP_US;
}
/* CONFIG_OT nibble: nearest 5 degC step, 40..90 degC (0 = comparator off) */
static inline uint8_t bq536_ot_code(int32_t temp_C) {
  if (temp_C <= (int32_t)(BQ536_OT_BASE_C + BQ536_OT_STEP_C)) return 1u;
  return bq536_clamp_code(((uint32_t)temp_C - BQ536_OT_BASE_C + BQ536_OT_STEP_C / 2u) / BQ536_OT_STEP_C,
                          BQ536_OT_CODE_MAX);
}
static inline int32_t bq536_ot_C(uint8_t nibble) {
  return (int32_t)(BQ536_OT_BASE_C + BQ536_OT_STEP_C * bq536_clamp_code(nibble & 0x0Fu, BQ536_OT_CODE_MAX));
}
/* CONFIG_OTT: nearest 10 ms step, 0..2.55 s */
static inline uint8_t bq536_ott_code(uint32_t delay_ms) {
  return bq536_clamp_code((delay_ms + BQ536_OTT_STEP_MS / 2u) / BQ536_OTT_STEP_MS, 255u);
}
/* CB_TIME: seconds up to 63 s (at least 1), whole minutes beyond (rounded up, at most 63) */
static inline uint8_t bq536_cb_time_code(uint32_t seconds) {
  if (seconds < 1u) seconds = 1u;
  if (seconds <= BQ536_BALANCE_UNITS_MAX) return (uint8_t)seconds;
  return (uint8_t)(BQ536_CBT_MINUTES | bq536_clamp_code((seconds + 59u) / 60u, BQ536_BALANCE_UNITS_MAX));
}
static inline uint32_t bq536_cb_time_s(uint8_t reg) {
  const uint32_t n = reg & BQ536_CBT_TIME_MASK;
  return (reg & BQ536_CBT_MINUTES) ? 60u * n : n;
}

#endif /* BQ76PL536A_REGS_H */
