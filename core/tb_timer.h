/* Monotonic wall-clock and process CPU time in nanoseconds. */
#ifndef TB_TIMER_H
#define TB_TIMER_H

#include <stdint.h>

uint64_t tb_time_ns(void);
uint64_t tb_cpu_time_ns(void);

#endif
