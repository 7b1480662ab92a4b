/* The correctness table: every triangle test's wrong answers against the
 * exact oracle (cgal) on (a) the 40 designed pairs, (b) random pairs in
 * general position, (c) each degenerate family (bench/pairgen.c), (d) the
 * JGT Shen-2003 pairs when ../shared/data is present. The first wrong pairs
 * of every method go to wrong-pairs.txt, in the `tritri` input format. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"
#include "tb_pairgen.h"
#include "tb_results.h"
#include "tb_timer.h"
#include "tb_tritri_run.h"

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
  int jrc = tb_pairs_read_jgt_dir(TB_SHARED_DATA "/jgt-shen2003", &sets[n].set, &sep, &err);
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
  int nsteps = nm * nsets, step = 0;
  for (int j = 0; j < nm && !failed; j++) {
    tb_table_row(t);
    tb_table_cell(t, "%s", m[j].name);
    for (int k = 0; k < nsets; k++, step++) {
      tb_progress("correctness", step, nsteps);
      unsigned char *got = malloc((size_t)sets[k].set.n + 1);
      if (!got) {
        tb_table_cell(t, "out of memory");
        continue;
      }
      uint64_t t0 = tb_time_ns();
      tb_tritri_classify(&m[j], &sets[k].set, got);
      double secs = (double)(tb_time_ns() - t0) * 1e-9;
      int wrong = 0;
      for (int i = 0; i < sets[k].set.n; i++) wrong += got[i] != sets[k].truth[i];
      char bname[160]; /* the classification's time, its wrong answers as counters */
      snprintf(bname, sizeof bname, "correctness/%s/%s", m[j].name, sets[k].name);
      tb_suite_bench(s, bname, &secs, NULL, 1, "s");
      tb_suite_counter(s, bname, "wrong", wrong);
      tb_suite_counter(s, bname, "pairs", sets[k].set.n);
      if (wf && wrong) list_wrong(wf, m[j].name, &sets[k], got);
      tb_table_cell(t, "%d", wrong);
      if (m[j].exact && wrong) {
        fprintf(stderr, "correctness: %s claims exactness but is wrong %d times on %s\n", m[j].name,
                wrong, sets[k].name);
        failed = 1;
      }
      free(got);
    }
    tb_table_cell(t, "%s", m[j].exact ? "yes" : "no");
  }
  tb_progress("correctness", nsteps, nsteps);
  if (wf) fclose(wf);
  tb_suite_note(s,
                "Every answer is compared with CGAL's do_intersect on the exact-predicates kernel "
                "(zero-area triangles as segments or points). Degenerate families use exactly "
                "representable coordinates, so each pair is exactly the configuration named "
                "(bench/pairgen.c). Pairs: %s. The first %d wrong pairs per method and family are "
                "in wrong-pairs.txt (feed them to `tissuebench tritri`).",
                o->full ? "full (10x)" : "quick", SHOW_WRONG);
  tb_suite_table(s, t);
  for (int k = 0; k < nsets; k++) tb_pairs_free(&sets[k].set), free(sets[k].truth);
  if (tb_suite_end(s, &err)) {
    fprintf(stderr, "correctness: %s\n", err.msg);
    return 1;
  }
  return failed;
}
