/* semihost.c - newlib system calls for the Cortex-M4 port over ARM
 * semihosting (QEMU: -semihosting-config enable=on,target=native).
 * stdout and stderr go to QEMU's stdout and stderr (":tt" opened for writing
 * and for appending); exit(status) ends QEMU with that status; the heap is
 * the RAM after .bss (sections.ld), used by newlib's stdio buffers only. */
#include <errno.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include "ls_m4.h"

#define SYS_OPEN 0x01
#define SYS_WRITE 0x05
#define SYS_READ 0x06
#define SYS_EXIT 0x18
#define SYS_EXIT_EXTENDED 0x20
#define ADP_STOPPED_APPLICATION_EXIT 0x20026

extern uint32_t __ls_m4_heap_start[], __ls_m4_heap_end[];

void ls_m4_semihost_report(const char *line);
void ls_m4_semihost_exit(int status);
int _write(int fd, const void *data, size_t bytes);
int _read(int fd, void *data, size_t bytes);
int _close(int fd);
int _fstat(int fd, struct stat *st);
int _isatty(int fd);
long _lseek(int fd, long offset, int whence);
void *_sbrk(ptrdiff_t increment);
void _exit(int status);
int _kill(int pid, int sig);
int _getpid(void);

/* One semihosting call: operation in r0, parameter block in r1, result in r0. */
static int32_t semihost(int32_t op, const void *block)
{
    register int32_t r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = block;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

/* Semihosting handles of the host's stdout (":tt", mode "w") and stderr
 * (":tt", mode "a"), opened on first use; -1 before. Port state, not library
 * state: src/ has no writable globals. */
static int32_t tt_handle[2] = {-1, -1};

static int32_t console(int fd)
{
    int i = fd == 2 ? 1 : 0;
    if (tt_handle[i] < 0) {
        static const char name[] = ":tt";
        uint32_t block[3];
        block[0] = (uint32_t)(uintptr_t)name;
        block[1] = i == 0 ? 4u : 8u; /* "w" -> stdout, "a" -> stderr */
        block[2] = (uint32_t)(sizeof name - 1u);
        tt_handle[i] = semihost(SYS_OPEN, block);
    }
    return tt_handle[i];
}

int _write(int fd, const void *data, size_t bytes)
{
    uint32_t block[3];
    int32_t left;
    if (fd != 1 && fd != 2) {
        errno = EBADF;
        return -1;
    }
    block[0] = (uint32_t)console(fd);
    block[1] = (uint32_t)(uintptr_t)data;
    block[2] = (uint32_t)bytes;
    left = semihost(SYS_WRITE, block); /* bytes NOT written */
    if (left < 0 || (size_t)left > bytes) {
        errno = EIO;
        return -1;
    }
    return (int)(bytes - (size_t)left);
}

void ls_m4_semihost_report(const char *line)
{
    (void)_write(2, line, strlen(line));
}

int _read(int fd, void *data, size_t bytes)
{
    (void)fd;
    (void)data;
    (void)bytes;
    return 0; /* no input: end of file */
}

int _close(int fd)
{
    (void)fd;
    return 0;
}

int _fstat(int fd, struct stat *st)
{
    (void)fd;
    memset(st, 0, sizeof *st);
    st->st_mode = S_IFCHR; /* a terminal: stdout is line-buffered */
    return 0;
}

int _isatty(int fd)
{
    return fd >= 0 && fd <= 2;
}

long _lseek(int fd, long offset, int whence)
{
    (void)fd;
    (void)offset;
    (void)whence;
    errno = ESPIPE;
    return -1;
}

static uintptr_t heap_top;

void *_sbrk(ptrdiff_t increment)
{
    uintptr_t old;
    if (heap_top == 0) heap_top = (uintptr_t)__ls_m4_heap_start;
    old = heap_top;
    if (increment < 0 || (uintptr_t)increment > (uintptr_t)__ls_m4_heap_end - old) {
        errno = ENOMEM;
        return (void *)-1;
    }
    heap_top = old + (uintptr_t)increment;
    return (void *)old;
}

size_t ls_m4_heap_used(void)
{
    return heap_top == 0 ? 0u : (size_t)(heap_top - (uintptr_t)__ls_m4_heap_start);
}

size_t ls_m4_heap_size(void)
{
    return (size_t)((uintptr_t)__ls_m4_heap_end - (uintptr_t)__ls_m4_heap_start);
}

void ls_m4_semihost_exit(int status)
{
    uint32_t block[2];
    block[0] = ADP_STOPPED_APPLICATION_EXIT;
    block[1] = (uint32_t)status;
    (void)semihost(SYS_EXIT_EXTENDED, block);
    /* Hosts without SYS_EXIT_EXTENDED: plain exit, success or failure only. */
    (void)semihost(SYS_EXIT, (const void *)(uintptr_t)(status == 0 ? ADP_STOPPED_APPLICATION_EXIT : 0x20023));
}

void _exit(int status)
{
    ls_m4_semihost_exit(status);
    for (;;) {
    }
}

int _kill(int pid, int sig)
{
    (void)pid;
    (void)sig;
    errno = EINVAL;
    return -1;
}

int _getpid(void)
{
    return 1;
}
