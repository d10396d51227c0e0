/* SPDX-License-Identifier: MIT */
/** @file The board support the firmware example and tests use on QEMU's mps2-an500: SysTick,
 * a virtual-instruction clock, and ending a run under semihosting. Plain C, so that firmware in
 * C can use it too. Port it by replacing startup.c's memory set-up and these few registers. */
#ifndef CMMCOMP_FIRMWARE_BOARD_H
#define CMMCOMP_FIRMWARE_BOARD_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Core clock of the AN500 image (QEMU's mps2 sysclk): SysTick counts at this rate. */
#define BOARD_CORE_CLOCK_HZ 25000000u

/** Starts SysTick on the core clock with `reload` + 1 cycles per period; with `interrupt`
 * non-zero it calls board_systick_handler() every period. */
void board_systick_start(uint32_t reload, int interrupt);
/** Stops SysTick. */
void board_systick_stop(void);
/** The SysTick down-counter (24 bits). */
uint32_t board_systick_value(void);
/** Called from the SysTick interrupt; the image defines it (a weak empty default exists). */
void board_systick_handler(void);

/** Masks and unmasks interrupts (PRIMASK). */
void board_irq_disable(void);
void board_irq_enable(void);

/** Ends the run: prints nothing, reports `code` to the host through semihosting (QEMU exits
 * with it), never returns. */
void board_exit(int code) __attribute__((noreturn));

#ifdef __cplusplus
}
#endif

#endif /* CMMCOMP_FIRMWARE_BOARD_H */
