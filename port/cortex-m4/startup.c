/* startup.c - vector table and reset handler of the Cortex-M4 port (QEMU
 * mps2-an386). See ls_m4.h for what a program gets; the memory layout is in
 * sections.ld. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include "ls_m4.h"

/* Linker-script symbols (their addresses are what matters). */
extern uint32_t __ls_m4_stack_bottom[], __ls_m4_stack_top[];
extern uint32_t __ls_m4_data_start[], __ls_m4_data_end[], __ls_m4_data_load[];
extern uint32_t __ls_m4_bss_start[], __ls_m4_bss_end[];
extern uint32_t __ls_m4_heap_start[], __ls_m4_heap_end[];

extern int main(void);
extern void __libc_init_array(void);
void ls_m4_reset(void);
void ls_m4_fault(void);
void ls_m4_semihost_report(const char *line); /* semihost.c: to stderr */
void ls_m4_semihost_exit(int status);          /* semihost.c */
void _init(void);
void _fini(void);

#define STACK_PAINT 0xC5A5C5A5u

/* The stack pointer, read without touching the stack. */
static uintptr_t current_sp(void)
{
    uintptr_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

/* Fills [bottom, below) with the paint pattern. The loop keeps its state in
 * registers, so it does not overwrite its own frame. */
static void paint(uint32_t *bottom, uintptr_t below)
{
    volatile uint32_t *p = bottom;
    while ((uintptr_t)p + 4u <= below) *p++ = STACK_PAINT;
}

/* Address of the deepest stack word that lost its paint (the top of the stack
 * when none did). */
static uintptr_t deepest_touched(void)
{
    const volatile uint32_t *p = __ls_m4_stack_bottom;
    while (p < __ls_m4_stack_top && *p == STACK_PAINT) p++;
    return (uintptr_t)p;
}

size_t ls_m4_stack_size(void)
{
    return (size_t)((uintptr_t)__ls_m4_stack_top - (uintptr_t)__ls_m4_stack_bottom);
}

size_t ls_m4_stack_high_water(void)
{
    return (size_t)((uintptr_t)__ls_m4_stack_top - deepest_touched());
}

uintptr_t ls_m4_stack_paint(void)
{
    uintptr_t sp = current_sp();
    paint(__ls_m4_stack_bottom, sp - 32u); /* a margin for paint()'s own frame */
    return sp;
}

size_t ls_m4_stack_used_since(uintptr_t mark)
{
    uintptr_t deepest = deepest_touched();
    return deepest < mark ? (size_t)(mark - deepest) : 0u;
}

size_t ls_m4_ram_size(void)
{
    return (size_t)((uintptr_t)__ls_m4_heap_end - (uintptr_t)__ls_m4_stack_bottom);
}

static void report(int status)
{
    char line[160];
    snprintf(line, sizeof line,
             "ls_m4: stack high-water %lu of %lu bytes, heap %lu of %lu bytes, exit %d\n",
             (unsigned long)ls_m4_stack_high_water(), (unsigned long)ls_m4_stack_size(),
             (unsigned long)ls_m4_heap_used(), (unsigned long)ls_m4_heap_size(), status);
    ls_m4_semihost_report(line);
}

void ls_m4_reset(void)
{
    const uint32_t *src = __ls_m4_data_load;
    uint32_t *dst;
    int status;
#if defined(__ARM_FP)
    /* CPACR: full access to CP10 and CP11 (the FPU) before any FP instruction. */
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
#endif
    for (dst = __ls_m4_data_start; dst < __ls_m4_data_end;) *dst++ = *src++;
    for (dst = __ls_m4_bss_start; dst < __ls_m4_bss_end;) *dst++ = 0;
    paint(__ls_m4_stack_bottom, current_sp() - 64u);
    __libc_init_array();
    status = main();
    fflush(stdout);
    report(status);
    exit(status);
}

void ls_m4_fault(void)
{
    ls_m4_semihost_report("ls_m4: fault (HardFault/MemManage/BusFault/UsageFault), exit 99\n");
    ls_m4_semihost_exit(99);
    for (;;) {
    }
}

static void unexpected_interrupt(void)
{
    ls_m4_semihost_report("ls_m4: unexpected interrupt, exit 98\n");
    ls_m4_semihost_exit(98);
    for (;;) {
    }
}

/* The vector table: initial stack pointer, then the handlers. The stack
 * pointer goes in as a function pointer so that the table is one type. */
typedef void (*ls_m4_vector)(void);
__attribute__((section(".vectors"), used)) static const ls_m4_vector vectors[48] = {
    (ls_m4_vector)(uintptr_t)__ls_m4_stack_top,
    ls_m4_reset,
    unexpected_interrupt, /* NMI */
    ls_m4_fault,          /* HardFault */
    ls_m4_fault,          /* MemManage */
    ls_m4_fault,          /* BusFault */
    ls_m4_fault,          /* UsageFault */
    0, 0, 0, 0,
    unexpected_interrupt, /* SVCall */
    unexpected_interrupt, /* DebugMonitor */
    0,
    unexpected_interrupt, /* PendSV */
    unexpected_interrupt, /* SysTick */
    /* external interrupts 0..31: none is enabled */
    unexpected_interrupt, unexpected_interrupt, unexpected_interrupt, unexpected_interrupt,
    unexpected_interrupt, unexpected_interrupt, unexpected_interrupt, unexpected_interrupt,
    unexpected_interrupt, unexpected_interrupt, unexpected_interrupt, unexpected_interrupt,
    unexpected_interrupt, unexpected_interrupt, unexpected_interrupt, unexpected_interrupt,
    unexpected_interrupt, unexpected_interrupt, unexpected_interrupt, unexpected_interrupt,
    unexpected_interrupt, unexpected_interrupt, unexpected_interrupt, unexpected_interrupt,
    unexpected_interrupt, unexpected_interrupt, unexpected_interrupt, unexpected_interrupt,
    unexpected_interrupt, unexpected_interrupt, unexpected_interrupt, unexpected_interrupt,
};

/* newlib's __libc_init_array and exit() call these; crti.o is not linked
 * (-nostartfiles). */
void _init(void)
{
}

void _fini(void)
{
}
