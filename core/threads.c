/* Worker threads (see tb_threads.h): a thin layer over OpenMP so that the
 * rest of the code does not depend on whether it was built with it, and the
 * thread pools of the libraries we call held to the same count.
 *
 * The pools read their settings once, when the libraries load, before main:
 *  - libgomp: OMP_THREAD_LIMIT caps every parallel region, CHOLMOD's too
 *    (its supernodal factorisation asks for 4 threads whatever we set);
 *    GOMP_SPINCOUNT bounds the busy wait at a barrier before the thread
 *    sleeps. On a quiet machine a short spin is what keeps a barrier cheap:
 *    a thread that sleeps is woken on an idle CPU, which a virtual machine
 *    takes tens of microseconds to bring back, at each of pbd-stvk's ~240
 *    barriers a step (2 threads on the liver: 10.4 ms a step passive, 1.5
 *    with 10000 spins). On a machine whose other processes keep the cores
 *    busy, spinning is what costs: the waiting thread burns the time slice
 *    the thread it waits for needs, and the scheduler favours the busy
 *    processes over it (2 threads beside two busy loops: 31 ms of CPU a step
 *    with 10000 spins, 1.5 passive, where a woken thread runs first). So the
 *    spin is 10000 when the load average at start leaves the cores free,
 *    and 0 (passive) when it does not.
 *  - OpenBLAS (pthreads): OPENBLAS_NUM_THREADS; its BLAS calls here are
 *    small (CHOLMOD's supernodes), one thread.
 * tb_threads_environment puts them in the environment and runs the program
 * again, once. Threads are not pinned to CPUs: on a shared machine a thread
 * pinned to a CPU another process uses holds up the whole team at every
 * barrier. Pinning is the user's (OMP_PROC_BIND, OMP_PLACES). */
#define _GNU_SOURCE
#include "tb_threads.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#define SPINCOUNT "10000"     /* a quiet machine's */
#define SPINCOUNT_BUSY "0"    /* a busy machine's: passive */
#define MARK "TB_THREADS_ENV" /* set once the environment is ours */

int tb_threads_cores(void) {
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (int)n : 1;
}

/* Sets name=value unless the user set name. */
static void put(const char *name, const char *value) {
  if (!getenv(name)) setenv(name, value, 1);
}

void tb_threads_environment(int n, char **argv) {
  char limit[16];
  if (n <= 0) n = tb_threads_cores();
  snprintf(limit, sizeof limit, "%d", n);
  const char *mark = getenv(MARK);
  if (mark && !strcmp(mark, limit)) return; /* the libraries loaded with it */
  setenv(MARK, limit, 1);
  setenv("OMP_THREAD_LIMIT", limit, 1);
  double load = 0;
  FILE *f = fopen("/proc/loadavg", "r");
  if (!f || fscanf(f, "%lf", &load) != 1) load = 0;
  if (f) fclose(f);
  int busy = load > tb_threads_cores() - 0.5; /* the others leave less than the cores */
  if (!getenv("OMP_WAIT_POLICY")) put("GOMP_SPINCOUNT", busy ? SPINCOUNT_BUSY : SPINCOUNT);
  put("OPENBLAS_NUM_THREADS", "1");
  execv("/proc/self/exe", argv);
  /* no /proc: go on with the pools as they are (the count still holds for
   * our own loops) */
}

static int automatic = 1; /* the count was not given: models choose (tb_model_step) */

/* One thread: no parallel region is active (max-active-levels 0), so the
 * libraries' regions with num_threads clauses (CHOLMOD's) run on the
 * calling thread too. */
int tb_threads_set(int n) {
  automatic = n <= 0;
  if (n <= 0) n = tb_threads_cores();
#ifdef _OPENMP
  int limit = omp_get_thread_limit();
  if (n > limit) n = limit;
  omp_set_num_threads(n);
  omp_set_max_active_levels(n > 1 ? 1 : 0);
#else
  n = 1;
#endif
  return n;
}

int tb_threads_auto(void) { return automatic; }
int tb_threads_setting(void) { return automatic ? 0 : tb_threads(); }

int tb_threads_serial_begin(void) {
#ifdef _OPENMP
  int was = omp_get_max_active_levels();
  omp_set_max_active_levels(0);
  return was;
#else
  return 0;
#endif
}

void tb_threads_serial_end(int was) {
#ifdef _OPENMP
  omp_set_max_active_levels(was);
#else
  (void)was;
#endif
}

int tb_threads(void) {
#ifdef _OPENMP
  int n = omp_get_max_threads(), limit = omp_get_thread_limit();
  return omp_get_max_active_levels() < 1 ? 1 : n < limit ? n : limit;
#else
  return 1;
#endif
}

int tb_thread_id(void) {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

int tb_threads_team(void) {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}
