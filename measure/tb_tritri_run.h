/* Running a triangle-test method over a set of pairs: the answers, and the
 * time per pair (shared by `tritri` and the triangle-test suites). */
#ifndef TB_TRITRI_RUN_H
#define TB_TRITRI_RUN_H

#include "collision/tb_pairs.h"
#include "collision/tb_tritri.h"

/* out[i] = the method's answer for pair i; returns how many were not 0/1. */
int tb_tritri_classify(const tb_tritri_method *m, const tb_pairset *s, unsigned char *out);
/* Times `repeat` passes over the set (tb_clock): cpu[k] = CPU ns/pair of
 * pass k (the calling thread's CPU time when one thread is in effect, else
 * the process's), wall[k] = wall ns/pair (wall may be NULL); returns the
 * median CPU ns/pair. */
double tb_tritri_time(const tb_tritri_method *m, const tb_pairset *s, int repeat, double *cpu,
                      double *wall);

#endif
