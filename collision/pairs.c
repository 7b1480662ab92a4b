/* Reading and writing triangle pairs: the `tritri` line format and the JGT
 * Shen-2003 benchmark files. Every malformed line is an error with its
 * file and line; coordinates must be finite. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_pairs.h"

int tb_pairs_add(tb_pairset *set, const tb_tripair *pair, int expect) {
  if (set->n == set->cap) {
    int cap = set->cap ? 2 * set->cap : 64;
    tb_tripair *p = realloc(set->pairs, sizeof *p * (size_t)cap);
    if (p) set->pairs = p;
    signed char *e = realloc(set->expect, (size_t)cap);
    if (e) set->expect = e;
    char **l = realloc(set->labels, sizeof *l * (size_t)cap);
    if (l) set->labels = l;
    if (!p || !e || !l) return -1;
    set->cap = cap;
  }
  set->pairs[set->n] = *pair;
  set->expect[set->n] = (signed char)expect;
  set->labels[set->n] = NULL;
  set->n++;
  return 0;
}

void tb_pairs_free(tb_pairset *set) {
  for (int i = 0; i < set->n; i++) free(set->labels[i]);
  free(set->pairs), free(set->expect), free(set->labels);
  memset(set, 0, sizeof *set);
}

/* Parses the next number of *s; 0 on success, else a reason. */
static const char *next_number(char **s, double *out) {
  while (**s == ' ' || **s == '\t' || **s == '\r' || **s == ',') (*s)++;
  if (!**s || **s == '\n' || **s == '#') return "expected 18 numbers per line";
  char *end;
  errno = 0;
  double v = strtod(*s, &end);
  if (end == *s) return "not a number";
  if (*end && !strchr(" \t\r\n,#", *end)) return "not a number";
  if (!isfinite(v) || (errno == ERANGE && fabs(v) > 1.0)) return "coordinate is not finite";
  *s = end;
  *out = v;
  return NULL;
}

/* The "# expect=E label" comment, if any, after position s. */
static int parse_expect(const char *s, char **label) {
  const char *h = strchr(s, '#');
  *label = NULL;
  if (!h) return -1;
  const char *e = strstr(h, "expect=");
  if (!e || (e[7] != '0' && e[7] != '1')) return -1;
  const char *l = e + 8;
  while (*l == ' ') l++;
  size_t n = strcspn(l, "\r\n");
  *label = malloc(n + 1);
  if (*label) memcpy(*label, l, n), (*label)[n] = 0;
  return e[7] - '0';
}

int tb_pairs_read(FILE *f, const char *name, tb_pairset *set, tb_error *err) {
  memset(set, 0, sizeof *set);
  char *line = NULL;
  size_t cap = 0;
  long lineno = 0;
  int rc = 0;
  ssize_t got;
  while ((got = getline(&line, &cap, f)) >= 0) {
    lineno++;
    if (memchr(line, 0, (size_t)got)) { /* would cut the line short unseen */
      rc = tb_error_set(err, name, lineno, "NUL byte in the line (a binary file?)");
      break;
    }
    char *s = line;
    while (*s == ' ' || *s == '\t' || *s == '\r') s++;
    if (!*s || *s == '\n' || *s == '#') continue;
    double v[18];
    const char *why = NULL;
    for (int k = 0; k < 18 && !why; k++) why = next_number(&s, &v[k]);
    while (!why && (*s == ' ' || *s == '\t' || *s == '\r' || *s == ',')) s++;
    if (!why && *s && *s != '\n' && *s != '#') why = "more than 18 numbers on the line";
    if (why) {
      rc = tb_error_set(err, name, lineno, "%s", why);
      break;
    }
    tb_tripair pr;
    for (int k = 0; k < 3; k++) {
      pr.p[k] = tb_v3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
      pr.q[k] = tb_v3(v[9 + 3 * k], v[10 + 3 * k], v[11 + 3 * k]);
    }
    char *label;
    int expect = parse_expect(s, &label);
    if (tb_pairs_add(set, &pr, expect)) {
      free(label);
      rc = tb_error_set(err, name, lineno, "out of memory");
      break;
    }
    set->labels[set->n - 1] = label;
  }
  if (!rc && ferror(f)) rc = tb_error_set(err, name, lineno, "read error");
  free(line);
  if (rc) tb_pairs_free(set);
  return rc;
}

int tb_pairs_read_file(const char *path, tb_pairset *set, tb_error *err) {
  memset(set, 0, sizeof *set);
  FILE *f = fopen(path, "r");
  if (!f) return tb_error_set(err, path, 0, "cannot open: %s", strerror(errno));
  int rc = tb_pairs_read(f, path, set, err);
  fclose(f);
  return rc;
}

int tb_pairs_read_jgt(const char *path, int label, tb_pairset *set, tb_error *err) {
  memset(set, 0, sizeof *set);
  FILE *f = fopen(path, "r");
  if (!f) return tb_error_set(err, path, 0, "cannot open: %s", strerror(errno));
  char *line = NULL;
  size_t cap = 0;
  long lineno = 0;
  int rc = 0, k = 0;
  tb_vec3 v[6];
  ssize_t got;
  while ((got = getline(&line, &cap, f)) >= 0) {
    lineno++;
    if (memchr(line, 0, (size_t)got)) {
      rc = tb_error_set(err, path, lineno, "NUL byte in the line (a binary file?)");
      break;
    }
    char *s = line;
    while (*s == ' ' || *s == '\t' || *s == '\r') s++;
    if (!*s || *s == '\n') continue;
    double c[3];
    const char *why = NULL;
    for (int j = 0; j < 3 && !why; j++) why = next_number(&s, &c[j]);
    while (!why && (*s == ' ' || *s == '\t' || *s == '\r')) s++;
    if (!why && *s && *s != '\n') why = "expected 3 numbers per line";
    if (why) {
      rc = tb_error_set(err, path, lineno, "%s", why);
      break;
    }
    v[k++] = tb_v3(c[0], c[1], c[2]);
    if (k == 6) {
      tb_tripair pr = {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
      if (tb_pairs_add(set, &pr, label)) {
        rc = tb_error_set(err, path, lineno, "out of memory");
        break;
      }
      k = 0;
    }
  }
  if (!rc && k) rc = tb_error_set(err, path, lineno, "truncated: a pair needs 6 lines");
  free(line);
  fclose(f);
  if (rc) tb_pairs_free(set);
  return rc;
}

int tb_pairs_read_jgt_dir(const char *dir, tb_pairset *in, tb_pairset *sep, tb_error *err) {
  char a[1024], b[1024];
  memset(sep, 0, sizeof *sep);
  if (snprintf(a, sizeof a, "%s/intersected.txt", dir) >= (int)sizeof a ||
      snprintf(b, sizeof b, "%s/separated.txt", dir) >= (int)sizeof b) {
    memset(in, 0, sizeof *in);
    return tb_error_set(err, dir, 0, "path too long");
  }
  FILE *probe = fopen(a, "r");
  if (!probe) {
    memset(in, 0, sizeof *in);
    tb_error_set(err, a, 0, "absent");
    return 1;
  }
  fclose(probe);
  if (tb_pairs_read_jgt(a, 1, in, err)) return -1;
  if (tb_pairs_read_jgt(b, 0, sep, err)) {
    tb_pairs_free(in);
    return -1;
  }
  return 0;
}

void tb_pairs_write_line(FILE *f, const tb_tripair *pr) {
  const tb_vec3 *v[6] = {&pr->p[0], &pr->p[1], &pr->p[2], &pr->q[0], &pr->q[1], &pr->q[2]};
  for (int i = 0; i < 6; i++) fprintf(f, "%s%a %a %a", i ? "  " : "", v[i]->x, v[i]->y, v[i]->z);
  fputc('\n', f);
}
