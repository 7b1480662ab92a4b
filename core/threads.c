/* Worker threads (see tb_threads.h): a thin layer over OpenMP so that the
 * rest of the code does not depend on whether it was built with it. */
#include "tb_threads.h"

#include <unistd.h>
#ifdef _OPENMP
#include <omp.h>
#endif

int tb_threads_cores(void) {
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (int)n : 1;
}

int tb_threads_set(int n) {
  if (n <= 0) n = tb_threads_cores();
#ifdef _OPENMP
  omp_set_num_threads(n);
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
