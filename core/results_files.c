/* The three files of a suite run: table.md (GitHub markdown: title, the
 * run's context, then notes, tables and charts in the order added), data.csv
 * (RFC 4180 quoting; a "table" column naming each row's table, then the
 * union of all tables' columns) and data.json in Google Benchmark's JSON
 * layout ("context" plus "benchmarks": one "iteration" entry per repetition,
 * then mean/median/stddev/min/max "aggregate" entries; min and max are our
 * extension to its mean/median/stddev). */
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

static void md_table(FILE *f, const tb_table *t) {
  fprintf(f, "## %s\n\n|", t->title[0] ? t->title : t->name);
  for (int j = 0; j < t->ncols; j++) {
    fputc(' ', f);
    md_cell(f, t->cols[j]);
    fputs(" |", f);
  }
  fputs("\n|", f);
  for (int j = 0; j < t->ncols; j++) { /* numbers align right */
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
      fputc(' ', f);
      md_cell(f, tb_results_cell(t, r, j));
      fputs(" |", f);
    }
    fputc('\n', f);
  }
  fputc('\n', f);
}

static void md_write(FILE *f, const tb_suite *s) {
  const tb_context *c = &s->ctx;
  fprintf(f, "# %s\n\n", s->title);
  fprintf(f, "- **Date**: %s\n", c->date);
  fprintf(f, "- **Host**: %s\n", c->host);
  fprintf(f, "- **CPU**: %s, %d cores", c->cpu, c->cores);
  if (c->mhz > 0) fprintf(f, ", %d MHz", c->mhz);
  fprintf(f, "\n- **Compiler**: %s, %s\n", c->compiler, c->flags);
  fprintf(f, "- **Commit**: %s%s\n", c->commit,
          c->dirty > 0    ? " (dirty)"
          : c->dirty == 0 ? " (clean)"
                          : "");
  fprintf(f, "- **Versions**: CHOLMOD %s, FCL %s, Bullet %s (double), CGAL %s, TetGen %s\n",
          c->cholmod, c->fcl, c->bullet, c->cgal, c->tetgen);
  fprintf(f, "- **Seed**: %llu\n\n", (unsigned long long)c->seed);
  for (int i = 0; i < s->nitems; i++) {
    const tb_results_item *it = &s->items[i];
    if (it->kind == TB_ITEM_NOTE)
      fprintf(f, "%s\n\n", it->text);
    else if (it->kind == TB_ITEM_TABLE)
      md_table(f, it->table);
    else
      fprintf(f, "![%s](%s.svg)\n\n", it->text, it->text);
  }
}

/* ---- data.csv ---- */

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

/* The header is "table" then the union of all tables' columns in order of
 * first appearance; a table using the same name twice gets two columns. */
static int csv_write(FILE *f, const tb_suite *s) {
  const char **uni = NULL;
  int nuni = 0, cap = 0, rc = 0;
  int *map = NULL, map_cap = 0;
  for (int pass = 0; pass < 2 && !rc; pass++) {
    if (pass == 1) {
      fputs("table", f);
      for (int k = 0; k < nuni; k++) {
        fputc(',', f);
        csv_field(f, uni[k]);
      }
      fputc('\n', f);
    }
    for (int i = 0; i < s->nitems && !rc; i++) {
      const tb_table *t = s->items[i].table;
      if (s->items[i].kind != TB_ITEM_TABLE) continue;
      int *m = tb_results_grow(map, &map_cap, t->ncols, sizeof *m);
      if (!m) {
        rc = -1;
        break;
      }
      map = m;
      for (int j = 0; j < t->ncols && !rc; j++) { /* the occ-th column of this name */
        int occ = 0, seen = 0;
        for (int q = 0; q < j; q++) occ += strcmp(t->cols[q], t->cols[j]) == 0;
        map[j] = -1;
        for (int k = 0; k < nuni && map[j] < 0; k++)
          if (strcmp(uni[k], t->cols[j]) == 0 && seen++ == occ) map[j] = k;
        if (map[j] >= 0) continue;
        const char **u = tb_results_grow(uni, &cap, nuni + 1, sizeof *u);
        if (!u)
          rc = -1;
        else {
          uni = u;
          uni[nuni] = t->cols[j];
          map[j] = nuni++;
        }
      }
      for (int r = 0; pass == 1 && r < t->nrows; r++) {
        csv_field(f, t->name);
        for (int k = 0; k < nuni; k++) {
          const char *v = "";
          for (int j = 0; j < t->ncols; j++)
            if (map[j] == k) v = tb_results_cell(t, r, j);
          fputc(',', f);
          csv_field(f, v);
        }
        fputc('\n', f);
      }
    }
  }
  free(uni);
  free(map);
  return rc;
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
  json_kv(f, "cpu_model", c->cpu);
  fputs("    \"caches\": [],\n", f);
  double load[3];
  if (getloadavg(load, 3) == 3)
    fprintf(f, "    \"load_avg\": [%.2f, %.2f, %.2f],\n", load[0], load[1], load[2]);
  json_kv(f, "library_build_type", strstr(c->flags, "buildtype=release") ? "release" : "debug");
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
  fprintf(f, "    \"seed\": %llu\n  },\n", (unsigned long long)c->seed);
}

/* One "benchmarks" entry; rep >= 0 for an iteration, else an aggregate. */
static void json_entry(FILE *f, const tb_results_bench *b, int family, int rep, const char *agg,
                       double real, double cpu, int last) {
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
            "      \"threads\": 1,\n      \"aggregate_name\": \"%s\",\n"
            "      \"aggregate_unit\": \"time\",\n      \"iterations\": %d,\n",
            agg, b->n);
  else
    fprintf(f,
            "      \"repetition_index\": %d,\n      \"threads\": 1,\n"
            "      \"iterations\": 1,\n",
            rep);
  fputs("      \"real_time\": ", f);
  json_num(f, real);
  fputs(",\n      \"cpu_time\": ", f);
  json_num(f, cpu);
  fprintf(f, ",\n      \"time_unit\": \"%s\"\n    }%s\n", b->unit, last ? "" : ",");
}

static void json_write(FILE *f, const tb_suite *s) {
  fputs("{\n", f);
  json_context(f, s);
  fputs("  \"benchmarks\": [\n", f);
  for (int i = 0; i < s->nbenches; i++) {
    const tb_results_bench *b = &s->benches[i];
    for (int r = 0; r < b->n; r++) json_entry(f, b, i, r, NULL, b->real[r], b->cpu[r], 0);
    tb_stats a = tb_stats_of(b->real, b->n), c = tb_stats_of(b->cpu, b->n);
    int last = i == s->nbenches - 1;
    json_entry(f, b, i, -1, "mean", a.mean, c.mean, 0);
    json_entry(f, b, i, -1, "median", a.median, c.median, 0);
    json_entry(f, b, i, -1, "stddev", a.stddev, c.stddev, 0);
    json_entry(f, b, i, -1, "min", a.min, c.min, 0);
    json_entry(f, b, i, -1, "max", a.max, c.max, last);
  }
  fputs("  ]\n}\n", f);
}

/* ---- writing them ---- */

int tb_results_write_files(tb_suite *s, tb_error *err) {
  static const char *const names[3] = {"table.md", "data.csv", "data.json"};
  for (int k = 0; k < 3; k++) {
    char *path = tb_results_join(s->dir, names[k]);
    if (!path) return tb_error_set(err, s->dir, 0, "out of memory");
    FILE *f = fopen(path, "w");
    if (!f) {
      tb_error_set(err, path, 0, "cannot write: %s", strerror(errno));
      free(path);
      return -1;
    }
    if (k == 0) md_write(f, s);
    if (k == 1 && csv_write(f, s)) tb_results_fail(s, "data.csv: out of memory");
    if (k == 2) json_write(f, s);
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
      tb_error_set(err, path, 0, "write failed");
      free(path);
      return -1;
    }
    free(path);
  }
  return 0;
}
