/* A suite's sweep split over machines (`reproduce --shard k/N`, `merge`).
 *
 * A suite whose work is a list of independent cases (one model run, one map
 * cell) names each case with a key and keeps its outcome in a tb_case: a
 * few numbers and short texts. Three modes, set for the whole process:
 *   normal  every case runs (TB_CASE_RUN);
 *   shard   the i-th case of the run (counted over every suite, in the order
 *           they ask) runs when i mod N = k - 1, the others are skipped;
 *           tb_suite_end then writes only the outcomes, <dir>/cases.ini;
 *   replay  no case runs: each outcome comes from the shards' cases.ini
 *           (TB_CASE_KNOWN), so the suite's tables, charts and notes come out
 *           of the same code as in a normal run, from the same numbers.
 * A case every shard needs (a reference solution the others compare with)
 * runs on every shard; its first shard's outcome is kept.
 *
 * cases.ini is INI (read with inih): a [case] section per case: key = KEY
 * first (inih cuts long section names, so the key is a value), v0, v1, ...
 * = %a (hexadecimal, so every bit reads back), t0, t1, ... = text, and
 * every = 1 for a case every shard runs. Keys and texts are percent-encoded
 * where INI would read a character otherwise. */
#include <errno.h>
#include <ini.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "results_priv.h"
#include "core/tb_parse.h"

enum { MODE_NORMAL, MODE_SHARD, MODE_REPLAY };

/* One outcome of the replay's book. */
typedef struct book_entry {
  char *folder, *key; /* the suite folder relative to the results root; the case's key */
  int every, shard;
  tb_case c;
} book_entry;

static struct {
  int mode, k, n;
  long counter; /* cases asked for so far in this run (shard mode) */
  char *root;   /* the results folder the suites write under */
  book_entry *book;
  int nbook, cap_book;
} g;

int tb_shard_set(int k, int n, const char *root, tb_error *err) {
  tb_shard_reset();
  if (n < 1 || k < 1 || k > n) return tb_error_set(err, "--shard", 0, "needs k/N with 1 <= k <= N");
  g.root = tb_results_dup(root);
  if (!g.root) return tb_error_set(err, "--shard", 0, "out of memory");
  g.mode = MODE_SHARD, g.k = k, g.n = n;
  return 0;
}

int tb_shard_replay(const char *root, tb_error *err) {
  tb_shard_reset();
  g.root = tb_results_dup(root);
  if (!g.root) return tb_error_set(err, "merge", 0, "out of memory");
  g.mode = MODE_REPLAY;
  return 0;
}

void tb_shard_reset(void) {
  for (int i = 0; i < g.nbook; i++) free(g.book[i].folder), free(g.book[i].key);
  free(g.book);
  free(g.root);
  memset(&g, 0, sizeof g);
}

int tb_shard_active(void) { return g.mode == MODE_SHARD; }

/* ---- percent-encoding: what INI would cut or comment out ---- */

static int plain(unsigned char ch) { return ch > ' ' && ch < 127 && !strchr("%;#[]=\\\"'", ch); }

/* Encodes s into out; -1 when it does not fit. */
static int encode(const char *s, char *out, size_t cap) {
  size_t n = 0;
  for (; *s; s++) {
    unsigned char ch = (unsigned char)*s;
    if (n + 4 > cap) return -1;
    if (plain(ch))
      out[n++] = (char)ch;
    else
      n += (size_t)snprintf(out + n, cap - n, "%%%02X", ch);
  }
  out[n] = 0;
  return 0;
}

static int hexval(char ch) {
  if (ch >= '0' && ch <= '9') return ch - '0';
  if (ch >= 'A' && ch <= 'F') return ch - 'A' + 10;
  if (ch >= 'a' && ch <= 'f') return ch - 'a' + 10;
  return -1;
}

/* Decodes s into out; -1 on a bad escape or when out is too small. */
static int decode(const char *s, char *out, size_t cap) {
  size_t n = 0;
  for (; *s; s++) {
    if (n + 1 >= cap) return -1;
    if (*s != '%') {
      out[n++] = *s;
      continue;
    }
    int hi = hexval(s[1]), lo = hi < 0 ? -1 : hexval(s[2]);
    if (lo < 0) return -1;
    out[n++] = (char)(16 * hi + lo);
    s += 2;
  }
  out[n] = 0;
  return 0;
}

/* ---- the suites' side ---- */

/* The suite folder relative to the results root ("" when outside it). */
static const char *folder_of(const tb_suite *s) {
  size_t n = g.root ? strlen(g.root) : 0;
  if (!n || strncmp(s->dir, g.root, n) || (s->dir[n] && s->dir[n] != '/')) return "";
  const char *rel = s->dir + n;
  while (*rel == '/') rel++;
  return rel;
}

static const book_entry *lookup(const char *folder, const char *key) {
  for (int i = 0; i < g.nbook; i++)
    if (!strcmp(g.book[i].folder, folder) && !strcmp(g.book[i].key, key)) return &g.book[i];
  return NULL;
}

int tb_suite_case(tb_suite *s, const char *key, int every, tb_case *c) {
  memset(c, 0, sizeof *c);
  if (!s) return TB_CASE_SKIP;
  s->case_open = 0;
  char enc[TB_CASE_KEY];
  if (!*key || encode(key, enc, sizeof enc)) {
    tb_results_fail(s, "case \"%.60s\": a key needs 1 to %d plain characters", key,
                    TB_CASE_KEY / 3);
    return TB_CASE_SKIP;
  }
  if (g.mode == MODE_REPLAY) {
    const book_entry *e = lookup(folder_of(s), key);
    if (!e) {
      tb_results_fail(s, "case \"%s\" of %s is in no shard's cases.ini", key, folder_of(s));
      return TB_CASE_SKIP;
    }
    *c = e->c;
    return TB_CASE_KNOWN;
  }
  if (g.mode == MODE_SHARD) {
    s->used_cases = 1;
    long i = every ? -1 : g.counter++;
    if (!every && i % g.n != g.k - 1) return TB_CASE_SKIP;
  }
  if (g.mode == MODE_SHARD) { /* kept for cases.ini; a normal run keeps nothing */
    tb_results_case *sv = tb_results_grow(s->cases, &s->cap_cases, s->ncases + 1, sizeof *sv);
    if (!sv) {
      tb_results_fail(s, "case \"%s\": out of memory", key);
      return TB_CASE_SKIP;
    }
    s->cases = sv;
    snprintf(sv[s->ncases].key, sizeof sv[s->ncases].key, "%s", key);
    sv[s->ncases].every = every;
    sv[s->ncases++].done = 0;
  }
  snprintf(s->case_key, sizeof s->case_key, "%s", key);
  s->case_open = 1;
  return TB_CASE_RUN;
}

void tb_suite_case_done(tb_suite *s, const tb_case *c) {
  if (!s) return;
  if (!s->case_open) {
    if (g.mode != MODE_REPLAY) tb_results_fail(s, "tb_suite_case_done without a case that runs");
    return;
  }
  s->case_open = 0;
  if (c->nv < 0 || c->nv > TB_CASE_VALUES || c->nt < 0 || c->nt > TB_CASE_TEXTS) {
    tb_results_fail(s, "case \"%s\": %d values, %d texts (at most %d, %d)", s->case_key, c->nv,
                    c->nt, TB_CASE_VALUES, TB_CASE_TEXTS);
    return;
  }
  if (g.mode == MODE_SHARD) {
    tb_results_case *sv = &s->cases[s->ncases - 1];
    sv->c = *c;
    sv->done = 1;
  }
}

/* Writes <dir>/cases.ini: the outcomes of the cases that ran here. */
int tb_results_shard_write(tb_suite *s, tb_error *err) {
  char *path = tb_results_join(s->dir, "cases.ini");
  FILE *f = path ? fopen(path, "w") : NULL;
  if (!f) {
    tb_error_set(err, path ? path : s->dir, 0, "cannot write: %s", strerror(errno));
    free(path);
    return -1;
  }
  fprintf(f, "; outcomes of the cases shard %d/%d ran (tissuebench merge reads them)\n", g.k, g.n);
  char buf[3 * (TB_CASE_TEXT > TB_CASE_KEY ? TB_CASE_TEXT : TB_CASE_KEY) + 16];
  for (int i = 0; i < s->ncases; i++) {
    const tb_results_case *sv = &s->cases[i];
    if (!sv->done) {
      tb_results_fail(s, "case \"%s\" ran but was never saved (tb_suite_case_done)", sv->key);
      continue;
    }
    encode(sv->key, buf, sizeof buf);
    fprintf(f, "\n[case]\nkey = %s\n", buf);
    if (sv->every) fprintf(f, "every = 1\n");
    for (int q = 0; q < sv->c.nv; q++) fprintf(f, "v%d = %a\n", q, sv->c.v[q]);
    for (int q = 0; q < sv->c.nt; q++) {
      encode(sv->c.t[q], buf, sizeof buf);
      fprintf(f, "t%d = %s\n", q, buf);
    }
  }
  int bad = ferror(f);
  if (fclose(f) || bad) {
    tb_error_set(err, path, 0, "cannot write: %s", strerror(errno));
    free(path);
    return -1;
  }
  free(path);
  return 0;
}

/* ---- loading the shards' outcomes (replay) ---- */

typedef struct loader {
  const char *path, *folder;
  int shard, failed, line;
  int cur; /* the book entry of the case being read, -1 before the first */
  FILE *f;
  tb_error *err;
} loader;

/* inih's reader: fgets, counting lines for the messages. */
static char *reader(char *str, int num, void *stream) {
  loader *L = stream;
  L->line++;
  return fgets(str, num, L->f);
}

static int fail_at(loader *L, int line, const char *fmt, const char *what) {
  if (!L->failed) tb_error_set(L->err, L->path, line, fmt, what);
  L->failed = 1;
  return 0;
}

/* Adds the entry (folder, key) unless a shard before gave it. */
static book_entry *book_add(loader *L, const char *key, int line) {
  for (int i = 0; i < g.nbook; i++)
    if (!strcmp(g.book[i].folder, L->folder) && !strcmp(g.book[i].key, key)) {
      if (g.book[i].shard == L->shard)
        return fail_at(L, line, "case \"%s\" given twice", key), NULL;
      return &g.book[i]; /* the same case from another shard: checked at its end */
    }
  book_entry *b = tb_results_grow(g.book, &g.cap_book, g.nbook + 1, sizeof *b);
  if (!b) return fail_at(L, line, "%s: out of memory", key), NULL;
  g.book = b;
  book_entry *e = &g.book[g.nbook];
  memset(e, 0, sizeof *e);
  e->folder = tb_results_dup(L->folder), e->key = tb_results_dup(key), e->shard = L->shard;
  if (!e->folder || !e->key) {
    free(e->folder), free(e->key);
    return fail_at(L, line, "%s: out of memory", key), NULL;
  }
  g.nbook++;
  return e;
}

static int handler(void *user, const char *section, const char *name, const char *value) {
  loader *L = user;
  int line = L->line;
  if (L->failed) return 0;
  if (strcmp(section, "case")) return fail_at(L, line, "section [%s]: expected [case]", section);
  if (!strcmp(name, "key")) { /* a case begins */
    char key[TB_CASE_KEY];
    if (decode(value, key, sizeof key) || !key[0])
      return fail_at(L, line, "'%s': not a case's key", value);
    book_entry *e = book_add(L, key, line);
    if (!e) return 0;
    L->cur = (int)(e - g.book);
    return 1;
  }
  if (L->cur < 0) return fail_at(L, line, "'%s' before the case's key", name);
  book_entry *e = &g.book[L->cur];
  const char *key = e->key;
  if (e->shard != L->shard) { /* a second shard's copy of a case */
    if (!e->every) return fail_at(L, line, "case \"%s\" ran on two shards", key);
    return 1; /* every shard ran it: the first shard's is kept */
  }
  char *end;
  if (!strcmp(name, "every")) {
    e->every = !strcmp(value, "1");
    return 1;
  }
  if ((name[0] == 'v' || name[0] == 't') && name[1] >= '0' && name[1] <= '9') {
    long q = strtol(name + 1, &end, 10);
    if (*end || q < 0 || q >= (name[0] == 'v' ? TB_CASE_VALUES : TB_CASE_TEXTS))
      return fail_at(L, line, "'%s': no such field of a case", name);
    if (name[0] == 'v') {
      errno = 0;
      double v = strtod(value, &end);
      if (end == value || *end) return fail_at(L, line, "'%s': not a number", value);
      e->c.v[q] = v;
      if (e->c.nv <= q) e->c.nv = (int)q + 1;
    } else {
      if (decode(value, e->c.t[q], sizeof e->c.t[q]))
        return fail_at(L, line, "'%s': a bad %%-escape or too long", value);
      if (e->c.nt <= q) e->c.nt = (int)q + 1;
    }
    return 1;
  }
  return fail_at(L, line, "'%s': no such field of a case", name);
}

int tb_shard_load(const char *path, const char *folder, int shard, tb_error *err) {
  if (g.mode != MODE_REPLAY) return tb_error_set(err, path, 0, "not replaying shards");
  FILE *f = fopen(path, "r");
  if (!f) return tb_error_set(err, path, 0, "cannot open: %s", strerror(errno));
  loader L = {path, folder, shard, 0, 0, -1, f, err};
  tb_ini_setup();
  int rc = ini_parse_stream(reader, &L, handler, &L);
  fclose(f);
  if (L.failed) return -1;
  if (rc > 0) return tb_error_set(err, path, rc, "not INI syntax");
  if (rc < 0) return tb_error_set(err, path, 0, "cannot read");
  return 0;
}
