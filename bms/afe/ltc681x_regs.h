/* LTC6811-1 / LTC6813-1 register layout and command set: the one definition shared by
 * packsim's daisy-chain model (models/afe/ltc681x.cpp) and its firmware driver
 * (bms/afe/ltc681x_driver.cpp). Plain C99, so a user's C firmware includes it too.
 * Names follow the Analog Devices data sheets (LTC6811-1/LTC6811-2 Rev. C, LTC6813-1);
 * only the subset packsim models is listed (docs/firmware-ltc681x.md).
 *
 * Link: an isoSPI daisy chain; the MCU talks to device 0 (the "primary", nearest the
 * host) through an isoSPI master (LTC6820), every device relays to the next.
 *   command:  CMD0 CMD1 PEC0 PEC1 -- CMD0 = CC[10:8], CMD1 = CC[7:0] (11-bit command code)
 *   write:    command, then per device 6 data bytes and their PEC. The data sheet: "data
 *             is sent to each device followed by the PEC ... CFGR0(S) ... PEC1(S), CFGR0(P)
 *             ... PEC1(P)" -- the FARTHEST device's data goes out first, device 0's last.
 *   read:     command, then per device 6 data bytes and the PEC that device computed --
 *             "the primary device sends out its data first ... followed by the data
 *             received on Port B": device 0's data comes back FIRST, the farthest last.
 *   PEC:      15-bit CRC, polynomial x^15+x^14+x^10+x^8+x^7+x^4+x^3+1 (0x4599), seed
 *             0b000000000010000 (16), MSB first; the 15-bit remainder is sent shifted
 *             left by one (a 0 appended as LSB), high byte first. The data sheet's worked
 *             example: PEC(0x00, 0x01) = 0x3D6E.
 * Nothing driven on the line reads as 1s: a device beyond a broken isoSPI link (or a
 * device that does not answer) leaves its 8 bytes at 0xFF, which never carries a valid
 * PEC (a valid PEC's last bit is always 0).
 */
#ifndef LTC681X_REGS_H
#define LTC681X_REGS_H

#include <stdint.h>

/* --- parts --- */
#define LTC6811_CELLS 12u
#define LTC6813_CELLS 18u
#define LTC6811_GPIOS 5u
#define LTC6813_GPIOS 9u
#define LTC681X_CELLS_MAX LTC6813_CELLS
#define LTC681X_GPIOS_MAX LTC6813_GPIOS

/* --- frames --- */
#define LTC681X_CMD_LEN 4u        /* CMD0 CMD1 PEC0 PEC1 */
#define LTC681X_GROUP_BYTES 6u    /* one register group of one device */
#define LTC681X_SLOT_BYTES 8u     /* a group and its PEC */
#define LTC681X_PEC_SEED 0x0010u
#define LTC681X_PEC_POLY 0x4599u
#define LTC681X_CMD0(cc) ((uint8_t)(((cc) >> 8) & 0x07u))
#define LTC681X_CMD1(cc) ((uint8_t)((cc) & 0xFFu))

/* --- command codes CC[10:0] (data sheets' command table) --- */
#define LTC681X_WRCFGA 0x001u
#define LTC681X_RDCFGA 0x002u
#define LTC681X_WRCFGB 0x024u /* LTC6813 only */
#define LTC681X_RDCFGB 0x026u /* LTC6813 only */
#define LTC681X_RDCVA 0x004u  /* cells 1-3 */
#define LTC681X_RDCVB 0x006u  /* cells 4-6 */
#define LTC681X_RDCVC 0x008u  /* cells 7-9 */
#define LTC681X_RDCVD 0x00Au  /* cells 10-12 */
#define LTC681X_RDCVE 0x009u  /* cells 13-15, LTC6813 only */
#define LTC681X_RDCVF 0x00Bu  /* cells 16-18, LTC6813 only */
#define LTC681X_RDAUXA 0x00Cu /* GPIO1-3 */
#define LTC681X_RDAUXB 0x00Eu /* GPIO4, GPIO5, REF */
#define LTC681X_RDAUXC 0x00Du /* GPIO6-8, LTC6813 only */
#define LTC681X_RDAUXD 0x00Fu /* GPIO9, cells 13-18 OV/UV flags, LTC6813 only */
#define LTC681X_RDSTATA 0x010u /* SC, ITMP, VA */
#define LTC681X_RDSTATB 0x012u /* VD, cells 1-12 OV/UV flags, REV, MUXFAIL, THSD */
#define LTC681X_MUTE 0x028u    /* LTC6813 only: discharge switches off, DCC kept */
#define LTC681X_UNMUTE 0x029u
#define LTC681X_CLRCELL 0x711u
#define LTC681X_CLRAUX 0x712u
#define LTC681X_CLRSTAT 0x713u
/* conversion commands: base | MD << 7 | fields */
#define LTC681X_ADCV_BASE 0x260u   /* | DCP << 4 | CH */
#define LTC681X_ADOW_BASE 0x228u   /* | PUP << 6 | DCP << 4 | CH */
#define LTC681X_ADAX_BASE 0x460u   /* | CHG */
#define LTC681X_ADSTAT_BASE 0x468u /* | CHST */
#define LTC681X_MD_SHIFT 7u
#define LTC681X_PUP_BIT 0x040u
#define LTC681X_DCP_BIT 0x010u
#define LTC681X_CH_MASK 0x007u

static inline uint16_t ltc681x_adcv(uint8_t md, uint8_t dcp, uint8_t ch) {
  return (uint16_t)(LTC681X_ADCV_BASE | ((uint16_t)(md & 3u) << LTC681X_MD_SHIFT) | (dcp ? LTC681X_DCP_BIT : 0u) |
                    (ch & LTC681X_CH_MASK));
}
static inline uint16_t ltc681x_adow(uint8_t md, uint8_t pup, uint8_t dcp, uint8_t ch) {
  return (uint16_t)(LTC681X_ADOW_BASE | ((uint16_t)(md & 3u) << LTC681X_MD_SHIFT) | (pup ? LTC681X_PUP_BIT : 0u) |
                    (dcp ? LTC681X_DCP_BIT : 0u) | (ch & LTC681X_CH_MASK));
}
static inline uint16_t ltc681x_adax(uint8_t md, uint8_t chg) {
  return (uint16_t)(LTC681X_ADAX_BASE | ((uint16_t)(md & 3u) << LTC681X_MD_SHIFT) | (chg & LTC681X_CH_MASK));
}
static inline uint16_t ltc681x_adstat(uint8_t md, uint8_t chst) {
  return (uint16_t)(LTC681X_ADSTAT_BASE | ((uint16_t)(md & 3u) << LTC681X_MD_SHIFT) | (chst & LTC681X_CH_MASK));
}

/* MD[1:0] with CFGRA ADCOPT (command bit descriptions table):
 *   MD  ADCOPT=0         ADCOPT=1
 *   01  27 kHz (fast)    14 kHz
 *   10   7 kHz (normal)   3 kHz
 *   11  26 Hz (filtered)  2 kHz
 *   00  422 Hz            1 kHz   -- not modelled (no conversion time below) */
#define LTC681X_MD_FAST 1u
#define LTC681X_MD_NORMAL 2u
#define LTC681X_MD_FILTERED 3u
/* CH / CHG / CHST = 0: every channel of the command */
#define LTC681X_CH_ALL 0u

/* Conversion times in us (the data sheets' conversion-time tables: ADCV all cells t6C
 * (Table 5) and one channel pair t1C (Table 6); ADAX all GPIOs and the 2nd reference
 * t6C (Table 7); ADSTAT SC, ITMP, VA, VD t4C (Table 9)). Index: 0 = 27 kHz, 1 = 14 kHz,
 * 2 = 7 kHz, 3 = 3 kHz, 4 = 2 kHz, 5 = 26 Hz. The LTC6813's three ADCs measure six
 * cells each, as the LTC6811's two do, so ADCV takes the same time on both. */
#define LTC681X_MODES 6u
#define LTC681X_T_ALL_US_INIT {1113u, 1288u, 2335u, 3033u, 4430u, 201317u}
#define LTC681X_T_ONE_US_INIT {201u, 230u, 405u, 521u, 754u, 33568u}
#define LTC681X_T_STAT_US_INIT {748u, 865u, 1563u, 2028u, 2959u, 134218u}
/* The mode index of (MD, ADCOPT), or -1 for MD = 00 (not modelled). */
static inline int ltc681x_mode_index(uint8_t md, uint8_t adcopt) {
  switch (md & 3u) {
    case LTC681X_MD_FAST: return adcopt ? 1 : 0;
    case LTC681X_MD_NORMAL: return adcopt ? 3 : 2;
    case LTC681X_MD_FILTERED: return adcopt ? 4 : 5;
    default: return -1;
  }
}
/* What a conversion command converts, for its time. */
enum ltc681x_conversion { LTC681X_CONV_CELLS = 0, LTC681X_CONV_GPIOS = 1, LTC681X_CONV_STATUS = 2 };
/* Conversion time in us of a command converting all channels (all != 0) or one channel
 * (pair / triple) of its kind; 0 for MD = 00. */
static inline uint32_t ltc681x_conversion_us(uint8_t md, uint8_t adcopt, enum ltc681x_conversion kind, int all) {
  static const uint32_t tAll[LTC681X_MODES] = LTC681X_T_ALL_US_INIT;
  static const uint32_t tOne[LTC681X_MODES] = LTC681X_T_ONE_US_INIT;
  static const uint32_t tStat[LTC681X_MODES] = LTC681X_T_STAT_US_INIT;
  const int i = ltc681x_mode_index(md, adcopt);
  if (i < 0) return 0u;
  if (!all) return tOne[i];
  return kind == LTC681X_CONV_STATUS ? tStat[i] : tAll[i];
}

/* --- Configuration Register Group A (CFGRA, both parts) --- */
#define LTC681X_CFGR0_GPIO_SHIFT 3u  /* GPIO5..1 in bits 7..3: 1 = pull-down off (default) */
#define LTC681X_CFGR0_REFON 0x04u
#define LTC681X_CFGR0_DTEN 0x02u     /* read only: the DTEN pin (discharge timer enabled) */
#define LTC681X_CFGR0_ADCOPT 0x01u
#define LTC681X_CFGR0_DEFAULT 0xF8u  /* GPIO pull-downs off, REFON 0, ADCOPT 0 */
/* CFGR1 = VUV[7:0], CFGR2 = VOV[3:0] << 4 | VUV[11:8], CFGR3 = VOV[11:4]
 *   UV comparison voltage = (VUV + 1) * 16 * 100 uV; OV = VOV * 16 * 100 uV */
/* CFGR4 = DCC8..DCC1; CFGR5 = DCTO[3:0] << 4 | DCC12..DCC9 */
#define LTC681X_DCTO_SHIFT 4u
/* --- Configuration Register Group B (CFGRB, LTC6813) ---
 * CFGRB0 = DCC16..DCC13 << 4 | GPIO9..GPIO6; CFGRB1 = MUTE(read only) FDRF PS[1:0] DTMEN
 * DCC0 DCC18 DCC17; CFGRB2..5 reserved */
#define LTC6813_CFGRB0_DEFAULT 0x0Fu
#define LTC6813_CFGRB1_MUTE 0x80u
#define LTC6813_CFGRB1_DTMEN 0x08u

/* DCTO: discharge time-out in minutes (memory bit descriptions table); code 0 = off.
 * Read back, DCTO holds the bucket of the time left (0: disabled or timed out). */
#define LTC681X_DCTO_CODES 16u
#define LTC681X_DCTO_HALF_MINUTES_INIT {0u, 1u, 2u, 4u, 6u, 8u, 10u, 20u, 30u, 40u, 60u, 80u, 120u, 150u, 180u, 240u}
static inline uint32_t ltc681x_dcto_s(uint8_t code) {
  static const uint32_t half[LTC681X_DCTO_CODES] = LTC681X_DCTO_HALF_MINUTES_INIT;
  return half[code & 0x0Fu] * 30u;
}
/* The smallest DCTO at least `seconds` long (0 s: timer off; beyond 120 min: 120 min). */
static inline uint8_t ltc681x_dcto_code(uint32_t seconds) {
  uint8_t c;
  if (seconds == 0u) return 0u;
  for (c = 1u; c < LTC681X_DCTO_CODES; ++c)
    if (ltc681x_dcto_s(c) >= seconds) return c;
  return (uint8_t)(LTC681X_DCTO_CODES - 1u);
}
/* UV / OV thresholds: the 12-bit field of a voltage in mV (UV: (VUV+1)*1.6 mV, nearest). */
static inline uint16_t ltc681x_vov_code(uint32_t mV) {
  const uint32_t c = (mV * 10u + 8u) / 16u;
  return (uint16_t)(c > 0xFFFu ? 0xFFFu : c);
}
static inline uint16_t ltc681x_vuv_code(uint32_t mV) {
  const uint32_t c = (mV * 10u + 8u) / 16u;
  return (uint16_t)(c == 0u ? 0u : (c - 1u > 0xFFFu ? 0xFFFu : c - 1u));
}

/* --- result scalings --- */
#define LTC681X_LSB_UV 100u         /* cell, GPIO, REF, VA, VD codes: 100 uV */
#define LTC681X_CLEARED 0xFFFFu     /* a result register after power-up or CLRxxx */
#define LTC6811_SC_FACTOR 20u       /* sum of cells = SC * 100 uV * 20 */
#define LTC6813_SC_FACTOR 30u       /* sum of cells = SC * 100 uV * 30 */
/* die temperature = ITMP * 100 uV / 7.6 mV/degC - 276 degC */
#define LTC681X_ITMP_UV_PER_C 7600u
#define LTC681X_ITMP_OFFSET_C 276
#define LTC681X_VREF2_MV 3000u       /* 2nd reference, biasing the GPIO thermistor dividers */
/* Open-wire rule (ADOW section): C(n) open, n = 1..cells-1, when
 * CELL_PU(n+1) - CELL_PD(n+1) < -400 mV; C0 open when CELL_PU(1) = 0; the top pin open
 * when CELL_PD(top) = 0. */
#define LTC681X_OPEN_WIRE_CODES 4000 /* 400 mV in 100 uV codes */
#define LTC681X_ADOW_CURRENT_UA 100u /* ADOW's pull-up / pull-down current */
/* STATB5 */
#define LTC681X_STB5_THSD 0x01u
#define LTC681X_STB5_MUXFAIL 0x02u

/* --- timing (electrical characteristics), in us --- */
#define LTC681X_T_WAKE_US 400u       /* SLEEP -> STANDBY (regulator start-up), max */
#define LTC681X_T_READY_US 10u       /* isoSPI IDLE -> READY, max */
#define LTC681X_T_IDLE_MIN_US 4300u  /* isoSPI port idle time-out, min (5.5 ms typ) */
#define LTC681X_T_SLEEP_MIN_US 1800000u /* watchdog time-out, min (2 s typ) */
#define LTC681X_T_REFUP_US 4400u     /* reference power-up (REFON 0 -> 1), max */

#endif /* LTC681X_REGS_H */
