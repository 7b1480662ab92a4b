/* The correctness table: every triangle test's wrong answers against the
 * exact oracle (cgal) on (a) the 40 designed pairs, (b) random pairs in
 * general position, (c) each degenerate family (measure/pairgen.c), (d) the
 * JGT Shen-2003 pairs when ../shared/data is present; (e) the scaled
 * family: those pairs with every coordinate times 2^k, k = -600 .. 600
 * (exact scaling, so the unscaled oracle's answers still hold).
 * The first wrong pairs of every method go to wrong-pairs.txt, in the
 * `tritri` input format. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_suites.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "measure/tb_pairgen.h"
#include "measure/tb_tritri_run.h"
#include "report/tb_results.h"

#define SHOW_WRONG 5
#define MAX_SETS 20

typedef struct named_set {
  char name[40];
  tb_pairset set;
  unsigned char *truth; /* the oracle's answers */
} named_set;

/* Loads the sets; returns how many (names of sets absent are noted). */
static int load_sets(const tb_suite_opts *o, named_set *sets, tb_suite *s, int *bad) {
  int n = 0;
  tb_error err;
  snprintf(sets[n].name, sizeof sets[n].name, "designed 40");
  if (tb_pairs_read_file(TB_DESIGNED_PAIRS, &sets[n].set, &err))
    tb_suite_note(s, "designed pairs not read: %s", err.msg);
  else
    n++;
  int nf;
  const tb_pair_family *f = tb_pair_families(&nf);
  for (int i = 0; i < nf; i++) {
    int count = (int)((i == 0 ? 1e6 : 1e5) * (o->full ? 10 : 1) * o->scale);
    if (count < 1) count = 1;
    memset(&sets[n].set, 0, sizeof sets[n].set);
    snprintf(sets[n].name, sizeof sets[n].name, "%s", f[i].name);
    if (tb_pairgen(&f[i], count, o->seed, &sets[n].set) == 0)
      n++;
    else
      tb_pairs_free(&sets[n].set);
  }
  tb_pairset sep;
  int jrc = tb_pairs_read_jgt_dir(TB_SHARED_DATA_FILE("jgt-shen2003"), &sets[n].set, &sep, &err);
  if (jrc < 0) {
    fprintf(stderr, "correctness: %s\n", err.msg);
    *bad = 1;
  } else if (jrc == 0) {
    for (int i = 0; i < sep.n; i++) tb_pairs_add(&sets[n].set, &sep.pairs[i], sep.expect[i]);
    tb_pairs_free(&sep);
    snprintf(sets[n].name, sizeof sets[n].name, "JGT Shen 2003");
    n++;
  } else {
    tb_suite_note(s, "JGT Shen-2003 pairs absent (%s): that column is left out.", err.msg);
  }
  return n;
}

static void list_wrong(FILE *f, const char *method, const named_set *ns, const unsigned char *got) {
  int shown = 0;
  for (int i = 0; i < ns->set.n && shown < SHOW_WRONG; i++) {
    if (got[i] == ns->truth[i]) continue;
    fprintf(f, "# %s on %s pair %d: answered %d, the oracle says %d\n", method, ns->name, i, got[i],
            ns->truth[i]);
    tb_pairs_write_line(f, &ns->set.pairs[i]);
    shown++;
  }
}

/* One method on one set: times it (one pass, CPU and wall), counts its wrong answers (benchmark
 * `bname`), lists the first ones; returns the count, -1 out of memory. */
static int run_one(tb_suite *s, FILE *wf, const tb_tritri_method *m, const named_set *ns,
                   const char *bname) {
  unsigned char *got = malloc((size_t)ns->set.n + 1);
  if (!got) return -1;
  tb_clock c = tb_clock_start();
  tb_tritri_classify(m, &ns->set, got);
  double wall_ms, cpu_ms;
  tb_clock_ms(&c, &wall_ms, &cpu_ms);
  int wrong = 0;
  for (int i = 0; i < ns->set.n; i++) wrong += got[i] != ns->truth[i];
  /* the pass's wall and CPU time, the wrong answers as counters */
  tb_suite_bench(s, bname, &wall_ms, &cpu_ms, 1, "ms");
  tb_suite_counter(s, bname, "wrong", wrong);
  tb_suite_counter(s, bname, "pairs", ns->set.n);
  if (wf && wrong) list_wrong(wf, m->name, ns, got);
  free(got);
  return wrong;
}

/* ---- the scaled family ---- */
/* Scales 2^k of the scaled rows (0: the unscaled pairs, for comparison). */
static const int SCALES[] = {-600, -500, -300, 0, 300, 500, 600};
#define NSCALES ((int)(sizeof SCALES / sizeof SCALES[0]))
#define SCALED_PER_FAMILY 200 /* the first pairs of every generated family */

/* The pairs scaled: the designed and JGT pairs and the first
 * SCALED_PER_FAMILY of every generated family, each coordinate times 2^k;
 * the truth of each is the oracle's answer on the unscaled pair. Returns 0,
 * -1 out of memory. */
static int make_scaled(const named_set *sets, int nsets, int e, named_set *out) {
  memset(out, 0, sizeof *out);
  snprintf(out->name, sizeof out->name, "2^%d", e);
  int total = 0;
  for (int k = 0; k < nsets; k++) total += sets[k].set.n;
  int *index = malloc((size_t)total * sizeof *index + 1);
  out->truth = malloc((size_t)total + 1);
  if (!index || !out->truth) {
    free(index);
    return -1;
  }
  for (int k = 0; k < nsets; k++) {
    tb_pairset head = sets[k].set;
    if (head.n > SCALED_PER_FAMILY && strcmp(sets[k].name, "designed 40") &&
        strcmp(sets[k].name, "JGT Shen 2003"))
      head.n = SCALED_PER_FAMILY;
    int n0 = out->set.n, added = tb_pairs_scaled(&head, e, &out->set, index);
    if (added < 0) {
      free(index);
      return -1;
    }
    for (int i = 0; i < added; i++) out->truth[n0 + i] = sets[k].truth[index[i]];
  }
  free(index);
  return 0;
}

/* The scaled rows: scale, pairs, then every method's wrong answers against
 * the unscaled oracle. Returns 1 when the oracle's answers changed. */
static int scaled_table(tb_suite *s, FILE *wf, const named_set *sets, int nsets, int *step,
                        int nsteps) {
  int nm, failed = 0;
  const tb_tritri_method *m = tb_tritri_methods(&nm);
  const char *cols[2 + 16];
  if (nm > 16) nm = 16;
  cols[0] = "scale", cols[1] = "pairs";
  for (int j = 0; j < nm; j++) cols[2 + j] = m[j].name;
  tb_table *t =
      tb_table_new("scaled", "Wrong answers on pairs scaled by 2^k (against cgal on the unscaled)",
                   2 + nm, cols);
  for (int e = 0; e < NSCALES; e++) {
    named_set ns;
    if (make_scaled(sets, nsets, SCALES[e], &ns)) {
      fprintf(stderr, "correctness: out of memory for the scaled pairs\n");
      tb_pairs_free(&ns.set), free(ns.truth);
      failed = 1;
      break;
    }
    tb_table_row(t);
    tb_table_cell(t, "2^%d", SCALES[e]);
    tb_table_cell(t, "%d", ns.set.n);
    for (int j = 0; j < nm; j++, (*step)++) {
      tb_progress("correctness", *step, nsteps);
      char bname[160];
      snprintf(bname, sizeof bname, "correctness/scaled/%s/2^%d", m[j].name, SCALES[e]);
      int wrong = run_one(s, wf, &m[j], &ns, bname);
      tb_table_cell(t, "%d", wrong);
      if (m[j].exact && wrong) { /* the oracle, and every test that claims exactness */
        fprintf(stderr, "correctness: %s changed %d answers under scaling by 2^%d\n", m[j].name,
                wrong, SCALES[e]);
        failed = 1;
      }
    }
    tb_pairs_free(&ns.set), free(ns.truth);
  }
  tb_suite_table(s, t);
  tb_suite_note(
      s,
      "Scaled rows: the designed and JGT pairs and the first %d pairs of every generated family, "
      "every coordinate multiplied by 2^k (exactly: pairs a coordinate of which would lose a bit "
      "to "
      "underflow are left out, hence the smaller counts below 2^0). Scaling by a power of two "
      "changes no intersection, so the reference is the oracle on the unscaled pairs; the oracle "
      "and every test that claims exactness must read 0 (the suite fails otherwise). The "
      "floating-point tests compute products of three and more coordinates (orientation "
      "determinants, plane distances and the products of their interval computations): scaled "
      "by 2^+-300 and beyond, such products overflow to infinity or underflow to zero or to "
      "subnormals, so signs and comparisons are lost. The mesh readers refuse coordinates beyond "
      "+-1e90 (TB_COORD_MAX, about 2^299): within it products of three coordinates stay finite, "
      "but tiny coordinates still cost the floating-point tests their precision.",
      SCALED_PER_FAMILY);
  return failed;
}

int tb_suite_correctness(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/correctness", o->results) >= (int)sizeof dir) return 1;
  tb_suite *s = tb_suite_begin(dir, "correctness",
                               "Triangle-triangle tests: wrong answers against the exact oracle",
                               o->seed, &err);
  if (!s) {
    fprintf(stderr, "correctness: %s\n", err.msg);
    return 1;
  }
  /* one thread: the methods' times are the calling thread's CPU time */
  int was = tb_threads_setting();
  tb_threads_set(1);
  named_set sets[MAX_SETS];
  int failed = 0, nsets = load_sets(o, sets, s, &failed), nm;
  const tb_tritri_method *m = tb_tritri_methods(&nm), *oracle = tb_tritri_find("cgal");
  /* the oracle's answers, and its agreement with the hand-made and JGT labels */
  for (int k = 0; k < nsets; k++) {
    sets[k].truth = malloc((size_t)sets[k].set.n + 1);
    if (!sets[k].truth || tb_tritri_classify(oracle, &sets[k].set, sets[k].truth)) {
      fprintf(stderr, "correctness: the oracle failed on %s\n", sets[k].name);
      failed = 1;
      continue;
    }
    int labelled = 0, agree = 0;
    for (int i = 0; i < sets[k].set.n; i++)
      if (sets[k].set.expect[i] >= 0)
        labelled++, agree += sets[k].set.expect[i] == sets[k].truth[i];
    if (labelled) {
      tb_suite_note(s, "The oracle agrees with the labels of %s on %d of %d pairs.", sets[k].name,
                    agree, labelled);
      failed |= agree != labelled;
    }
  }
  const char *cols[2 + MAX_SETS];
  char colname[MAX_SETS][64];
  cols[0] = "method";
  for (int k = 0; k < nsets; k++) {
    if (snprintf(colname[k], sizeof colname[k], "%s (of %d)", sets[k].name, sets[k].set.n) < 0)
      colname[k][0] = 0;
    cols[1 + k] = colname[k];
  }
  cols[1 + nsets] = "claims exact";
  tb_table *t = tb_table_new("wrong", "Wrong answers against cgal, per family", 2 + nsets, cols);
  char path[1024];
  snprintf(path, sizeof path, "%s/wrong-pairs.txt", dir);
  FILE *wf = fopen(path, "w");
  if (wf)
    fprintf(wf, "# The first %d wrong pairs of every method and family (tritri format).\n",
            SHOW_WRONG);
  int nsteps = nm * nsets + (failed ? 0 : nm * NSCALES), step = 0;
  for (int j = 0; j < nm && !failed; j++) {
    tb_table_row(t);
    tb_table_cell(t, "%s", m[j].name);
    for (int k = 0; k < nsets; k++, step++) {
      tb_progress("correctness", step, nsteps);
      char bname[160];
      snprintf(bname, sizeof bname, "correctness/%.60s/%.60s", m[j].name, sets[k].name);
      int wrong = run_one(s, wf, &m[j], &sets[k], bname);
      if (wrong < 0) {
        tb_table_cell(t, "out of memory");
        continue;
      }
      tb_table_cell(t, "%d", wrong);
      if (m[j].exact && wrong) {
        fprintf(stderr, "correctness: %s claims exactness but is wrong %d times on %s\n", m[j].name,
                wrong, sets[k].name);
        failed = 1;
      }
    }
    tb_table_cell(t, "%s", m[j].exact ? "yes" : "no");
  }
  tb_suite_note(
      s,
      "Every answer is compared with CGAL's do_intersect on the exact-predicates kernel "
      "(zero-area triangles as segments or points). Degenerate families use exactly "
      "representable coordinates, so each pair is exactly the configuration named "
      "(measure/pairgen.c). Pairs: %s. The first %d wrong pairs per method and family are "
      "in wrong-pairs.txt (feed them to `tissuebench tritri`). Each method's pass over "
      "a family is timed once on one thread (CPU and wall time in the timings table "
      "and data.json); the speed comparison is table 4.1's.",
      o->full ? "full (10x)" : "quick", SHOW_WRONG);
  tb_suite_table(s, t);
  if (!failed) failed = scaled_table(s, wf, sets, nsets, &step, nsteps);
  tb_progress("correctness", nsteps, nsteps);
  if (wf) fclose(wf);
  for (int k = 0; k < nsets; k++) tb_pairs_free(&sets[k].set), free(sets[k].truth);
  tb_threads_set(was);
  if (tb_suite_end(s, &err)) {
    fprintf(stderr, "correctness: %s\n", err.msg);
    return 1;
  }
  return failed;
}
