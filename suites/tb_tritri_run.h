/* Running a triangle-test method over a set of pairs: the answers, and the
 * median time per pair (shared by `tritri` and the triangle-test suites). */
#ifndef TB_TRITRI_RUN_H
#define TB_TRITRI_RUN_H

#include "collision/tb_pairs.h"
#include "collision/tb_tritri.h"

/* out[i] = the method's answer for pair i; returns how many were not 0/1. */
int tb_tritri_classify(const tb_tritri_method *m, const tb_pairset *s, unsigned char *out);
/* Times `repeat` passes over the set: samples[k] = ns/pair of pass k;
 * returns the median. */
double tb_tritri_time(const tb_tritri_method *m, const tb_pairset *s, int repeat, double *samples);

#endif
