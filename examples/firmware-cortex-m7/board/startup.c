/* SPDX-License-Identifier: MIT */
/** @file Reset handler, vector table and fault handler for QEMU's mps2-an500 (Cortex-M7), and the
 * board functions of board.h. Output goes through semihosting (newlib's librdimon): printf
 * reaches QEMU's stdout when it runs with -semihosting-config enable=on,target=native. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "board.h"

extern uint32_t __data_start__, __data_end__, __data_load__, __bss_start__, __bss_end__;
extern uint32_t __stack_top__;
extern void __libc_init_array(void);
extern void initialise_monitor_handles(void);
extern int main(void);

#define REG32(address) (*(volatile uint32_t*)(address))
#define SCB_CPACR REG32(0xE000ED88u)
#define SYST_CSR REG32(0xE000E010u)
#define SYST_RVR REG32(0xE000E014u)
#define SYST_CVR REG32(0xE000E018u)

void Reset_Handler(void) __attribute__((noreturn));
void Default_Handler(void);
void HardFault_Handler(void);
void SysTick_Handler(void);

/* -nostartfiles drops crti.o/crtn.o, which define these; newlib's __libc_init_array calls them
 * around the .init_array constructors, which are all an image needs. */
void _init(void);
void _fini(void);
void _init(void) {}
void _fini(void) {}

void Reset_Handler(void) {
  /* The FPU first (CP10, CP11 full access): the C code below may already use its registers. */
  SCB_CPACR |= 0xFu << 20;
  __asm volatile("dsb\n isb" ::: "memory");
  for (volatile uint32_t *src = &__data_load__, *dst = &__data_start__; dst < &__data_end__;) {
    *dst++ = *src++;
  }
  for (volatile uint32_t* dst = &__bss_start__; dst < &__bss_end__;) *dst++ = 0;
  initialise_monitor_handles();
  __libc_init_array();
  board_exit(main());
}

/* A fault is a failed run, never a hang that only a test timeout would catch. */
void HardFault_Handler(void) {
  static const char message[] = "FAULT: HardFault\n";
  fwrite(message, 1, sizeof message - 1, stdout);
  fflush(stdout);
  board_exit(3);
}

void Default_Handler(void) {
  static const char message[] = "FAULT: unexpected exception\n";
  fwrite(message, 1, sizeof message - 1, stdout);
  fflush(stdout);
  board_exit(4);
}

__attribute__((weak)) void board_systick_handler(void) {}
void SysTick_Handler(void) { board_systick_handler(); }

/* Cortex-M vector table: initial stack pointer, then the 15 system exceptions. The AN500's
 * external interrupts are not used here (they would follow, up to the device's count). A union,
 * because the first entry is an address of data and the others are handlers. */
typedef union {
  uint32_t* stack;
  void (*handler)(void);
} vector_entry;

__attribute__((section(".vectors"), used)) static const vector_entry vector_table[16] = {
    {.stack = &__stack_top__},
    {.handler = Reset_Handler},
    {.handler = Default_Handler},   /* NMI */
    {.handler = HardFault_Handler}, /* HardFault */
    {.handler = HardFault_Handler}, /* MemManage */
    {.handler = HardFault_Handler}, /* BusFault */
    {.handler = HardFault_Handler}, /* UsageFault */
    {.handler = 0},                 /* reserved */
    {.handler = 0},
    {.handler = 0},
    {.handler = 0},
    {.handler = Default_Handler}, /* SVCall */
    {.handler = Default_Handler}, /* DebugMonitor */
    {.handler = 0},               /* reserved */
    {.handler = Default_Handler}, /* PendSV */
    {.handler = SysTick_Handler},
};

void board_systick_start(uint32_t reload, int interrupt) {
  SYST_CSR = 0;
  SYST_RVR = reload & 0x00FFFFFFu;
  SYST_CVR = 0;
  /* CLKSOURCE = core clock, TICKINT as asked, ENABLE. */
  SYST_CSR = (1u << 2) | (interrupt ? (1u << 1) : 0u) | 1u;
}

void board_systick_stop(void) { SYST_CSR = 0; }

uint32_t board_systick_value(void) { return SYST_CVR & 0x00FFFFFFu; }

void board_irq_disable(void) { __asm volatile("cpsid i" ::: "memory"); }
void board_irq_enable(void) { __asm volatile("cpsie i" ::: "memory"); }

void board_exit(int code) {
  fflush(stdout);
  exit(code); /* librdimon: SYS_EXIT through semihosting */
  for (;;) {
  }
}
