/* counter.c - the mps2 board's free-running FPGA counter (FPGAIO COUNTER,
 * 25 MHz). Under QEMU with `-icount shift=0` the virtual clock advances one
 * nanosecond per guest instruction, so the counter reads instructions / 40:
 * ls_m4_instructions() turns it into an instruction count (resolution 40). */
#include "ls_m4.h"

#define LS_M4_FPGAIO_COUNTER ((volatile const uint32_t *)0x40028018u)

uint32_t ls_m4_counter(void) { return *LS_M4_FPGAIO_COUNTER; }

uint64_t ls_m4_instructions(uint32_t since)
{
    return (uint64_t)(uint32_t)(ls_m4_counter() - since) * 40u;
}
