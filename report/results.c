/* The results collector: tables of formatted cells, notes,
 * timing samples and their statistics (mean, median: the middle value or the
 * mean of the two middle ones; sample standard deviation with n - 1; min,
 * max), gathered per suite run and handed to report/results_files.c at the
 * end. Misuse of a table or a suite (too many cells, unknown time unit, ...)
 * is remembered and reported by tb_suite_end, never a crash. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "results_priv.h"
#include "core/tb_threads.h"

/* ---- small helpers ---- */

char *tb_results_dup(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

static char *vformat(const char *fmt, va_list ap) {
  va_list ap2;
  va_copy(ap2, ap);
  int n = vsnprintf(NULL, 0, fmt, ap2);
  va_end(ap2);
  if (n < 0) return NULL;
  char *s = malloc((size_t)n + 1);
  if (s) vsnprintf(s, (size_t)n + 1, fmt, ap);
  return s;
}

char *tb_results_join(const char *dir, const char *name) {
  size_t a = strlen(dir), b = strlen(name);
  char *p = malloc(a + b + 2);
  if (!p) return NULL;
  memcpy(p, dir, a);
  p[a] = '/';
  memcpy(p + a + 1, name, b + 1);
  return p;
}

void *tb_results_grow(void *p, int *cap, int need, size_t size) {
  if (need <= *cap) return p;
  int c = *cap ? *cap * 2 : 8;
  while (c < need) c *= 2;
  void *q = realloc(p, (size_t)c * size);
  if (q) *cap = c;
  return q;
}

/* ---- tables ---- */

tb_table *tb_table_new(const char *name, const char *title, int ncols, const char *const *cols) {
  if (!name || !*name || ncols <= 0 || !cols) return NULL;
  for (int j = 0; j < ncols; j++)
    if (!cols[j]) return NULL;
  tb_table *t = calloc(1, sizeof *t);
  if (!t) return NULL;
  t->ncols = ncols;
  t->name = tb_results_dup(name);
  t->title = tb_results_dup(title ? title : "");
  t->cols = calloc((size_t)ncols, sizeof *t->cols);
  t->csv_cols = calloc((size_t)ncols, sizeof *t->csv_cols);
  t->only = calloc((size_t)ncols, 1);
  int ok = t->name && t->title && t->cols && t->csv_cols && t->only;
  for (int j = 0; ok && j < ncols; j++) ok = (t->cols[j] = tb_results_dup(cols[j])) != NULL;
  if (!ok) {
    tb_table_free(t);
    return NULL;
  }
  return t;
}

static void table_fail(tb_table *t, const char *what) {
  if (!t->err[0]) snprintf(t->err, sizeof t->err, "table \"%s\": %s", t->name, what);
}

void tb_table_row(tb_table *t) {
  if (!t) return;
  size_t nc = (size_t)t->ncols;
  if (t->nrows == t->cap_rows) { /* the cells, their values and kinds grow together */
    int cap = t->cap_rows ? 2 * t->cap_rows : 8;
    char **c = realloc(t->cells, (size_t)cap * nc * sizeof *c);
    if (c) t->cells = c;
    double *v = c ? realloc(t->vals, (size_t)cap * nc * sizeof *v) : NULL;
    if (v) t->vals = v;
    unsigned char *k = v ? realloc(t->isnum, (size_t)cap * nc) : NULL;
    if (!k) {
      table_fail(t, "out of memory");
      return;
    }
    t->isnum = k;
    t->cap_rows = cap;
  }
  size_t at = (size_t)t->nrows * nc;
  memset(t->cells + at, 0, nc * sizeof *t->cells);
  memset(t->vals + at, 0, nc * sizeof *t->vals);
  memset(t->isnum + at, 0, nc);
  t->nrows++;
  t->next = 0;
}

/* The next cell's index, or -1 (recorded) when there is no room. */
static long next_cell(tb_table *t) {
  const char *bad = t->nrows == 0         ? "cell before the first tb_table_row"
                    : t->next >= t->ncols ? "a row has more cells than columns"
                                          : NULL;
  if (bad) {
    table_fail(t, bad);
    return -1;
  }
  return (long)(t->nrows - 1) * t->ncols + t->next;
}

static void set_cell(tb_table *t, long at, char *text, int isnum, double value) {
  if (!text) {
    table_fail(t, "out of memory");
    return;
  }
  t->cells[at] = text;
  t->isnum[at] = (unsigned char)isnum;
  t->vals[at] = value;
  t->next++;
}

void tb_table_cell(tb_table *t, const char *fmt, ...) {
  if (!t) return;
  long at = next_cell(t);
  if (at < 0) return;
  va_list ap;
  va_start(ap, fmt);
  char *s = vformat(fmt, ap);
  va_end(ap);
  set_cell(t, at, s, 0, 0);
}

/* 1 when fmt has exactly one conversion and it is a floating one (%f %e %g
 * %a, either case, with flags, width and precision); "%%" is text. */
static int one_double_conversion(const char *fmt) {
  int n = 0;
  for (const char *p = fmt; *p; p++) {
    if (*p != '%') continue;
    if (*++p == '%') continue;
    p += strspn(p, "-+ #0");
    p += strspn(p, "0123456789");
    if (*p == '.') p += 1 + strspn(p + 1, "0123456789");
    if (!*p || !strchr("fFeEgGaA", *p)) return 0;
    n++;
  }
  return n == 1;
}

void tb_table_num(tb_table *t, double value, const char *fmt) {
  if (!t) return;
  if (!fmt || !one_double_conversion(fmt)) {
    table_fail(t, "tb_table_num needs a format with one floating conversion");
    return;
  }
  long at = next_cell(t);
  if (at < 0) return;
  char *s = NULL;
  if (!isfinite(value)) {
    s = tb_results_dup("-");
  } else {
    int n = snprintf(NULL, 0, fmt, value);
    s = n < 0 ? NULL : malloc((size_t)n + 1);
    if (s) snprintf(s, (size_t)n + 1, fmt, value);
  }
  set_cell(t, at, s, 1, value);
}

void tb_table_numf(tb_table *t, double value, const char *fmt, ...) {
  if (!t) return;
  long at = next_cell(t);
  if (at < 0) return;
  va_list ap;
  va_start(ap, fmt);
  char *s = vformat(fmt, ap);
  va_end(ap);
  set_cell(t, at, s, 1, value);
}

void tb_table_only(tb_table *t, int col, int where) {
  if (!t) return;
  if (col < 0 || col >= t->ncols || (where != TB_MD_ONLY && where != TB_CSV_ONLY)) {
    table_fail(t, "tb_table_only: no such column, or not TB_MD_ONLY / TB_CSV_ONLY");
    return;
  }
  t->only[col] = (unsigned char)where;
}

void tb_table_csv_name(tb_table *t, int col, const char *name) {
  if (!t) return;
  if (col < 0 || col >= t->ncols || !name || !*name) {
    table_fail(t, "tb_table_csv_name: no such column, or no name");
    return;
  }
  char *d = tb_results_dup(name);
  if (!d) {
    table_fail(t, "out of memory");
    return;
  }
  free(t->csv_cols[col]);
  t->csv_cols[col] = d;
}

void tb_table_free(tb_table *t) {
  if (!t) return;
  for (size_t i = 0; t->cells && i < (size_t)t->nrows * (size_t)t->ncols; i++) free(t->cells[i]);
  for (int j = 0; t->cols && j < t->ncols; j++) free(t->cols[j]);
  for (int j = 0; t->csv_cols && j < t->ncols; j++) free(t->csv_cols[j]);
  free(t->cells);
  free(t->vals);
  free(t->isnum);
  free(t->cols);
  free(t->csv_cols);
  free(t->only);
  free(t->name);
  free(t->title);
  free(t);
}

/* ---- statistics ---- */

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

tb_stats tb_stats_of(const double *samples, int n) {
  tb_stats st = {0, 0, 0, 0, 0, 0};
  if (!samples || n <= 0) return st;
  st.n = n;
  double sum = 0;
  st.min = st.max = samples[0];
  for (int i = 0; i < n; i++) {
    sum += samples[i];
    if (samples[i] < st.min) st.min = samples[i];
    if (samples[i] > st.max) st.max = samples[i];
  }
  st.mean = sum / n;
  if (n > 1) { /* sample standard deviation, two passes for accuracy */
    double ss = 0;
    for (int i = 0; i < n; i++) ss += (samples[i] - st.mean) * (samples[i] - st.mean);
    st.stddev = sqrt(ss / (n - 1));
  }
  double *v = malloc((size_t)n * sizeof *v);
  if (!v) {
    st.median = NAN; /* no memory to sort a copy */
    return st;
  }
  memcpy(v, samples, (size_t)n * sizeof *v);
  qsort(v, (size_t)n, sizeof *v, cmp_double);
  st.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  free(v);
  return st;
}

/* ---- the suite ---- */

void tb_results_fail(tb_suite *s, const char *fmt, ...) {
  if (s->err[0]) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(s->err, sizeof s->err, fmt, ap);
  va_end(ap);
}

/* mkdir -p */
int tb_results_make_dirs(const char *dir, tb_error *err) {
  char *p = tb_results_dup(dir);
  if (!p) return tb_error_set(err, dir, 0, "out of memory");
  for (char *q = p + 1;; q++) {
    char c = *q;
    if (c != '/' && c != 0) continue;
    *q = 0;
    if (mkdir(p, 0777) != 0 && errno != EEXIST) {
      int e = errno;
      free(p);
      return tb_error_set(err, dir, 0, "cannot create folder: %s", strerror(e));
    }
    *q = c;
    if (!c) break;
  }
  free(p);
  struct stat sb;
  if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode)) return tb_error_set(err, dir, 0, "not a folder");
  return 0;
}

tb_suite *tb_suite_begin(const char *dir, const char *name, const char *title, uint64_t seed,
                         tb_error *err) {
  if (!dir || !*dir || !name || !*name) {
    tb_error_set(err, "tb_suite_begin", 0, "a suite needs an output folder and a name");
    return NULL;
  }
  if (tb_results_make_dirs(dir, err)) return NULL;
  tb_suite *s = calloc(1, sizeof *s);
  if (s) {
    s->dir = tb_results_dup(dir);
    s->name = tb_results_dup(name);
    s->title = tb_results_dup(title && *title ? title : name);
  }
  if (!s || !s->dir || !s->name || !s->title) {
    if (s) {
      free(s->dir);
      free(s->name);
      free(s->title);
    }
    free(s);
    tb_error_set(err, dir, 0, "out of memory");
    return NULL;
  }
  ssize_t n = readlink("/proc/self/exe", s->exe, sizeof s->exe - 1);
  if (n > 0)
    s->exe[n] = 0;
  else
    snprintf(s->exe, sizeof s->exe, "unknown");
  tb_context_collect(&s->ctx, seed);
  tb_noise_mark_take(&s->start);
  /* the folder is marked until tb_suite_end: a run killed on the way leaves the mark */
  char mark[1200];
  snprintf(mark, sizeof mark, "%s/" TB_INCOMPLETE, dir);
  FILE *f = fopen(mark, "w");
  if (f) {
    fprintf(f,
            "The suite %s started writing this folder at %s and did not finish (interrupted or "
            "crashed): its files may be partial or from an earlier run. Run it again.\n",
            name, s->ctx.date);
    fclose(f);
  }
  return s;
}

const tb_context *tb_suite_context(const tb_suite *s) { return s ? &s->ctx : NULL; }

int tb_results_add(tb_suite *s, int kind, char *text, tb_table *t) {
  tb_results_item *it = tb_results_grow(s->items, &s->cap_items, s->nitems + 1, sizeof *it);
  if (!it) return -1;
  s->items = it;
  it[s->nitems++] = (tb_results_item){kind, text, t, NULL};
  return 0;
}

void tb_suite_note(tb_suite *s, const char *fmt, ...) {
  if (!s) return;
  va_list ap;
  va_start(ap, fmt);
  char *text = vformat(fmt, ap);
  va_end(ap);
  if (!text || tb_results_add(s, TB_ITEM_NOTE, text, NULL)) {
    free(text);
    tb_results_fail(s, "a note: out of memory");
  }
}

void tb_suite_table(tb_suite *s, tb_table *t) {
  if (!s || !t) {
    if (s) tb_results_fail(s, "a table could not be created (bad arguments or out of memory)");
    tb_table_free(t);
    return;
  }
  if (t->err[0]) tb_results_fail(s, "%s", t->err);
  if (tb_results_add(s, TB_ITEM_TABLE, NULL, t)) {
    tb_results_fail(s, "table \"%s\": out of memory", t->name);
    tb_table_free(t);
  }
}

void tb_suite_figure(tb_suite *s, const char *file, const char *fmt, ...) {
  if (!s || tb_results_partial(s)) return;
  if (!file || !*file || file[0] == '/' || strstr(file, "..")) {
    tb_results_fail(s, "a figure needs a file name inside the suite folder, without \"..\"");
    return;
  }
  char *path = tb_results_join(s->dir, file);
  struct stat sb;
  int found = path && stat(path, &sb) == 0 && S_ISREG(sb.st_mode);
  free(path);
  if (!found) {
    tb_results_fail(s, "figure \"%s\": no such file in %s", file, s->dir);
    return;
  }
  char *name = tb_results_dup(file);
  if (!name || tb_results_add(s, TB_ITEM_FIGURE, name, NULL)) {
    free(name);
    tb_results_fail(s, "figure \"%s\": out of memory", file);
    return;
  }
  if (fmt) {
    va_list ap;
    va_start(ap, fmt);
    s->items[s->nitems - 1].caption = vformat(fmt, ap);
    va_end(ap);
  }
}

void tb_suite_caption(tb_suite *s, const char *name, const char *fmt, ...) {
  if (!s || tb_results_partial(s)) return;
  tb_results_item *it = NULL;
  for (int i = s->nitems - 1; i >= 0 && !it && name && fmt; i--)
    if ((s->items[i].kind == TB_ITEM_CHART || s->items[i].kind == TB_ITEM_FIGURE) &&
        strcmp(s->items[i].text, name) == 0)
      it = &s->items[i];
  if (!it) {
    tb_results_fail(s, "caption for \"%s\": no chart or figure of that name", name ? name : "");
    return;
  }
  va_list ap;
  va_start(ap, fmt);
  char *c = vformat(fmt, ap);
  va_end(ap);
  if (!c) {
    tb_results_fail(s, "caption for \"%s\": out of memory", name);
    return;
  }
  free(it->caption);
  it->caption = c;
}

static const char *const units[] = {"ns", "us", "ms", "s"};
static const double unit_seconds[] = {1e-9, 1e-6, 1e-3, 1.0};

static int unit_index(const char *u) {
  for (int i = 0; u && i < 4; i++)
    if (strcmp(u, units[i]) == 0) return i;
  return -1;
}

void tb_suite_bench(tb_suite *s, const char *name, const double *real, const double *cpu, int n,
                    const char *unit) {
  if (!s) return;
  int u = unit_index(unit);
  if (!name || !*name || !real || n <= 0) {
    tb_results_fail(s, "benchmark \"%s\": needs a name and at least one repetition",
                    name ? name : "");
    return;
  }
  if (u < 0) {
    tb_results_fail(s, "benchmark \"%s\": time unit \"%s\" is not ns, us, ms or s", name,
                    unit ? unit : "(null)");
    return;
  }
  if (!cpu) {
    tb_results_fail(s, "benchmark \"%s\": needs CPU times beside the wall times", name);
    return;
  }
  tb_results_bench b = {.name = tb_results_dup(name),
                        .unit = units[u],
                        .n = n,
                        .threads = tb_threads(),
                        .real = malloc((size_t)n * sizeof(double)),
                        .cpu = malloc((size_t)n * sizeof(double))};
  tb_results_bench *bs = b.name && b.real && b.cpu ? tb_results_grow(s->benches, &s->cap_benches,
                                                                     s->nbenches + 1, sizeof *bs)
                                                   : NULL;
  if (!bs) {
    free(b.name);
    free(b.real);
    free(b.cpu);
    tb_results_fail(s, "benchmark \"%s\": out of memory", name);
    return;
  }
  memcpy(b.real, real, (size_t)n * sizeof(double));
  memcpy(b.cpu, cpu, (size_t)n * sizeof(double));
  s->benches = bs;
  bs[s->nbenches++] = b;
}

/* The fields of a benchmark entry a counter must not shadow. */
static const char *const entry_fields[] = {
    "name",       "family_index",    "per_family_instance_index",
    "run_name",   "run_type",        "repetitions",
    "threads",    "aggregate_name",  "aggregate_unit",
    "iterations", "real_time",       "cpu_time",
    "time_unit",  "repetition_index"};

void tb_suite_counter(tb_suite *s, const char *bench, const char *key, double value) {
  if (!s) return;
  if (!bench || !*bench || !key || !*key) {
    tb_results_fail(s, "a counter needs a benchmark name and a key");
    return;
  }
  for (size_t i = 0; i < sizeof entry_fields / sizeof entry_fields[0]; i++)
    if (strcmp(key, entry_fields[i]) == 0) {
      tb_results_fail(s, "benchmark \"%s\": counter \"%s\" is one of the entry's own fields", bench,
                      key);
      return;
    }
  tb_results_bench *b = NULL;
  for (int i = s->nbenches - 1; i >= 0 && !b; i--)
    if (strcmp(s->benches[i].name, bench) == 0) b = &s->benches[i];
  if (!b) { /* counters only */
    tb_results_bench *bs =
        tb_results_grow(s->benches, &s->cap_benches, s->nbenches + 1, sizeof *bs);
    char *name = bs ? tb_results_dup(bench) : NULL;
    if (!name) {
      if (bs) s->benches = bs;
      tb_results_fail(s, "benchmark \"%s\": out of memory", bench);
      return;
    }
    s->benches = bs;
    b = &bs[s->nbenches++];
    *b = (tb_results_bench){.name = name, .unit = "s", .threads = tb_threads()};
  }
  for (int i = 0; i < b->ncounters; i++)
    if (strcmp(b->keys[i], key) == 0) {
      b->counters[i] = value; /* the last value counts */
      return;
    }
  int cap = b->cap_counters;
  char **k = tb_results_grow(b->keys, &cap, b->ncounters + 1, sizeof *k);
  if (k) b->keys = k;
  cap = b->cap_counters;
  double *v = k ? tb_results_grow(b->counters, &cap, b->ncounters + 1, sizeof *v) : NULL;
  if (v) b->counters = v;
  char *d = v ? tb_results_dup(key) : NULL;
  if (!d) {
    tb_results_fail(s, "benchmark \"%s\": out of memory", bench);
    return;
  }
  b->cap_counters = cap;
  b->keys[b->ncounters] = d;
  b->counters[b->ncounters++] = value;
}

void tb_suite_counter_est(tb_suite *s, const char *bench, const char *key, tb_est e) {
  char k[128];
  tb_suite_counter(s, bench, key, e.value);
  snprintf(k, sizeof k, "%s_low", key);
  tb_suite_counter(s, bench, k, e.lo);
  snprintf(k, sizeof k, "%s_high", key);
  tb_suite_counter(s, bench, k, e.hi);
}

/* ---- end of the run ---- */

/* The timings as one more table of table.md and its CSV, all in one unit:
 * the benchmarks' own when they share it, else ms. Counter-only entries
 * have no time and are left out. */
static void add_timings(tb_suite *s) {
  int u = -1;
  for (int i = 0; i < s->nbenches; i++)
    if (s->benches[i].n > 0) {
      int bu = unit_index(s->benches[i].unit);
      u = u < 0 || u == bu ? bu : 2;
    }
  if (u < 0) return;
  char h[7][40];
  const char *what[7] = {"median CPU", "CPU 95% low", "CPU 95% high", "median wall",
                         "mean wall",  "min wall",    "max wall"};
  const char *cols[10] = {"benchmark", "repetitions", "threads"};
  for (int k = 0; k < 7; k++) {
    snprintf(h[k], sizeof h[k], "%s (%s)", what[k], units[u]);
    cols[k + 3] = h[k];
  }
  tb_table *t = tb_table_new("timings",
                             "Timings: CPU time with its 95% interval, wall time (every repetition "
                             "is in data.json)",
                             10, cols);
  for (int i = 0; t && i < s->nbenches; i++) {
    const tb_results_bench *b = &s->benches[i];
    if (b->n == 0) continue;
    double k = unit_seconds[unit_index(b->unit)] / unit_seconds[u];
    tb_stats a = tb_stats_of(b->real, b->n);
    tb_est c = tb_median_est(b->cpu, b->n);
    double v[7] = {c.value, c.lo, c.hi, a.median, a.mean, a.min, a.max};
    tb_table_row(t);
    tb_table_cell(t, "%s", b->name);
    tb_table_cell(t, "%d", b->n);
    tb_table_cell(t, "%d", b->threads);
    for (int q = 0; q < 7; q++) tb_table_num(t, v[q] * k, fabs(v[q] * k) >= 1e4 ? "%.0f" : "%.4g");
  }
  tb_suite_table(s, t);
}

static void suite_free(tb_suite *s) {
  for (int i = 0; i < s->nitems; i++) {
    free(s->items[i].text);
    free(s->items[i].caption);
    tb_table_free(s->items[i].table);
  }
  for (int i = 0; i < s->nbenches; i++) {
    free(s->benches[i].name);
    free(s->benches[i].real);
    free(s->benches[i].cpu);
    for (int k = 0; k < s->benches[i].ncounters; k++) free(s->benches[i].keys[k]);
    free(s->benches[i].keys);
    free(s->benches[i].counters);
  }
  free(s->items);
  free(s->benches);
  free(s->cases);
  free(s->dir);
  free(s->name);
  free(s->title);
  free(s);
}

tb_noise tb_suite_noise(const tb_suite *s, int threads) {
  tb_noise_mark now;
  tb_noise_mark_take(&now);
  return tb_noise_between(&s->start, &now, threads);
}

/* The suite's machine load, as a note and in the context; on stderr when
 * other processes left this one fewer than one core. */
static void note_noise(tb_suite *s) {
  s->ctx.noise = tb_suite_noise(s, 1), s->ctx.have_noise = 1;
  char what[300];
  tb_noise_describe(&s->ctx.noise, what, sizeof what);
  tb_suite_note(s, "Machine load during this suite (%.0f s): %s.%s", s->ctx.noise.seconds, what,
                s->ctx.noise.busy
                    ? " CPU times of single-threaded work hold (another process's time slices "
                      "do not count); wall times and thread scaling do not."
                    : "");
  if (s->ctx.noise.busy) fprintf(stderr, "tissuebench: %s: %s\n", s->name, what);
}

int tb_suite_end(tb_suite *s, tb_error *err) {
  if (!s) return tb_error_set(err, "tb_suite_end", 0, "no suite (tb_suite_begin failed?)");
  char mark[1200];
  snprintf(mark, sizeof mark, "%s/" TB_INCOMPLETE, s->dir);
  remove(mark);
  note_noise(s);
  if (tb_results_partial(s)) { /* a shard's share of the cases: only their outcomes */
    int rc = tb_results_shard_write(s, err);
    if (!rc && s->err[0]) rc = tb_error_set(err, s->dir, 0, "%s", s->err);
    suite_free(s);
    return rc;
  }
  add_timings(s);
  int rc = tb_results_write_files(s, err);
  if (!rc && s->err[0]) rc = tb_error_set(err, s->dir, 0, "%s", s->err);
  tb_results_report_add(s);
  suite_free(s);
  return rc;
}
