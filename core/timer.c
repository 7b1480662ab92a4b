/* Monotonic wall-clock, thread and process CPU time (POSIX clock_gettime). */
#define _POSIX_C_SOURCE 200809L
#include "tb_timer.h"

#include <time.h>

#include "tb_threads.h"

static uint64_t clock_ns(clockid_t id) {
  struct timespec ts;
  clock_gettime(id, &ts);
  return (uint64_t)ts.tv_sec * 1000000000ull + (uint64_t)ts.tv_nsec;
}

uint64_t tb_time_ns(void) { return clock_ns(CLOCK_MONOTONIC); }
uint64_t tb_cpu_time_ns(void) { return clock_ns(CLOCK_PROCESS_CPUTIME_ID); }

/* The CPU reads are inside the wall reads, so that on one thread the CPU
 * time of a stretch is never above its wall time. */
tb_clock tb_clock_start(void) {
  tb_clock c;
  c.process = tb_threads() > 1;
  c.wall = clock_ns(CLOCK_MONOTONIC);
  c.cpu = clock_ns(c.process ? CLOCK_PROCESS_CPUTIME_ID : CLOCK_THREAD_CPUTIME_ID);
  return c;
}

void tb_clock_ms(const tb_clock *c, double *wall_ms, double *cpu_ms) {
  uint64_t p = clock_ns(c->process ? CLOCK_PROCESS_CPUTIME_ID : CLOCK_THREAD_CPUTIME_ID);
  uint64_t w = clock_ns(CLOCK_MONOTONIC);
  if (wall_ms) *wall_ms = (double)(w - c->wall) * 1e-6;
  if (cpu_ms) *cpu_ms = (double)(p - c->cpu) * 1e-6;
}
