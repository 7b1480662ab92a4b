/* `tissuebench advise`: from the measured points of `figure pareto`
 * (results/pareto/<scene>/points.csv), the cheapest model + resolution +
 * parameters whose error against the reference is within a tolerance (a
 * model no more than the scene needs), or the most accurate within a time
 * budget per step; with the evidence: every point within the tolerance by
 * cost, and the best points rejected; the choice itself is tb_advise_pick
 * (tested on synthetic tables). The points file is measure/tb_points.h;
 * its speeds are CPU time on one thread (steps/s, ms/step). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"
#include "core/tb_paths.h"
#include "measure/tb_points.h"

/* ---- the choice ---- */

int tb_advise_pick(const tb_point *p, int n, double tol, double budget_ms) {
  int best = -1;
  for (int k = 0; k < n; k++) {
    if (!tb_point_usable(&p[k])) continue;
    if (tol > 0 && !(p[k].rms_err <= tol)) continue;
    if (budget_ms > 0 && !(p[k].ms_step <= budget_ms)) continue;
    if (best < 0) {
      best = k;
      continue;
    }
    const tb_point *a = &p[k], *b = &p[best];
    int better = tol > 0 ? (a->steps_per_s > b->steps_per_s ||
                            (a->steps_per_s == b->steps_per_s && a->rms_err < b->rms_err))
                         : (a->rms_err < b->rms_err ||
                            (a->rms_err == b->rms_err && a->steps_per_s > b->steps_per_s));
    if (better) best = k;
  }
  return best;
}

/* ---- the command ---- */

static void print_row(const tb_point *p, const char *mark) {
  printf("%-2s %-10s %6d %6d  %-34s %10.0f %9.4f %9.3f%% %9.3f%%  %s\n", mark, p->model,
         p->resolution, p->nodes, p->params, p->steps_per_s, p->ms_step, 100 * p->rms_err,
         100 * p->max_err, p->state);
}

static void print_header(void) {
  printf("   %-10s %6s %6s  %-34s %10s %9s %10s %10s  %s\n", "model", "res", "nodes", "params",
         "steps/s", "ms/step", "rms err", "max err", "state");
}

/* Sort keys for the evidence lists. */
static const tb_point *sort_base;
static int by_cost(const void *a, const void *b) {
  const tb_point *p = &sort_base[*(const int *)a], *q = &sort_base[*(const int *)b];
  if (p->ms_step != q->ms_step) return p->ms_step < q->ms_step ? -1 : 1;
  return *(const int *)a - *(const int *)b;
}
static int by_error(const void *a, const void *b) {
  const tb_point *p = &sort_base[*(const int *)a], *q = &sort_base[*(const int *)b];
  if (p->rms_err != q->rms_err) return p->rms_err < q->rms_err ? -1 : 1;
  return *(const int *)a - *(const int *)b;
}

static int usage(const char *msg) {
  fprintf(stderr,
          "tissuebench advise: %s\n"
          "usage: tissuebench advise --scene NAME (--tol X | --budget-ms Y | both) "
          "[--points FILE] [--results DIR]\n",
          msg);
  return TB_EXIT_INPUT;
}

int tb_cmd_advise(int argc, char **argv) {
  const char *scene = NULL, *points = NULL, *results = tb_results_dir();
  double tol = 0, budget = 0;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (i + 1 >= argc) return usage("an option without its value (or unknown)");
    if (!strcmp(a, "--scene"))
      scene = argv[++i];
    else if (!strcmp(a, "--points"))
      points = argv[++i];
    else if (!strcmp(a, "--results"))
      results = argv[++i];
    else if (!strcmp(a, "--tol") || !strcmp(a, "--budget-ms")) {
      double v;
      if (tb_cli_parse_double(a, argv[++i], &v) || !(v > 0))
        return usage("--tol and --budget-ms take a number > 0");
      *(!strcmp(a, "--tol") ? &tol : &budget) = v;
    } else
      return usage("unknown option");
  }
  if (!scene && !points) return usage("--scene NAME (or --points FILE) is required");
  if (!(tol > 0) && !(budget > 0)) return usage("--tol X or --budget-ms Y is required");
  char path[1024];
  if (!points) {
    if (snprintf(path, sizeof path, "%s/pareto/%s/points.csv", results, scene) >= (int)sizeof path)
      return usage("path too long");
    points = path;
  }
  tb_point *p;
  int n;
  tb_error err;
  if (tb_points_read(points, &p, &n, &err)) {
    fprintf(stderr, "tissuebench advise: %s\n", err.msg);
    if (strstr(err.msg, "cannot read"))
      fprintf(stderr, "  (make the points with: tissuebench figure pareto --scene %s)\n",
              scene ? scene : "NAME");
    return TB_EXIT_INPUT;
  }
  int *idx = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1)), nusable = 0;
  if (!idx) return free(p), TB_EXIT_FAIL;
  for (int k = 0; k < n; k++) nusable += tb_point_usable(&p[k]);
  int pick = tb_advise_pick(p, n, tol, budget);
  printf("points: %s (%d, %d settled; speeds in CPU time on one thread)\n", points, n, nusable);
  if (tol > 0)
    printf("tolerance: rms surface error <= %g%% of the largest displacement\n", 100 * tol);
  if (budget > 0) printf("budget: <= %g ms of CPU time per step (one thread)\n", budget);
  sort_base = p;
  int rc = TB_EXIT_OK;
  if (pick < 0) {
    printf("\nno settled point qualifies.\n");
    rc = TB_EXIT_FAIL;
  } else {
    printf("\nchoice (%s):\n",
           tol > 0 ? "the cheapest within the tolerance" : "the most accurate within the budget");
    print_header();
    print_row(&p[pick], "=>");
  }
  /* evidence: the qualifying points (by cost, or by error for a budget) */
  int m = 0;
  for (int k = 0; k < n; k++)
    if (tb_point_usable(&p[k]) && (!(tol > 0) || p[k].rms_err <= tol) &&
        (!(budget > 0) || p[k].ms_step <= budget))
      idx[m++] = k;
  qsort(idx, (size_t)m, sizeof *idx, tol > 0 ? by_cost : by_error);
  printf("\nevidence: %d point(s) qualify, %s:\n", m,
         tol > 0 ? "cheapest first" : "most accurate first");
  if (m) print_header();
  for (int k = 0; k < m; k++) print_row(&p[idx[k]], idx[k] == pick ? "=>" : "");
  /* the best rejected: settled points that miss, by what they missed on */
  m = 0;
  for (int k = 0; k < n; k++)
    if (tb_point_usable(&p[k]) &&
        ((tol > 0 && p[k].rms_err > tol) || (budget > 0 && p[k].ms_step > budget)))
      idx[m++] = k;
  qsort(idx, (size_t)m, sizeof *idx, tol > 0 ? by_error : by_cost);
  printf("\nrejected: %d settled point(s) miss (%s first; at most 5 shown):\n", m,
         tol > 0 ? "the most accurate" : "the cheapest");
  if (m) print_header();
  for (int k = 0; k < m && k < 5; k++) print_row(&p[idx[k]], "x");
  if (n - nusable)
    printf("\nnot considered: %d unstable or unsettled point(s) (no equilibrium to compare)\n",
           n - nusable);
  if (rc) {
    printf("\n");
    fprintf(stderr, "tissuebench advise: no settled point has %s%s%s\n",
            tol > 0 ? "rms error within the tolerance" : "", tol > 0 && budget > 0 ? " and " : "",
            budget > 0 ? "ms/step within the budget" : "");
  }
  free(idx), free(p);
  return rc;
}
