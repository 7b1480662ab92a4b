/* Worker threads (see tb_threads.h): a thin layer over OpenMP so that the
 * rest of the code does not depend on whether it was built with it.
 *
 * Placement. A step of the position-based models passes a barrier per
 * colour (about 240 per step). Unplaced, Linux often starts libgomp's
 * worker on the CPU of the thread that created it and leaves the two
 * there, taking turns: every barrier then waits for a time slice, and the
 * same run takes 3x as long one time in three (liver-drop, 2 threads: 0.14
 * or 0.42 ms per step). So when more than one thread is asked for, no more
 * than the CPUs this process may use, and the user has not placed them
 * (OMP_PROC_BIND, OMP_PLACES, GOMP_CPU_AFFINITY), thread i is pinned to the
 * i-th of those CPUs; back to one thread, the caller gets its own CPU set
 * back. */
#define _GNU_SOURCE
#include "tb_threads.h"

#include <stdlib.h>
#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#include <pthread.h>
#include <sched.h>
#endif

int tb_threads_cores(void) {
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (int)n : 1;
}

#ifdef _OPENMP
static int have_mask;    /* the caller's CPU set was saved */
static cpu_set_t caller; /* the CPU set the process started with */

static int user_placed(void) {
  return getenv("OMP_PROC_BIND") || getenv("OMP_PLACES") || getenv("GOMP_CPU_AFFINITY");
}

/* Pins thread i of n to the i-th CPU of the saved set (see the head). */
static void place(int n) {
  if (!have_mask) {
    if (sched_getaffinity(0, sizeof caller, &caller)) return;
    have_mask = 1;
  }
  if (n <= 1 || n > CPU_COUNT(&caller)) {
    pthread_setaffinity_np(pthread_self(), sizeof caller, &caller);
    return;
  }
  int cpu[CPU_SETSIZE], ncpu = 0;
  for (int c = 0; c < CPU_SETSIZE; c++)
    if (CPU_ISSET(c, &caller)) cpu[ncpu++] = c;
#pragma omp parallel num_threads(n)
  {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu[omp_get_thread_num()], &one);
    pthread_setaffinity_np(pthread_self(), sizeof one, &one);
  }
}
#endif

int tb_threads_set(int n) {
  if (n <= 0) n = tb_threads_cores();
#ifdef _OPENMP
  omp_set_num_threads(n);
  if (!user_placed()) place(n);
#else
  n = 1;
#endif
  return n;
}

int tb_threads(void) {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}
