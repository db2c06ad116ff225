/* BQ76PL455A register layout and UART frame format: the one definition shared by
 * packsim's chain model (models/afe/bq76pl455a.cpp) and its firmware driver
 * (bms/afe/bq76pl455a_driver.cpp). Plain C99 so a user's C firmware includes it too.
 *
 * Addresses and names follow the datasheet's register map (SREV..MAGIC2). Items
 * marked [model] are packsim's choices where the public material leaves a field
 * open; docs/firmware-bq76pl455a.md lists them.
 *
 * Frames on the UART (the MCU talks to the bottom device; devices relay up and down
 * the differential daisy chain):
 *   command:  [init][device address, single-device / group requests only]
 *             [register address, 1 or 2 bytes][data, 0-8 bytes][CRC-16 lo][CRC-16 hi]
 *     init:   bit 7 = 1 (command frame); bits 6:4 request type; bit 3 = 2-byte
 *             register address; bits 2:0 data size (0-6 = bytes, 7 = 8 bytes)
 *     a request "with response" to a register other than CMD is a read: its one
 *     data byte is the number of bytes to return minus 1
 *   response: [n - 1][n data bytes][CRC-16 lo][CRC-16 hi], bit 7 of the first byte 0
 *   CRC-16:   x^16 + x^15 + x^2 + 1, initial value 0, bit-reflected (LSB first),
 *             no final XOR (CRC-16/ARC), over every byte before it, sent low byte first
 * Multi-byte registers are big-endian. */
#ifndef PACKSIM_BQ76PL455A_REGS_H
#define PACKSIM_BQ76PL455A_REGS_H

#include <stdint.h>

/* ---- frame format ---- */
#define PL455_INIT_COMMAND 0x80u      /* bit 7: command frame (response frames have it clear) */
#define PL455_REQ_MASK 0x70u          /* bits 6:4: request type */
#define PL455_REQ_SINGLE_R 0x00u      /* one device, with response */
#define PL455_REQ_SINGLE_NR 0x10u     /* one device, no response */
#define PL455_REQ_GROUP_R 0x20u       /* devices whose GROUP_ID matches, with response */
#define PL455_REQ_GROUP_NR 0x30u
#define PL455_REQ_BROADCAST_R 0x60u   /* every device, with response (top device first) */
#define PL455_REQ_BROADCAST_NR 0x70u
#define PL455_INIT_ADDR16 0x08u       /* bit 3: the register address takes 2 bytes */
#define PL455_INIT_SIZE_MASK 0x07u    /* bits 2:0: data bytes, 7 means 8 */
#define PL455_MAX_COMMAND_DATA 8u
#define PL455_MAX_RESPONSE_DATA 128u
#define PL455_RESPONSE_OVERHEAD 3u    /* length byte + CRC-16 */
#define PL455_CRC_POLY 0x8005u        /* x^16 + x^15 + x^2 + 1 (processed reflected: 0xA001) */
#define PL455_CRC_INIT 0x0000u
#define PL455_MAX_DEVICES 16u         /* addresses 0..15 on one daisy chain */
#define PL455_UART_BITS_PER_BYTE 10u  /* start + 8 data + stop */
#define PL455_DEFAULT_BAUD 250000u

/* Command data size field for n bytes (n = 1..6 or 8). */
#define PL455_SIZE_FIELD(n) ((uint8_t)((n) >= 8u ? 7u : (n)))
/* Data bytes a size field stands for. */
#define PL455_SIZE_BYTES(field) ((uint8_t)(((field) & 7u) == 7u ? 8u : ((field) & 7u)))

/* ---- registers: address and size in bytes ---- */
#define PL455_REG_SREV 0x00u        /* silicon revision, read only */
#define PL455_REG_CMD 0x02u         /* command: a write starts a sample of CHANNELS */
#define PL455_REG_CHANNELS 0x03u    /* 4 bytes: channel select */
#define PL455_REG_OVERSMPL 0x07u    /* oversampling */
#define PL455_REG_ADDR 0x0Au        /* device address (auto-addressing writes it) */
#define PL455_REG_GROUP_ID 0x0Bu
#define PL455_REG_DEV_CTRL 0x0Cu    /* device control: auto-address, reset */
#define PL455_REG_NCHAN 0x0Du       /* cells connected (ADC UV/OV checks cells 1..NCHAN) */
#define PL455_REG_DEVCONFIG 0x0Eu   /* device configuration */
#define PL455_REG_PWRCONFIG 0x0Fu
#define PL455_REG_COMCONFIG 0x10u   /* 2 bytes: baud rate, interfaces enabled */
#define PL455_REG_TXHOLDOFF 0x12u
#define PL455_REG_CBCONFIG 0x13u    /* balancing configuration: balance time */
#define PL455_REG_CBENBL 0x14u      /* 2 bytes: balancing switch per cell (bit k-1 = cell k) */
#define PL455_REG_CTO 0x28u         /* communication timeout: the device supervises its link */
#define PL455_REG_STATUS 0x51u      /* device status */
#define PL455_REG_FAULT_SUM 0x52u   /* 2 bytes: fault summary; write 1s to clear groups */
#define PL455_REG_FAULT_UV 0x54u    /* 2 bytes: ADC under-voltage per cell */
#define PL455_REG_FAULT_OV 0x56u    /* 2 bytes: ADC over-voltage per cell */
#define PL455_REG_FAULT_AUX 0x58u   /* 2 bytes: AUX thresholds per input */
#define PL455_REG_FAULT_2UV 0x5Au   /* 2 bytes: comparator under-voltage per cell */
#define PL455_REG_FAULT_2OV 0x5Cu   /* 2 bytes: comparator over-voltage per cell */
#define PL455_REG_FAULT_COM 0x5Eu   /* 2 bytes: communication faults */
#define PL455_REG_FAULT_SYS 0x60u
#define PL455_REG_FAULT_DEV 0x61u   /* 2 bytes */
#define PL455_REG_FAULT_GPI 0x63u
#define PL455_REG_FO_CTRL 0x6Eu     /* 2 bytes: FAULT_SUM bits that drive the FAULT output */
#define PL455_REG_MAGIC1 0x82u      /* 4 bytes: first EEPROM key */
#define PL455_REG_COMP_UV 0x8Cu     /* comparator under-voltage threshold */
#define PL455_REG_COMP_OV 0x8Du     /* comparator over-voltage threshold */
#define PL455_REG_CELL_UV 0x8Eu     /* 2 bytes: ADC under-voltage threshold, cell code */
#define PL455_REG_CELL_OV 0x90u     /* 2 bytes: ADC over-voltage threshold, cell code */
#define PL455_REG_AUX0_UV 0x92u     /* 2 bytes each: AUXn_UV at 0x92 + 4n, AUXn_OV at 0x94 + 4n */
#define PL455_REG_AUX_UV(n) ((uint8_t)(0x92u + 4u * (n)))
#define PL455_REG_AUX_OV(n) ((uint8_t)(0x94u + 4u * (n)))
#define PL455_REG_EE_BURN 0xFAu     /* EEPROM write: refused unless MAGIC1/MAGIC2 hold the keys */
#define PL455_REG_MAGIC2 0xFCu      /* 4 bytes: second EEPROM key */
#define PL455_REG_COUNT 256u

/* ---- CMD ---- */
#define PL455_CMD_SAMPLE 0x00u      /* sample CHANNELS; a request with response sends the results */
#define PL455_CMD_SEND_HELD 0x01u   /* [model] send the held results of the last sample, no new sample */

/* ---- CHANNELS (32 bits): the sample reply lists the selected channels from the
 * highest bit down, 2 bytes each, big-endian ---- */
#define PL455_CH_CELL(k) ((uint32_t)1u << (15u + (k))) /* cell k = 1..16 */
#define PL455_CH_CELLS(n) ((uint32_t)(((1ul << (n)) - 1ul) << 16)) /* cells 1..n */
#define PL455_AUX_INPUTS 8u                           /* AUX0..AUX7 */
#define PL455_CH_AUX(n) ((uint32_t)1u << (8u + (n)))   /* AUX input n = 0..7 */
#define PL455_CH_DIE_TEMP ((uint32_t)1u << 7)          /* [model] die temperature */
#define PL455_CH_MODULE ((uint32_t)1u << 6)            /* [model] module voltage */

/* ---- OVERSMPL: bits 2:0 = log2(samples averaged per channel), 0..5 ---- */
#define PL455_OVERSMPL_LOG2_MASK 0x07u
#define PL455_OVERSMPL_MAX_LOG2 5u

/* ---- DEV_CTRL ---- */
#define PL455_DEV_CTRL_AUTO_ADDRESS 0x08u /* enter auto-address mode (broadcast) */
#define PL455_DEV_CTRL_SHUTDOWN 0x40u
#define PL455_DEV_CTRL_RESET 0x80u        /* [model] reload the EEPROM, forget the address */

/* ---- DEVCONFIG ---- */
#define PL455_DEVCONFIG_ADDR_SEL 0x10u    /* address from the ADDR register (auto-addressing) */
#define PL455_DEVCONFIG_COMP_ENA 0x02u    /* [model] secondary comparators (cells, AUX) running */

/* ---- COMCONFIG: bits 15:12 baud rate, interfaces in the low byte ---- */
#define PL455_COMCONFIG_BAUD_SHIFT 12u    /* 0 = 125k, 1 = 250k, 2 = 500k, 3 = 1M */
#define PL455_COMCONFIG_UART_EN 0x0080u
#define PL455_COMCONFIG_COMM_HIGH 0x0040u
#define PL455_COMCONFIG_COMM_LOW 0x0020u
#define PL455_COMCONFIG_FAULT_HIGH 0x0010u
#define PL455_COMCONFIG_FAULT_LOW 0x0008u

/* ---- CBCONFIG: bits 6:4 balance time code; the device clears CBENBL when it expires ---- */
#define PL455_CBCONFIG_TIME_SHIFT 4u
#define PL455_CBCONFIG_TIME_MASK 0x70u
#define PL455_BALANCE_TIME_CODES 8u
/* [model] seconds per code: 0 = balancing stopped */
#define PL455_BALANCE_TIME_S_INIT {0u, 1u, 60u, 120u, 300u, 600u, 1200u, 1800u}

/* ---- CTO: bits 2:0 fault timer code. A device that hears no valid frame for that long
 * sets FAULT_SYS.CTO (and with FAULT_SUM.SYS in FO_CTRL, its FAULT output): the IC
 * notices a dead MCU or a cut link by itself. Code 0 (the power-up value) is off. ---- */
#define PL455_CTO_FAULT_MASK 0x07u
#define PL455_CTO_FAULT_CODES 8u
/* [model] milliseconds per code */
#define PL455_CTO_FAULT_MS_INIT {0ul, 100ul, 2000ul, 10000ul, 60000ul, 600000ul, 1800000ul, 7200000ul}

/* ---- STATUS ---- */
#define PL455_STATUS_DRDY 0x01u           /* [model] the last sample's results are ready */
#define PL455_STATUS_AUTO_ADDR 0x80u      /* [model] in auto-address mode, no address yet */

/* ---- FAULT_SUM (write 1 to a bit: clear that group's latched faults whose condition is gone) ---- */
#define PL455_FAULT_SUM_UV 0x8000u        /* ADC under-voltage (FAULT_UV) */
#define PL455_FAULT_SUM_OV 0x4000u        /* ADC over-voltage (FAULT_OV) */
#define PL455_FAULT_SUM_AUXUV 0x2000u     /* AUX below AUXn_UV: an NTC over temperature */
#define PL455_FAULT_SUM_AUXOV 0x1000u     /* AUX above AUXn_OV: an NTC cold or open */
#define PL455_FAULT_SUM_CMPUV 0x0800u     /* comparator under-voltage (FAULT_2UV) */
#define PL455_FAULT_SUM_CMPOV 0x0400u     /* comparator over-voltage (FAULT_2OV) */
#define PL455_FAULT_SUM_COMM 0x0200u
#define PL455_FAULT_SUM_SYS 0x0100u
#define PL455_FAULT_SUM_CHIP 0x0080u
#define PL455_FAULT_SUM_GPI 0x0040u
#define PL455_FAULT_SUM_ALL 0xFFC0u

/* FAULT_AUX: bit n = AUXn under its UV threshold, bit 8 + n = AUXn over its OV threshold [model] */
#define PL455_FAULT_AUX_UV(n) ((uint16_t)(1u << (n)))
#define PL455_FAULT_AUX_OV(n) ((uint16_t)(1u << (8u + (n))))
/* FAULT_SYS */
#define PL455_FAULT_SYS_CTO 0x01u         /* [model] communication timeout expired */
/* FAULT_COM */
#define PL455_FAULT_COM_UART_CRC 0x0001u  /* [model] a command frame failed its CRC and was dropped */

/* ---- thresholds and scalings ---- */
#define PL455_CODE_FULL_SCALE 65535u
#define PL455_CELL_FULL_SCALE_MV 5000.0f     /* cell V = code * 5 / 65535 */
#define PL455_MODULE_FULL_SCALE_MV 100000.0f /* module V = code * 100 / 65535 */
#define PL455_DIE_TEMP_DC_PER_CODE 1         /* [model] die temperature: signed 0.1 degC */
/* COMP_UV / COMP_OV: threshold in bits 7:1, 25 mV steps from a base */
#define PL455_COMP_SHIFT 1u
#define PL455_COMP_STEP_MV 25u
#define PL455_COMP_UV_BASE_MV 700u   /* 0.700 .. 3.875 V */
#define PL455_COMP_OV_BASE_MV 2000u  /* 2.000 .. 5.175 V */
#define PL455_COMP_MAX_STEPS 127u

/* ---- EEPROM keys and burn ---- */
#define PL455_MAGIC1_KEY 0x8C2DB494ul /* [model] stand-in values for the datasheet's keys */
#define PL455_MAGIC2_KEY 0xA54B2C53ul
#define PL455_EE_BURN_GO 0x01u

/* ---- timing ---- */
#define PL455_SAMPLE_US_PER_CHANNEL 100u  /* per channel and per oversample */
#define PL455_RESPONSE_TIMEOUT_US 1000u   /* [model] the MCU gives up on a reply after this */

#endif /* PACKSIM_BQ76PL455A_REGS_H */
