/* Monotonic wall-clock and CPU time. A measurement records both: CPU time
 * ranks single-threaded work on a busy machine (another process's time
 * slices do not count), wall time is what threads are for. */
#ifndef TB_TIMER_H
#define TB_TIMER_H

#include <stdint.h>

uint64_t tb_time_ns(void);     /* wall */
uint64_t tb_cpu_time_ns(void); /* the process's CPU time, every thread's */

/* A stopwatch over wall and CPU time. Its CPU clock is the calling
 * thread's when one thread works (tb_threads() == 1 at the start), else the
 * process's (every worker's time counts). */
typedef struct tb_clock {
  uint64_t wall, cpu;
  int process; /* 1: the CPU clock is the process's */
} tb_clock;
tb_clock tb_clock_start(void);
/* Milliseconds since c started: wall into *wall_ms, CPU into *cpu_ms
 * (either may be NULL). */
void tb_clock_ms(const tb_clock *c, double *wall_ms, double *cpu_ms);

#endif
