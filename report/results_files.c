/* The files of a suite run: table.md (GitHub markdown: title, the run's
 * context, then notes, tables and charts in the order added), one CSV per
 * table, table-<name>.csv (RFC 4180 quoting; bare numbers, units in the
 * header; a column mixing numbers and text is reported as a misuse), the
 * same in tidy long form, table-<name>.long.csv (one measurement a row: the
 * row's text columns, then metric, value, unit, the unit taken from the
 * header's parentheses), and
 * data.json in Google Benchmark's JSON layout ("context" plus "benchmarks":
 * one "iteration" entry per repetition, then mean/median/stddev/min/max
 * "aggregate" entries, min and max being our extension to its
 * mean/median/stddev; user counters as extra numeric fields). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "results_priv.h"

/* ---- table.md ---- */

/* A markdown table cell: '|' escaped, line breaks as spaces. */
static void md_cell(FILE *f, const char *s) {
  for (; *s; s++) {
    if (*s == '|')
      fputs("\\|", f);
    else
      fputc(*s == '\n' || *s == '\r' ? ' ' : *s, f);
  }
}

static int is_number(const char *s) {
  char *end;
  if (!*s) return 0;
  strtod(s, &end);
  return *end == 0;
}

static void md_table(FILE *f, const tb_table *t, int level) {
  fprintf(f, "%.*s %s\n\n|", level, "######", t->title[0] ? t->title : t->name);
  for (int j = 0; j < t->ncols; j++) {
    if (t->only[j] == TB_CSV_ONLY) continue;
    fputc(' ', f);
    md_cell(f, t->cols[j]);
    fputs(" |", f);
  }
  fputs("\n|", f);
  for (int j = 0; j < t->ncols; j++) { /* numbers align right */
    if (t->only[j] == TB_CSV_ONLY) continue;
    int numeric = 0, other = 0;
    for (int r = 0; r < t->nrows; r++) {
      const char *c = tb_results_cell(t, r, j);
      if (*c) is_number(c) ? numeric++ : other++;
    }
    fputs(numeric && !other ? " ---: |" : " --- |", f);
  }
  fputc('\n', f);
  for (int r = 0; r < t->nrows; r++) {
    fputc('|', f);
    for (int j = 0; j < t->ncols; j++) {
      if (t->only[j] == TB_CSV_ONLY) continue;
      fputc(' ', f);
      md_cell(f, tb_results_cell(t, r, j));
      fputs(" |", f);
    }
    fputc('\n', f);
  }
  fputc('\n', f);
}

void tb_results_md_context(FILE *f, const tb_context *c) {
  fprintf(f, "- **Date**: %s\n", c->date);
  fprintf(f, "- **Host**: %s\n", c->host);
  fprintf(f, "- **CPU**: %s, %d cores, %d threads used", c->cpu, c->cores, c->threads);
  if (c->mhz > 0) fprintf(f, ", %d MHz", c->mhz);
  fprintf(f, "\n- **Compiler**: %s, %s\n", c->compiler, c->flags);
  fprintf(f, "- **Commit**: %s%s\n", c->commit,
          c->dirty > 0    ? " (dirty)"
          : c->dirty == 0 ? " (clean)"
                          : "");
  fprintf(f, "- **Versions**: CHOLMOD %s, FCL %s, Bullet %s (double), CGAL %s, TetGen %s\n",
          c->cholmod, c->fcl, c->bullet, c->cgal, c->tetgen);
  fprintf(f, "- **Seed**: %llu\n\n", (unsigned long long)c->seed);
}

/* A picture: the image, then its caption as a line of its own (viewers do
 * not show the alt text). Charts link their other format. */
static void md_picture(FILE *f, const tb_results_item *it, const char *prefix, const char *ext) {
  const char *cap = it->caption ? it->caption : it->text;
  fputs("![", f);
  for (; *cap; cap++) /* alt text: no brackets, one line */
    if (!strchr("[]", *cap)) fputc(*cap == '\n' || *cap == '\r' ? ' ' : *cap, f);
  if (it->kind == TB_ITEM_CHART) {
    fprintf(f, "](%s%s.%s)\n\n", prefix, it->text, ext);
    if (it->caption)
      fprintf(f, "*%s* ([%s](%s%s.%s))\n\n", it->caption, strcmp(ext, "png") ? "PNG" : "SVG",
              prefix, it->text, strcmp(ext, "png") ? "png" : "svg");
  } else {
    fprintf(f, "](%s%s)\n\n", prefix, it->text);
    if (it->caption) fprintf(f, "*%s*\n\n", it->caption);
  }
}

void tb_results_md_body(FILE *f, const tb_suite *s, const char *prefix, int level,
                        const char *ext) {
  for (int i = 0; i < s->nitems; i++) {
    const tb_results_item *it = &s->items[i];
    if (it->kind == TB_ITEM_NOTE)
      fprintf(f, "%s\n\n", it->text);
    else if (it->kind == TB_ITEM_TABLE)
      md_table(f, it->table, level);
    else
      md_picture(f, it, prefix, ext);
  }
}

static void md_write(FILE *f, const tb_suite *s) {
  fprintf(f, "# %s\n\n", s->title);
  tb_results_md_context(f, &s->ctx);
  tb_results_md_body(f, s, "", 2, "svg");
}

/* ---- table-<name>.csv ---- */

static void csv_field(FILE *f, const char *s) {
  if (!s[strcspn(s, ",\"\r\n")] && s[0] != ' ' && (!*s || s[strlen(s) - 1] != ' ')) {
    fputs(s, f);
    return;
  }
  fputc('"', f);
  for (; *s; s++) {
    if (*s == '"') fputc('"', f);
    fputc(*s, f);
  }
  fputc('"', f);
}

/* A text cell that reads as a number in the CSV ("" and "-" are empty). */
static int text_is_empty(const char *c) { return !*c || strcmp(c, "-") == 0; }

/* A column is tidy when its non-empty cells are all numbers (tb_table_num,
 * or text that reads as one) or all other text. Records the first column
 * that mixes them, e.g. "2.1x" among numbers. */
static void csv_check(tb_suite *s, const tb_table *t) {
  for (int j = 0; j < t->ncols; j++) {
    if (t->only[j] == TB_MD_ONLY) continue;
    const char *num = NULL, *text = NULL;
    for (int r = 0; r < t->nrows; r++) {
      size_t at = (size_t)r * (size_t)t->ncols + (size_t)j;
      const char *c = tb_results_cell(t, r, j);
      if (t->isnum[at] || is_number(c))
        num = num ? num : c;
      else if (!text_is_empty(c))
        text = text ? text : c;
    }
    if (num && text) {
      tb_results_fail(s,
                      "table \"%s\", column \"%s\": numbers and text mixed (\"%s\" beside "
                      "\"%s\"); a number with a unit or sign belongs in tb_table_num",
                      t->name, t->cols[j], text, num);
      return;
    }
  }
}

/* One table: its header (CSV names where set), then its rows. */
static void csv_write(FILE *f, const tb_table *t) {
  for (int j = 0, first = 1; j < t->ncols; j++) {
    if (t->only[j] == TB_MD_ONLY) continue;
    if (!first) fputc(',', f);
    first = 0;
    csv_field(f, t->csv_cols[j] ? t->csv_cols[j] : t->cols[j]);
  }
  fputc('\n', f);
  for (int r = 0; r < t->nrows; r++) {
    for (int j = 0, first = 1; j < t->ncols; j++) {
      if (t->only[j] == TB_MD_ONLY) continue;
      size_t at = (size_t)r * (size_t)t->ncols + (size_t)j;
      const char *c = tb_results_cell(t, r, j);
      if (!first) fputc(',', f);
      first = 0;
      if (t->isnum[at]) {
        if (isfinite(t->vals[at])) fprintf(f, "%.10g", t->vals[at]);
      } else if (!text_is_empty(c)) {
        csv_field(f, c);
      }
    }
    fputc('\n', f);
  }
}

/* Units a header's parentheses may hold (others, such as "(CPU)", qualify the metric). */
static int is_unit(const char *u, size_t n) {
  static const char *const units[] = {
      "ns",      "us",      "ms",      "s",       "min",     "h",   "%",  "% of length", "Hz",
      "kHz",     "MHz",     "GHz",     "B",       "kB",      "KiB", "MB", "MiB",         "GB",
      "GiB",     "bytes",   "x",       "mm",      "cm",      "m",   "Pa", "kPa",         "deg",
      "degrees", "ns/pair", "ms/step", "us/step", "steps/s", "1/s"};
  for (size_t k = 0; k < sizeof units / sizeof units[0]; k++)
    if (strlen(units[k]) == n && !strncmp(units[k], u, n)) return 1;
  return 0;
}

/* The long form: a column holds text when none of its cells is a number. */
static int text_column(const tb_table *t, int j) {
  for (int r = 0; r < t->nrows; r++)
    if (t->isnum[(size_t)r * (size_t)t->ncols + (size_t)j]) return 0;
  return 1;
}

static void long_write(FILE *f, const tb_table *t) {
  for (int j = 0; j < t->ncols; j++)
    if (t->only[j] != TB_MD_ONLY && text_column(t, j)) {
      csv_field(f, t->csv_cols[j] ? t->csv_cols[j] : t->cols[j]);
      fputc(',', f);
    }
  fputs("metric,value,unit\n", f);
  for (int r = 0; r < t->nrows; r++)
    for (int j = 0; j < t->ncols; j++) {
      size_t at = (size_t)r * (size_t)t->ncols + (size_t)j;
      if (t->only[j] == TB_MD_ONLY || !t->isnum[at] || !isfinite(t->vals[at])) continue;
      for (int k = 0; k < t->ncols; k++)
        if (t->only[k] != TB_MD_ONLY && text_column(t, k)) {
          const char *c = tb_results_cell(t, r, k);
          if (!text_is_empty(c)) csv_field(f, c);
          fputc(',', f);
        }
      /* "time (ms)": metric "time", unit "ms"; "steps/s (CPU)" stays whole, CPU being no unit */
      const char *name = t->csv_cols[j] ? t->csv_cols[j] : t->cols[j];
      char metric[200], unit[64] = "";
      snprintf(metric, sizeof metric, "%s", name);
      const char *open = strrchr(name, '(');
      size_t n = open ? (size_t)(open - name) : 0, len = strlen(name);
      if (open && name[len - 1] == ')' && is_unit(open + 1, len - (size_t)(open - name) - 2)) {
        snprintf(unit, sizeof unit, "%.*s", (int)(len - (size_t)(open - name) - 2), open + 1);
        while (n > 0 && name[n - 1] == ' ') n--;
        snprintf(metric, sizeof metric, "%.*s", (int)n, name);
      }
      csv_field(f, metric);
      fprintf(f, ",%.10g,", t->vals[at]);
      if (unit[0]) csv_field(f, unit);
      fputc('\n', f);
    }
}

/* ---- data.json ---- */

static void json_str(FILE *f, const char *s) {
  fputc('"', f);
  for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
    switch (*p) {
      case '"':
        fputs("\\\"", f);
        break;
      case '\\':
        fputs("\\\\", f);
        break;
      case '\n':
        fputs("\\n", f);
        break;
      case '\r':
        fputs("\\r", f);
        break;
      case '\t':
        fputs("\\t", f);
        break;
      default:
        if (*p < 0x20)
          fprintf(f, "\\u%04x", *p);
        else
          fputc(*p, f);
    }
  }
  fputc('"', f);
}

static void json_num(FILE *f, double x) {
  if (isfinite(x))
    fprintf(f, "%.10g", x);
  else
    fputs("null", f);
}

/* "key": "value", on its own line. */
static void json_kv(FILE *f, const char *key, const char *value) {
  fputs("    ", f);
  json_str(f, key);
  fputs(": ", f);
  json_str(f, value);
  fputs(",\n", f);
}

static void json_context(FILE *f, const tb_suite *s) {
  const tb_context *c = &s->ctx;
  fputs("  \"context\": {\n", f);
  json_kv(f, "date", c->date);
  json_kv(f, "host_name", c->host);
  json_kv(f, "executable", s->exe);
  fprintf(f, "    \"num_cpus\": %d,\n    \"mhz_per_cpu\": %d,\n", c->cores, c->mhz);
  fprintf(f, "    \"cpu_scaling_enabled\": %s,\n", c->cpu_scaling ? "true" : "false");
  json_kv(f, "cpu_model", c->cpu);
  fputs("    \"caches\": [", f);
  for (int i = 0; i < c->ncaches; i++) {
    fputs(i ? ",\n      {\"type\": " : "\n      {\"type\": ", f);
    json_str(f, c->caches[i].type);
    fprintf(f, ", \"level\": %d, \"size\": %ld, \"num_sharing\": %d}", c->caches[i].level,
            c->caches[i].size, c->caches[i].num_sharing);
  }
  fputs(c->ncaches ? "\n    ],\n" : "],\n", f);
  if (c->have_load)
    fprintf(f, "    \"load_avg\": [%.2f, %.2f, %.2f],\n", c->load[0], c->load[1], c->load[2]);
  if (c->have_noise && c->noise.known)
    fprintf(f,
            "    \"others_busy_cores\": %.3f,\n    \"steal_share\": %.4f,\n"
            "    \"involuntary_switches_per_s\": %.1f,\n    \"machine_busy\": %s,\n",
            c->noise.others, c->noise.steal, c->noise.switches, c->noise.busy ? "true" : "false");
  else
    fputs("    \"load_avg\": [],\n", f);
  json_kv(f, "library_build_type", c->build_type);
  json_kv(f, "suite", s->name);
  json_kv(f, "title", s->title);
  json_kv(f, "compiler", c->compiler);
  json_kv(f, "flags", c->flags);
  json_kv(f, "git_commit", c->commit);
  fprintf(f, "    \"git_dirty\": %s,\n", c->dirty > 0 ? "true" : c->dirty == 0 ? "false" : "null");
  json_kv(f, "cholmod_version", c->cholmod);
  json_kv(f, "fcl_version", c->fcl);
  json_kv(f, "bullet_version", c->bullet);
  json_kv(f, "cgal_version", c->cgal);
  json_kv(f, "tetgen_version", c->tetgen);
  fprintf(f, "    \"threads\": %d,\n", c->threads);
  fprintf(f, "    \"seed\": %llu\n  },\n", (unsigned long long)c->seed);
}

/* Seconds per unit of "ns", "us", "ms" or "s". */
static double unit_s(const char *unit) {
  return !strcmp(unit, "ns") ? 1e-9 : !strcmp(unit, "us") ? 1e-6 : !strcmp(unit, "ms") ? 1e-3 : 1;
}

/* The file's one time unit: the largest of s, ms, us, ns in which every benchmark's median CPU
 * and wall times are at least 1 (Google Benchmark's compare.py prints whole units). */
static const char *file_unit(const tb_suite *s) {
  static const char *const units[4] = {"s", "ms", "us", "ns"};
  double least = INFINITY;
  for (int i = 0; i < s->nbenches; i++) {
    const tb_results_bench *b = &s->benches[i];
    if (b->n == 0) continue;
    tb_stats a = tb_stats_of(b->real, b->n), c = tb_stats_of(b->cpu, b->n);
    double u = unit_s(b->unit);
    if (a.median > 0) least = fmin(least, a.median * u);
    if (c.median > 0) least = fmin(least, c.median * u);
  }
  for (int k = 0; k < 3; k++)
    if (least >= unit_s(units[k])) return units[k];
  return "ns";
}

/* One "benchmarks" entry in the file's unit; rep >= 0 for an iteration, else an aggregate. */
static void json_entry(FILE *f, const tb_results_bench *b, const char *unit, int family, int rep,
                       const char *agg, double real, double cpu, int last) {
  double scale = unit_s(b->unit) / unit_s(unit);
  real *= scale, cpu *= scale;
  fputs("    {\n      \"name\": ", f);
  if (agg) {
    size_t n = strlen(b->name) + strlen(agg) + 2;
    char *name = malloc(n);
    if (name) snprintf(name, n, "%s_%s", b->name, agg);
    json_str(f, name ? name : b->name);
    free(name);
  } else {
    json_str(f, b->name);
  }
  fprintf(f, ",\n      \"family_index\": %d,\n      \"per_family_instance_index\": 0,\n", family);
  fputs("      \"run_name\": ", f);
  json_str(f, b->name);
  fprintf(f, ",\n      \"run_type\": \"%s\",\n      \"repetitions\": %d,\n",
          agg ? "aggregate" : "iteration", b->n);
  if (agg)
    fprintf(f,
            "      \"threads\": %d,\n      \"aggregate_name\": \"%s\",\n"
            "      \"aggregate_unit\": \"time\",\n      \"iterations\": %d,\n",
            b->threads, agg, b->n);
  else
    fprintf(f,
            "      \"repetition_index\": %d,\n      \"threads\": %d,\n"
            "      \"iterations\": 1,\n",
            rep, b->threads);
  fputs("      \"real_time\": ", f);
  json_num(f, real);
  fputs(",\n      \"cpu_time\": ", f);
  json_num(f, cpu);
  fprintf(f, ",\n      \"time_unit\": \"%s\"", unit);
  int stddev = agg && strcmp(agg, "stddev") == 0; /* counters are constant per benchmark */
  for (int k = 0; k < b->ncounters; k++) {
    fputs(",\n      ", f);
    json_str(f, b->keys[k]);
    fputs(": ", f);
    json_num(f, stddev && isfinite(b->counters[k]) ? 0 : b->counters[k]);
  }
  fprintf(f, "\n    }%s\n", last ? "" : ",");
}

static void json_write(FILE *f, const tb_suite *s) {
  fputs("{\n", f);
  json_context(f, s);
  fputs("  \"benchmarks\": [\n", f);
  const char *u = file_unit(s);
  for (int i = 0; i < s->nbenches; i++) {
    const tb_results_bench *b = &s->benches[i];
    int last = i == s->nbenches - 1;
    if (b->n == 0) { /* counters only: one iteration, no time */
      json_entry(f, b, u, i, 0, NULL, 0, 0, last);
      continue;
    }
    for (int r = 0; r < b->n; r++) json_entry(f, b, u, i, r, NULL, b->real[r], b->cpu[r], 0);
    tb_stats a = tb_stats_of(b->real, b->n), c = tb_stats_of(b->cpu, b->n);
    json_entry(f, b, u, i, -1, "mean", a.mean, c.mean, 0);
    json_entry(f, b, u, i, -1, "median", a.median, c.median, 0);
    json_entry(f, b, u, i, -1, "stddev", a.stddev, c.stddev, 0);
    json_entry(f, b, u, i, -1, "min", a.min, c.min, 0);
    json_entry(f, b, u, i, -1, "max", a.max, c.max, last);
  }
  fputs("  ]\n}\n", f);
}

/* ---- writing them ---- */

static int write_file(tb_suite *s, const char *name, const tb_table *t, int long_form,
                      tb_error *err) {
  char *path = tb_results_join(s->dir, name);
  if (!path) return tb_error_set(err, s->dir, 0, "out of memory");
  FILE *f = fopen(path, "w");
  if (!f) {
    tb_error_set(err, path, 0, "cannot write: %s", strerror(errno));
    free(path);
    return -1;
  }
  if (t && long_form)
    long_write(f, t);
  else if (t)
    csv_write(f, t);
  else if (strcmp(name, "table.md") == 0)
    md_write(f, s);
  else
    json_write(f, s);
  int bad = ferror(f);
  if (fclose(f) != 0 || bad) {
    tb_error_set(err, path, 0, "write failed");
    free(path);
    return -1;
  }
  free(path);
  return 0;
}

/* table-<name>.csv with characters other than letters, digits, '.', '_'
 * and '-' as '-'; the k-th table of an earlier table's name gets -k. */
static void csv_name(const tb_suite *s, int item, char *out, size_t cap) {
  const char *name = s->items[item].table->name;
  int same = 0;
  for (int i = 0; i < item; i++)
    same += s->items[i].kind == TB_ITEM_TABLE && strcmp(s->items[i].table->name, name) == 0;
  int n = snprintf(out, cap, "table-%s", name);
  for (char *p = out + 6; *p; p++)
    if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-", *p)) *p = '-';
  if (n < 0 || (size_t)n >= cap) return;
  if (same)
    snprintf(out + n, cap - (size_t)n, "-%d.csv", same + 1);
  else
    snprintf(out + n, cap - (size_t)n, ".csv");
}

int tb_results_write_files(tb_suite *s, tb_error *err) {
  char *old = tb_results_join(s->dir, "data.csv"); /* the stacked CSV of earlier versions */
  if (old) remove(old);
  free(old);
  if (write_file(s, "table.md", NULL, 0, err)) return -1;
  for (int i = 0; i < s->nitems; i++) {
    if (s->items[i].kind != TB_ITEM_TABLE) continue;
    char name[200], lname[210];
    csv_name(s, i, name, sizeof name);
    csv_check(s, s->items[i].table);
    if (write_file(s, name, s->items[i].table, 0, err)) return -1;
    snprintf(lname, sizeof lname, "%.*s.long.csv", (int)(strlen(name) - 4), name);
    if (write_file(s, lname, s->items[i].table, 1, err)) return -1;
  }
  return write_file(s, "data.json", NULL, 0, err);
}
