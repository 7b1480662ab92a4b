/* REPORT.md, the one document of a `reproduce` run (tb_report_* in
 * tb_results.h): while a report is open, tb_suite_end hands it each suite's
 * body rendered as markdown (headings one chapter deeper, links prefixed
 * with the suite folder relative to the report, charts as PNG); at the end
 * the report writes its title, the run's context once, which suites ran,
 * failed or were not run, then chapter by chapter the suites in the order
 * they were placed. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "results_priv.h"

/* A finished suite's body, waiting for tb_report_end. */
typedef struct report_section {
  char *folder; /* relative to the report's folder, e.g. "pareto/liver" */
  char *title;
  char *body;
  int used;
} report_section;

/* The layout: chapters and suites in document order. */
typedef struct report_slot {
  int chapter; /* 1: a chapter heading (text, intro); 0: a suite */
  char *text;  /* heading or suite folder */
  char *extra; /* the chapter's intro or the suite's summary */
  int status;
} report_slot;

struct tb_report {
  char *dir;
  char *title;
  tb_context ctx;
  report_section *sections;
  int nsections, cap_sections;
  report_slot *slots;
  int nslots, cap_slots;
  int oom;
};

static tb_report *open_report; /* the one report collecting suites */

tb_report *tb_report_begin(const char *dir, const char *title, uint64_t seed, tb_error *err) {
  if (open_report) {
    tb_error_set(err, dir ? dir : "tb_report_begin", 0, "a report is already open");
    return NULL;
  }
  if (!dir || !*dir) {
    tb_error_set(err, "tb_report_begin", 0, "a report needs a folder");
    return NULL;
  }
  if (tb_results_make_dirs(dir, err)) return NULL;
  tb_report *r = calloc(1, sizeof *r);
  if (r) {
    r->dir = tb_results_dup(dir);
    r->title = tb_results_dup(title && *title ? title : "Report");
  }
  if (!r || !r->dir || !r->title) {
    if (r) free(r->dir), free(r->title);
    free(r);
    tb_error_set(err, dir, 0, "out of memory");
    return NULL;
  }
  size_t n = strlen(r->dir); /* "results/" names the same folder as "results" */
  while (n > 1 && r->dir[n - 1] == '/') r->dir[--n] = 0;
  tb_context_collect(&r->ctx, seed);
  open_report = r;
  return r;
}

/* The suite folder relative to the report's, or NULL when outside it. */
static const char *inside(const tb_report *r, const char *dir) {
  size_t n = strlen(r->dir);
  if (strncmp(dir, r->dir, n) != 0 || dir[n] != '/') return NULL;
  dir += n;
  while (*dir == '/') dir++;
  return *dir ? dir : NULL;
}

static void add_section(tb_report *r, const char *folder, const char *title, char *body);
static void write_section(const char *dir, const char *title, const char *body, tb_report *r);

void tb_results_report_add(const tb_suite *s) {
  tb_report *r = open_report;
  const char *rel = r ? inside(r, s->dir) : NULL;
  if (!rel) return;
  char *prefix = malloc(strlen(rel) + 2);
  char *body = NULL;
  size_t len = 0;
  FILE *f = prefix ? open_memstream(&body, &len) : NULL;
  if (!f) {
    free(body);
    free(prefix);
    r->oom = 1;
    return;
  }
  sprintf(prefix, "%s/", rel);
  tb_results_md_body(f, s, prefix, 4, "png");
  free(prefix);
  int bad = ferror(f);
  if (fclose(f) || bad) {
    free(body);
    r->oom = 1;
    return;
  }
  if (tb_shard_active()) write_section(s->dir, s->title, body, r);
  add_section(r, rel, s->title, body);
}

/* Takes body; r->oom on failure. */
static void add_section(tb_report *r, const char *folder, const char *title, char *body) {
  report_section *ss = tb_results_grow(r->sections, &r->cap_sections, r->nsections + 1, sizeof *ss);
  if (ss) r->sections = ss;
  report_section sec = {tb_results_dup(folder), tb_results_dup(title), body, 0};
  if (!ss || !sec.folder || !sec.title) {
    free(sec.folder), free(sec.title), free(sec.body);
    r->oom = 1;
    return;
  }
  r->sections[r->nsections++] = sec;
}

/* A shard's whole suite: its report body in <dir>/report-section.md (the
 * title, then the body), which `merge` places in the merged report. */
static void write_section(const char *dir, const char *title, const char *body, tb_report *r) {
  char *path = tb_results_join(dir, TB_REPORT_SECTION);
  FILE *f = path ? fopen(path, "w") : NULL;
  int bad = !f;
  if (f) {
    fprintf(f, "%s\n%s", title, body);
    bad = ferror(f) | (fclose(f) != 0);
  }
  if (bad) r->oom = 1;
  free(path);
}

int tb_report_section_file(tb_report *r, const char *path, const char *folder, tb_error *err) {
  if (!r) return tb_error_set(err, path, 0, "no report");
  FILE *f = fopen(path, "r");
  if (!f) return tb_error_set(err, path, 0, "cannot open: %s", strerror(errno));
  char *text = NULL;
  size_t len = 0;
  FILE *m = open_memstream(&text, &len);
  char buf[4096];
  size_t n;
  while (m && (n = fread(buf, 1, sizeof buf, f)) > 0) fwrite(buf, 1, n, m);
  int bad = ferror(f) || !m;
  fclose(f);
  if (m && fclose(m)) bad = 1;
  char *nl = text ? strchr(text, '\n') : NULL;
  if (bad || !nl) {
    free(text);
    return tb_error_set(err, path, 0, bad ? "cannot read" : "no title line");
  }
  *nl = 0;
  char *body = tb_results_dup(nl + 1);
  add_section(r, folder, text, body ? body : tb_results_dup(""));
  free(text);
  return r->oom ? tb_error_set(err, path, 0, "out of memory") : 0;
}

static void add_slot(tb_report *r, int chapter, const char *text, const char *extra, int status) {
  if (!r) return;
  report_slot *sl = tb_results_grow(r->slots, &r->cap_slots, r->nslots + 1, sizeof *sl);
  if (!sl) {
    r->oom = 1;
    return;
  }
  r->slots = sl;
  report_slot s = {chapter, tb_results_dup(text ? text : ""), extra ? tb_results_dup(extra) : NULL,
                   status};
  if (!s.text || (extra && !s.extra)) {
    free(s.text), free(s.extra);
    r->oom = 1;
    return;
  }
  r->slots[r->nslots++] = s;
}

void tb_report_chapter(tb_report *r, const char *heading, const char *intro) {
  add_slot(r, 1, heading, intro, 0);
}

void tb_report_suite(tb_report *r, const char *folder, const char *summary, int status) {
  add_slot(r, 0, folder, summary, status);
}

/* Does section folder f belong to the suite folder name (itself or below)? */
static int belongs(const char *f, const char *name) {
  size_t n = strlen(name);
  return strncmp(f, name, n) == 0 && (f[n] == 0 || f[n] == '/');
}

/* "a, b and c" of the suites with this status. */
static int list_status(FILE *f, const tb_report *r, int status) {
  int n = 0, total = 0;
  for (int i = 0; i < r->nslots; i++) total += !r->slots[i].chapter && r->slots[i].status == status;
  for (int i = 0; i < r->nslots; i++) {
    const report_slot *s = &r->slots[i];
    if (s->chapter || s->status != status) continue;
    fprintf(f, "%s`%s`", n == 0 ? "" : n + 1 == total ? " and " : ", ", s->text);
    n++;
  }
  return n;
}

static void write_report(FILE *f, tb_report *r) {
  fprintf(f, "# %s\n\n", r->title);
  fputs("The run's context (every suite's table.md and data.json record their own):\n\n", f);
  tb_results_md_context(f, &r->ctx);
  int counts[3] = {0, 0, 0};
  for (int i = 0; i < r->nslots; i++)
    if (!r->slots[i].chapter && r->slots[i].status >= 0 && r->slots[i].status <= 2)
      counts[r->slots[i].status]++;
  static const char *const said[3] = {
      "Ran: ", "**Failed** (their results may be partial): ", "Not run this time (`--only`): "};
  for (int k = 0; k < 3; k++) {
    if (!counts[k]) continue;
    fputs(said[k], f);
    list_status(f, r, k);
    fputs(".\n\n", f);
  }
  fputs(
      "Each suite's folder also holds its tables as CSV (units in the headers), "
      "data.json (Google Benchmark's layout) and the charts as SVG.\n\n",
      f);
  for (int i = 0; i < r->nslots; i++) {
    const report_slot *c = &r->slots[i];
    if (c->chapter) { /* shown when one of its suites ran */
      int any = 0;
      for (int j = i + 1; j < r->nslots && !r->slots[j].chapter; j++)
        any |= r->slots[j].status != TB_REPORT_NOT_RUN;
      if (!any) continue;
      fprintf(f, "## %s\n\n", c->text);
      if (c->extra && *c->extra) fprintf(f, "%s\n\n", c->extra);
      continue;
    }
    if (c->status == TB_REPORT_NOT_RUN) continue;
    int found = 0;
    for (int k = 0; k < r->nsections; k++) {
      report_section *sec = &r->sections[k];
      if (sec->used || !belongs(sec->folder, c->text)) continue;
      sec->used = 1;
      found = 1;
      fprintf(f, "### %s: %s\n\n", sec->folder, sec->title);
      if (c->extra && *c->extra) fprintf(f, "*%s.*", c->extra);
      fprintf(f, "%s([table.md](%s/table.md), [data.json](%s/data.json))\n\n",
              c->extra && *c->extra ? " " : "", sec->folder, sec->folder);
      if (c->status == TB_REPORT_FAILED)
        fputs("**This suite failed**: what it wrote is below; see its messages.\n\n", f);
      fputs(sec->body, f);
    }
    if (!found)
      fprintf(f, "### %s\n\n**%s** and wrote no results.\n\n", c->text,
              c->status == TB_REPORT_FAILED ? "This suite failed" : "This suite ran");
  }
  /* Suites in the folder that no slot placed (a caller's omission) */
  for (int k = 0; k < r->nsections; k++) {
    report_section *sec = &r->sections[k];
    if (sec->used) continue;
    fprintf(f, "## %s: %s\n\n([table.md](%s/table.md))\n\n", sec->folder, sec->title, sec->folder);
    fputs(sec->body, f);
  }
}

int tb_report_end(tb_report *r, tb_error *err) {
  if (!r) return tb_error_set(err, "tb_report_end", 0, "no report (tb_report_begin failed?)");
  if (open_report == r) open_report = NULL;
  int rc = 0;
  char *path = tb_results_join(r->dir, "REPORT.md");
  FILE *f = path ? fopen(path, "w") : NULL;
  if (!path)
    rc = tb_error_set(err, r->dir, 0, "out of memory");
  else if (!f)
    rc = tb_error_set(err, path, 0, "cannot write: %s", strerror(errno));
  else {
    write_report(f, r);
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) rc = tb_error_set(err, path, 0, "write failed");
  }
  if (!rc && r->oom) rc = tb_error_set(err, path, 0, "out of memory: some suites are missing");
  free(path);
  for (int k = 0; k < r->nsections; k++)
    free(r->sections[k].folder), free(r->sections[k].title), free(r->sections[k].body);
  for (int i = 0; i < r->nslots; i++) free(r->slots[i].text), free(r->slots[i].extra);
  free(r->sections);
  free(r->slots);
  free(r->dir);
  free(r->title);
  free(r);
  return rc;
}
