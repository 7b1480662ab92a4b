/* Running a triangle-test method over a set of pairs (suites/tb_tritri_run.h):
 * its answers, and its time per pair over repeated passes. */
#include <stdint.h>

#include "tb_tritri_run.h"
#include "core/tb_timer.h"
#include "report/tb_results.h"

/* Classifies every pair; returns the number of invalid answers (not 0/1). */
int tb_tritri_classify(const tb_tritri_method *m, const tb_pairset *s, unsigned char *out) {
  int bad = 0;
  for (int i = 0; i < s->n; i++) {
    int r = m->test(s->pairs[i].p, s->pairs[i].q);
    bad += r != 0 && r != 1;
    out[i] = (unsigned char)r;
  }
  return bad;
}

/* Median ns per pair over `repeat` passes over the whole set. */
double tb_tritri_time(const tb_tritri_method *m, const tb_pairset *s, int repeat, double *samples) {
  volatile int sink = 0;
  for (int k = 0; k < repeat; k++) {
    uint64_t t0 = tb_time_ns();
    int acc = 0;
    for (int i = 0; i < s->n; i++) acc += m->test(s->pairs[i].p, s->pairs[i].q);
    samples[k] = (double)(tb_time_ns() - t0) / (s->n ? s->n : 1);
    sink += acc;
  }
  (void)sink;
  return tb_stats_of(samples, repeat).median;
}
