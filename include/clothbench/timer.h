/* The wall clock every timing in clothbench is read from. */
#ifndef CB_TIMER_H
#define CB_TIMER_H

/* Monotonic wall clock in milliseconds (CLOCK_MONOTONIC). */
double cb_now_ms(void);

#endif
