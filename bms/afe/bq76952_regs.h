/* BQ76952 register layout (TI BQ76952 datasheet and BQ769x2 technical reference
 * manual): the one definition shared by packsim's model of the part
 * (models/afe/bq76952.*) and packsim's firmware driver (bms/afe/bq76952_driver.*).
 * Plain C99 so a user's C firmware includes it too.
 *
 * The part is one device per I2C bus (7-bit address BQ952_I2C_ADDR). A transaction
 * as packsim's bus contract carries it (bms/packsim_fw.h, bus_transfer):
 *   tx: [addr<<1 | 0][command][data 0][data 1]...           (write; the command
 *       register auto-increments with each data byte)
 *   rx: when rx_len > 0, a repeated start with [addr<<1 | 1] (implied, not in tx),
 *       then the bytes read from command, command+1, ...
 * In CRC mode each data byte is followed by a CRC-8 (polynomial 0x07, initial 0x00,
 * MSB first, no final XOR):
 *   write: CRC of byte 0 covers [addr<<1][command][data 0]; later bytes cover the
 *          data byte alone. A wrong CRC makes the device drop the whole write.
 *   read:  CRC of byte 0 covers [addr<<1][command][addr<<1 | 1][data 0]; later bytes
 *          cover the data byte alone (so rx_len = 2 x data bytes).
 *
 * Direct commands read 16-bit values little-endian. Subcommands: write the 16-bit
 * code to 0x3E/0x3F (low byte first); results appear in the 32-byte buffer at 0x40
 * with the checksum (~sum of code and data bytes) at 0x60 and the length (data + 4)
 * at 0x61. Data memory (0x9180..) is read the same way and written by putting the
 * address and data at 0x3E.. then checksum and length at 0x60/0x61; the device only
 * accepts data-memory writes in CONFIG_UPDATE mode (SET_CFGUPDATE ... EXIT_CFGUPDATE).
 */
#ifndef PACKSIM_BQ76952_REGS_H
#define PACKSIM_BQ76952_REGS_H

#include <stdint.h>

/* --- link --- */
#define BQ952_I2C_ADDR 0x08u          /* 7-bit, default (Settings:Configuration:I2C Address) */
#define BQ952_CRC8_POLY 0x07u         /* x^8 + x^2 + x + 1 */
#define BQ952_CRC8_INIT 0x00u
#define BQ952_I2C_BITS_PER_BYTE 9u    /* 8 data bits + ACK */
#define BQ952_I2C_FRAME_BITS 2u       /* start (or repeated start) and stop, per phase */
#define BQ952_MAX_CELLS 16u
#define BQ952_MAX_TS 3u               /* TS1..TS3 (TS3 on the FETs) */

/* --- direct commands --- */
#define BQ952_CONTROL_STATUS 0x00u
#define BQ952_SAFETY_ALERT_A 0x02u
#define BQ952_SAFETY_STATUS_A 0x03u
#define BQ952_SAFETY_ALERT_B 0x04u
#define BQ952_SAFETY_STATUS_B 0x05u
#define BQ952_SAFETY_ALERT_C 0x06u
#define BQ952_SAFETY_STATUS_C 0x07u
#define BQ952_BATTERY_STATUS 0x12u    /* 2 bytes */
#define BQ952_CELL_VOLTAGE(n) ((uint8_t)(0x14u + 2u * ((n) - 1u))) /* n = 1..16, int16 mV */
#define BQ952_STACK_VOLTAGE 0x34u     /* userV (10 mV) */
#define BQ952_PACK_VOLTAGE 0x36u
#define BQ952_LD_VOLTAGE 0x38u
#define BQ952_CC2_CURRENT 0x3Au       /* int16 userA, positive charges the pack */
#define BQ952_SUBCMD_LOW 0x3Eu
#define BQ952_SUBCMD_HIGH 0x3Fu
#define BQ952_TRANSFER_BUFFER 0x40u   /* 32 bytes */
#define BQ952_TRANSFER_BUFFER_LEN 32u
#define BQ952_RESP_CHECKSUM 0x60u
#define BQ952_RESP_LENGTH 0x61u
#define BQ952_ALARM_STATUS 0x62u      /* latched, write 1 to clear */
#define BQ952_ALARM_RAW_STATUS 0x64u
#define BQ952_ALARM_ENABLE 0x66u
#define BQ952_INT_TEMPERATURE 0x68u   /* 0.1 K */
#define BQ952_TS1_TEMPERATURE 0x70u   /* 0.1 K; TS2 0x72, TS3 0x74 */
#define BQ952_TS_TEMPERATURE(k) ((uint8_t)(0x70u + 2u * (k))) /* k = 0..2 */
#define BQ952_FET_STATUS 0x7Fu
#define BQ952_DIRECT_SPACE 0x80u      /* direct commands 0x00..0x7F */

/* Safety Alert / Status A */
#define BQ952_SA_CUV 0x04u
#define BQ952_SA_COV 0x08u
#define BQ952_SA_OCC 0x10u
#define BQ952_SA_OCD1 0x20u
#define BQ952_SA_OCD2 0x40u
#define BQ952_SA_SCD 0x80u
/* Safety Alert / Status B */
#define BQ952_SB_UTC 0x01u
#define BQ952_SB_UTD 0x02u
#define BQ952_SB_UTINT 0x04u
#define BQ952_SB_OTC 0x10u
#define BQ952_SB_OTD 0x20u
#define BQ952_SB_OTINT 0x40u
#define BQ952_SB_OTF 0x80u
/* Safety Alert / Status C */
#define BQ952_SC_OCD3 0x80u

/* Battery Status (16 bits) */
#define BQ952_BS_CFGUPDATE 0x0001u
#define BQ952_BS_POR 0x0008u          /* set at reset, cleared on EXIT_CFGUPDATE */
#define BQ952_BS_SEC_SHIFT 8u         /* security: 1 full access, 2 unsealed, 3 sealed */
#define BQ952_BS_SEC_FULLACCESS 1u
#define BQ952_BS_SS 0x0800u           /* a safety status bit is set */

/* Alarm Status / Alarm Raw Status / Alarm Enable (16 bits) */
#define BQ952_AL_ADSCAN 0x0002u       /* voltage ADC scan complete */
#define BQ952_AL_CB 0x0004u           /* balancing active */
#define BQ952_AL_XDSG 0x0020u         /* DSG FET off */
#define BQ952_AL_XCHG 0x0040u         /* CHG FET off */
#define BQ952_AL_FULLSCAN 0x0080u     /* full measurement loop complete: data ready */
#define BQ952_AL_INITCOMP 0x0200u     /* initialisation after reset complete */
#define BQ952_AL_SSA 0x4000u          /* Safety Status A has a bit set */
#define BQ952_AL_SSBC 0x8000u         /* Safety Status B or C has a bit set */
#define BQ952_AL_ENABLE_DEFAULT 0xF800u

/* FET Status */
#define BQ952_FET_CHG 0x01u
#define BQ952_FET_PCHG 0x02u
#define BQ952_FET_DSG 0x04u
#define BQ952_FET_PDSG 0x08u
#define BQ952_FET_ALRT_PIN 0x40u

/* Manufacturing Status (subcommand) / Mfg Status Init (data memory) */
#define BQ952_MFG_FET_EN 0x0010u      /* 0: FET test mode (FETs off), 1: normal FET control */

/* --- subcommands --- */
#define BQ952_SUB_DEVICE_NUMBER 0x0001u /* reads BQ952_DEVICE_NUMBER */
#define BQ952_SUB_RESET 0x0012u
#define BQ952_SUB_FET_ENABLE 0x0022u    /* toggles FET_EN */
#define BQ952_SUB_MANUFACTURING_STATUS 0x0057u
#define BQ952_SUB_DASTATUS6 0x0076u     /* accumulated charge (userAh, I4 + U4 fraction), time (s) */
#define BQ952_SUB_RESET_PASSQ 0x0082u   /* clears the accumulated charge */
#define BQ952_SUB_CB_ACTIVE_CELLS 0x0083u /* 16-bit mask: read = balancing now, write = start */
#define BQ952_SUB_CBSTATUS1 0x0085u     /* seconds host-controlled balancing has been active */
#define BQ952_SUB_SET_CFGUPDATE 0x0090u
#define BQ952_SUB_EXIT_CFGUPDATE 0x0092u
#define BQ952_SUB_DSG_PDSG_OFF 0x0093u
#define BQ952_SUB_CHG_PCHG_OFF 0x0094u
#define BQ952_SUB_ALL_FETS_OFF 0x0095u
#define BQ952_SUB_ALL_FETS_ON 0x0096u
#define BQ952_DEVICE_NUMBER 0x7695u

/* --- data memory (Settings / Protections) --- */
#define BQ952_DM_FIRST 0x9180u
#define BQ952_DM_LAST 0x937Fu
#define BQ952_DM_DA_CONFIG 0x9303u          /* H1: bits 1:0 USER_AMPS (0.1, 1, 10, 100 mA) */
#define BQ952_DM_ENABLED_PROT_A 0x9261u     /* H1: Safety A bits */
#define BQ952_DM_ENABLED_PROT_B 0x9262u     /* H1: Safety B bits */
#define BQ952_DM_ENABLED_PROT_C 0x9263u     /* H1: Safety C bits */
#define BQ952_DM_CHG_FET_PROT_A 0x9265u     /* H1: which A faults open CHG */
#define BQ952_DM_CHG_FET_PROT_B 0x9266u
#define BQ952_DM_DSG_FET_PROT_A 0x9269u     /* H1: which A faults open DSG */
#define BQ952_DM_DSG_FET_PROT_B 0x926Au
#define BQ952_DM_DSG_FET_PROT_C 0x926Bu     /* H1: which C faults open DSG */
#define BQ952_DM_CUV_THRESHOLD 0x9275u      /* U1 20..90, 50.6 mV */
#define BQ952_DM_CUV_DELAY 0x9276u          /* U2, 3.3 ms */
#define BQ952_DM_COV_THRESHOLD 0x9278u      /* U1 20..110, 50.6 mV */
#define BQ952_DM_COV_DELAY 0x9279u          /* U2, 3.3 ms */
#define BQ952_DM_CUV_RECOVERY_HYST 0x927Bu  /* U1, 50.6 mV */
#define BQ952_DM_COV_RECOVERY_HYST 0x927Cu  /* U1, 50.6 mV */
#define BQ952_DM_OCC_THRESHOLD 0x9280u      /* U1 2..62, 2 mV across the shunt */
#define BQ952_DM_OCC_DELAY 0x9281u          /* U1 1..127: (n + 2) x 3.3 ms */
#define BQ952_DM_OCD1_THRESHOLD 0x9282u     /* U1 2..100, 2 mV */
#define BQ952_DM_OCD1_DELAY 0x9283u         /* U1 1..127: (n + 2) x 3.3 ms */
#define BQ952_DM_SCD_THRESHOLD 0x9286u      /* U1: index into BQ952_SCD_THRESHOLDS_MV */
#define BQ952_DM_OCD3_THRESHOLD 0x928Au     /* I2 userA, negative: a discharge current */
#define BQ952_DM_OCD3_DELAY 0x928Cu         /* U1 0..255 s */
#define BQ952_DM_SCD_RECOVERY_TIME 0x9294u  /* U1, s */
#define BQ952_DM_OTC_THRESHOLD 0x929Au      /* I1 degC */
#define BQ952_DM_OTC_DELAY 0x929Bu          /* U1 s */
#define BQ952_DM_OTC_RECOVERY 0x929Cu       /* I1 degC (absolute) */
#define BQ952_DM_OTD_THRESHOLD 0x929Du
#define BQ952_DM_OTD_DELAY 0x929Eu
#define BQ952_DM_OTD_RECOVERY 0x929Fu
#define BQ952_DM_OTF_THRESHOLD 0x92A0u
#define BQ952_DM_OTF_DELAY 0x92A1u
#define BQ952_DM_OTF_RECOVERY 0x92A2u
#define BQ952_DM_UTC_THRESHOLD 0x92A6u
#define BQ952_DM_UTC_DELAY 0x92A7u
#define BQ952_DM_UTC_RECOVERY 0x92A8u
#define BQ952_DM_UTD_THRESHOLD 0x92A9u
#define BQ952_DM_UTD_DELAY 0x92AAu
#define BQ952_DM_UTD_RECOVERY 0x92ABu
#define BQ952_DM_PROT_RECOVERY_TIME 0x92AFu /* U1 s: OCC / OCD recovery */
#define BQ952_DM_DSG_CURRENT_THRESHOLD 0x9310u /* I2 userA: above it the pack discharges */
#define BQ952_DM_CHG_CURRENT_THRESHOLD 0x9312u /* I2 userA: above it the pack charges */
#define BQ952_DM_CB_CONFIG 0x9335u          /* H1 Balancing Configuration: */
#define BQ952_CB_CHG 0x01u                  /*   autonomous balancing while charging */
#define BQ952_CB_RLX 0x02u                  /*   autonomous balancing at rest (relax) */
#define BQ952_CB_NO_CMD 0x10u               /*   host balancing commands ignored */
#define BQ952_DM_CB_MIN_CELL_TEMP 0x9336u   /* I1 degC */
#define BQ952_DM_CB_MAX_CELL_TEMP 0x9337u   /* I1 degC */
#define BQ952_DM_CB_MAX_INT_TEMP 0x9338u    /* I1 degC */
#define BQ952_DM_CB_MAX_CELLS 0x933Au       /* U1: cells balanced at once */
#define BQ952_DM_CB_CHG_MIN_CELL_V 0x933Bu  /* I2 mV */
#define BQ952_DM_CB_CHG_MIN_DELTA 0x933Du   /* U1 mV: start above the lowest cell */
#define BQ952_DM_CB_CHG_STOP_DELTA 0x933Eu  /* U1 mV: stop at */
#define BQ952_DM_CB_RLX_MIN_CELL_V 0x933Fu  /* I2 mV */
#define BQ952_DM_CB_RLX_MIN_DELTA 0x9341u   /* U1 mV */
#define BQ952_DM_CB_RLX_STOP_DELTA 0x9342u  /* U1 mV */
#define BQ952_DM_CB_INTERVAL 0x9339u        /* U1 s: host balancing ends this long after the last CB_ACTIVE_CELLS write */
#define BQ952_DM_MFG_STATUS_INIT 0x9343u    /* H2: FET_EN at power-up */

/* --- scalings --- */
#define BQ952_CELL_LSB_MV 1.0f
#define BQ952_USERV_MV 10.0f                /* stack / PACK / LD (DA Configuration default) */
#define BQ952_TEMP_LSB_K 0.1f
#define BQ952_COV_CUV_LSB_MV 50.6f
#define BQ952_PROT_DELAY_LSB_MS 3.3f
#define BQ952_OC_DELAY_OFFSET 2u            /* OCC/OCD1 delay = (setting + 2) x 3.3 ms */
#define BQ952_COV_MIN 20u
#define BQ952_COV_MAX 110u
#define BQ952_CUV_MIN 20u
#define BQ952_CUV_MAX 90u
#define BQ952_OCC_MIN 2u
#define BQ952_OCC_MAX 62u
#define BQ952_OCD1_MIN 2u
#define BQ952_OCD1_MAX 100u
#define BQ952_OC_DELAY_MIN 1u
#define BQ952_OC_DELAY_MAX 127u
#define BQ952_OC_THRESHOLD_LSB_MV 2.0f
#define BQ952_USER_AMPS_DEFAULT 1u          /* DA Configuration USER_AMPS: 1 mA */
/* DA Configuration USER_AMPS field -> one userA in 0.1 mA */
#define BQ952_USER_AMPS_TENTHS_MA(field) ((field) == 0u ? 1u : (field) == 1u ? 10u : (field) == 2u ? 100u : 1000u)
/* The USER_AMPS field for a unit of `tenths_mA` (1, 10, 100 or 1000; larger -> 3). */
static inline uint8_t bq952_user_amps_field(uint32_t tenths_mA) {
  uint8_t f = 0;
  while (f < 3u && BQ952_USER_AMPS_TENTHS_MA(f) < tenths_mA) ++f;
  return f;
}
/* SCD threshold settings 0..15 in mV across the shunt */
#define BQ952_SCD_THRESHOLDS_MV \
  { 10, 20, 40, 60, 80, 100, 125, 150, 175, 200, 250, 300, 350, 400, 450, 500 }
#define BQ952_SCD_SETTINGS 16u

/* --- timing --- */
#define BQ952_LOOP_SLOT_US 3000u            /* one ADC slot of the measurement loop */
#define BQ952_LOOP_BASE_SLOTS 18u           /* a loop's slots: 16 cells, VC16/PACK/LD, die/VREF/VSS; + 1 per TS (up to 3) */
#define BQ952_CC_CONVERSION_US 250000u      /* coulomb counter (CC1) conversion */
#define BQ952_SUBCMD_US 500u                /* a subcommand's result is ready in the buffer (approximate) */

#endif /* PACKSIM_BQ76952_REGS_H */
