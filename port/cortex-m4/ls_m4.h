/* ls_m4.h - the bare-metal Cortex-M4 port: QEMU's mps2-an386 board with
 * semihosting (the files beside this one: startup.c, semihost.c, full.ld,
 * mcu.ld, sections.ld).
 *
 * What the port gives a program: a reset handler that sets up C (FPU on,
 * .data copied, .bss zeroed), paints the free stack and calls main(); stdout
 * and stderr through semihosting (printf works, newlib); a heap for newlib's
 * stdio only (the library never allocates); exit(status) becomes QEMU's exit
 * status; any fault exits with status 99. After main returns, the reset
 * handler writes one line to stderr:
 *     ls_m4: stack high-water H of S bytes, heap U bytes
 * where H is the deepest stack use since reset, found by painting.
 *
 * Stack measurement by painting: every free word of the stack is filled with
 * a pattern; the deepest word that no longer holds it is the high-water
 * mark. To measure one call, take a mark right before it:
 *     uintptr_t m = ls_m4_stack_paint();   // repaint everything below here
 *     run_job();
 *     size_t used = ls_m4_stack_used_since(m);
 */
#ifndef LS_M4_H
#define LS_M4_H

#include <stddef.h>
#include <stdint.h>

/* Bytes reserved for the stack by the linker script (64 KiB in full.ld,
 * 8 KiB in mcu.ld). */
size_t ls_m4_stack_size(void);

/* Deepest stack use since reset, in bytes from the top of the stack. */
size_t ls_m4_stack_high_water(void);

/* Paints the free stack below the caller's frame and returns the current
 * stack pointer: the mark for ls_m4_stack_used_since(). */
uintptr_t ls_m4_stack_paint(void);

/* Deepest stack use below `mark` since the ls_m4_stack_paint() that returned
 * it, in bytes (0 if nothing below the mark was touched). */
size_t ls_m4_stack_used_since(uintptr_t mark);

/* Bytes the heap (newlib's stdio buffers) has grown to, and its capacity. */
size_t ls_m4_heap_used(void);
size_t ls_m4_heap_size(void);

/* RAM in the linker script's RAM region, in bytes. */
size_t ls_m4_ram_size(void);

/* The board's free-running 25 MHz counter (FPGAIO COUNTER; wraps after
 * 2^32 ticks). Under QEMU run with `-icount shift=0` (one instruction per
 * virtual nanosecond), ls_m4_instructions(start) = (counter - start) x 40 is
 * the number of instructions executed since `start` was read, to within 40
 * (tests/tools/run_m4.sh sets LS_M4_ICOUNT=1 for it). Without -icount the
 * counter follows the host's clock and the figure means nothing. */
uint32_t ls_m4_counter(void);
uint64_t ls_m4_instructions(uint32_t since);

#endif /* LS_M4_H */
