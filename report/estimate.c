/* Estimates with intervals, and the verdicts made from them
 * (report/tb_results.h). The interval of a median is distribution-free:
 * order statistics of the sorted samples, j-th and (n+1-j)-th (1-based),
 * j the largest whose binomial tail P(Bin(n, 1/2) < j) is at most 2.5%
 * (e.g. Conover, Practical Nonparametric Statistics, 3rd ed., §3.2); it
 * covers the true median with probability >= 95% whatever the distribution
 * of the samples. A ratio is the median of the paired ratios of
 * interleaved repetitions, so a machine that slows down over a run slows
 * both sides of every pair alike. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_results.h"

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The largest j (1 <= j <= n/2) with P(Bin(n, 1/2) < j) <= 0.025, or 0. */
static int order_rank(int n) {
  double cdf = 0;
  int j = 0;
  for (int i = 0; 2 * i < n; i++) { /* cdf = P(X <= i) */
    cdf += exp(lgamma(n + 1.0) - lgamma(i + 1.0) - lgamma(n - i + 1.0) - n * log(2.0));
    if (cdf > 0.025) break;
    j = i + 1; /* P(X < i + 1) <= 0.025 */
  }
  return j;
}

/* Sorted finite copy of x; returns how many. */
static int finite_sorted(const double *x, int n, double **out) {
  *out = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  int m = 0;
  for (int i = 0; *out && i < n; i++)
    if (isfinite(x[i])) (*out)[m++] = x[i];
  if (*out) qsort(*out, (size_t)m, sizeof(double), cmp);
  return *out ? m : 0;
}

static tb_est median_of_sorted(const double *s, int m) {
  tb_est e = {NAN, NAN, NAN, m};
  if (m < 1) return e;
  e.value = m % 2 ? s[m / 2] : 0.5 * (s[m / 2 - 1] + s[m / 2]);
  int j = order_rank(m);
  e.lo = j ? s[j - 1] : s[0];
  e.hi = j ? s[m - j] : s[m - 1];
  return e;
}

tb_est tb_median_est(const double *x, int n) {
  double *s;
  int m = finite_sorted(x, n, &s);
  tb_est e = median_of_sorted(s, m);
  free(s);
  return e;
}

tb_est tb_ratio_est(const double *a, const double *b, int n) {
  double *r = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  int m = 0;
  for (int i = 0; r && i < n; i++)
    if (isfinite(a[i]) && isfinite(b[i]) && a[i] > 0 && b[i] > 0) r[m++] = a[i] / b[i];
  tb_est e = tb_median_est(r, m);
  free(r);
  return e;
}

void tb_table_est(tb_table *t, tb_est e, const char *fmt, const char *unit) {
  char f[64];
  snprintf(f, sizeof f, "%s%s (%s-%s)", fmt, unit, fmt, fmt);
  if (isfinite(e.value))
    tb_table_numf(t, e.value, f, e.value, e.lo, e.hi);
  else
    tb_table_cell(t, "-");
}

int tb_verdict(tb_est e, double goal, int at_least) {
  if (e.n < TB_EST_MIN || !isfinite(e.lo) || !isfinite(e.hi)) return TB_NOISE;
  if (at_least ? e.lo >= goal : e.hi <= goal) return TB_MET;
  if (at_least ? e.hi < goal : e.lo > goal) return TB_NOT_MET;
  return TB_NOISE;
}

const char *tb_verdict_text(tb_est e, double goal, int at_least, char *buf, size_t cap) {
  int v = tb_verdict(e, goal, at_least);
  if (v == TB_MET)
    snprintf(buf, cap, "met");
  else if (v == TB_NOT_MET)
    snprintf(buf, cap, "not met");
  else if (e.n < TB_EST_MIN)
    snprintf(buf, cap, "inconclusive (%d repetition%s: a 95%% interval needs %d)", e.n,
             e.n == 1 ? "" : "s", TB_EST_MIN);
  else
    snprintf(buf, cap, "inconclusive (noise: the 95%% interval %.3g-%.3g holds %.3g)", e.lo, e.hi,
             goal);
  return buf;
}
