/* Running a triangle-test method over a set of pairs (measure/tb_tritri_run.h):
 * its answers, and its time per pair over repeated passes. */
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

/* CPU and wall ns per pair of every pass over the whole set; the median CPU
 * figure. */
double tb_tritri_time(const tb_tritri_method *m, const tb_pairset *s, int repeat, double *cpu,
                      double *wall) {
  volatile int sink = 0;
  double per = 1e6 / (s->n ? s->n : 1); /* ms for the set -> ns per pair */
  for (int k = 0; k < repeat; k++) {
    tb_clock c = tb_clock_start();
    int acc = 0;
    for (int i = 0; i < s->n; i++) acc += m->test(s->pairs[i].p, s->pairs[i].q);
    double w, p;
    tb_clock_ms(&c, &w, &p);
    cpu[k] = p * per;
    if (wall) wall[k] = w * per;
    sink += acc;
  }
  (void)sink;
  return tb_stats_of(cpu, repeat).median;
}
