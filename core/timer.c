/* Monotonic wall-clock and process CPU time (POSIX clock_gettime). */
#define _POSIX_C_SOURCE 200809L
#include "tb_timer.h"

#include <time.h>

static uint64_t clock_ns(clockid_t id) {
  struct timespec ts;
  clock_gettime(id, &ts);
  return (uint64_t)ts.tv_sec * 1000000000ull + (uint64_t)ts.tv_nsec;
}

uint64_t tb_time_ns(void) { return clock_ns(CLOCK_MONOTONIC); }
uint64_t tb_cpu_time_ns(void) { return clock_ns(CLOCK_PROCESS_CPUTIME_ID); }
