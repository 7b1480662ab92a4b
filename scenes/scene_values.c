/* The values of scene files: numbers that may name a scene parameter
 * ("0.5*release"), comma-separated lists of them, node-id lists and id
 * files, node selectors, and the paths a scene names (relative to its
 * folder, or `data:` for ../shared/data). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene_priv.h"
#include "core/tb_paths.h"

/* ---- numbers ---- */

/* "1.5", "amplitude", "0.5*release", "-amplitude". */
int tb_scene_parse_expr(const char *s, tb_expr *e) {
  while (*s == ' ' || *s == '\t') s++;
  char *end;
  errno = 0;
  double k = strtod(s, &end);
  const char *name = s;
  if (end != s) {
    if (errno || !isfinite(k)) return -1;
    while (*end == ' ' || *end == '\t') end++;
    if (!*end) return e->k = k, e->param = -1, 0;
    if (*end != '*') return -1;
    name = end + 1;
  } else {
    k = 1;
    if (*s == '-') k = -1, name = s + 1;
  }
  while (*name == ' ' || *name == '\t') name++;
  size_t n = strcspn(name, " \t");
  char buf[32];
  if (!n || n >= sizeof buf) return -1;
  memcpy(buf, name, n), buf[n] = 0;
  for (const char *p = name + n; *p; p++)
    if (*p != ' ' && *p != '\t') return -1;
  int i = tb_scene_param_index(buf);
  if (i < 0) return -1;
  return e->k = k, e->param = i, 0;
}

/* Comma-separated expressions: exactly n (or between nmin and n); returns the count or -1. */
int tb_scene_parse_list(const char *s, tb_expr *out, int nmin, int n) {
  char buf[512];
  if (strlen(s) >= sizeof buf) return -1;
  strcpy(buf, s);
  int k = 0;
  for (char *tok = buf, *next; tok; tok = next) {
    next = strchr(tok, ',');
    if (next) *next++ = 0;
    if (k == n || tb_scene_parse_expr(tok, &out[k])) return -1;
    k++;
  }
  return k >= nmin ? k : -1;
}

/* ---- selectors ---- */

static int parse_ids(const char *s, int **ids, int *n) {
  int cap = 16;
  *n = 0;
  *ids = malloc(sizeof(int) * (size_t)cap);
  if (!*ids) return -1;
  while (*s) {
    while (*s == ' ' || *s == '\t' || *s == ',' || *s == '\n' || *s == '\r') s++;
    if (!*s) break;
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || errno || v < 0 || v > 2000000000 || (*end && !strchr(" \t,\r\n", *end)))
      return -1;
    if (*n == cap) {
      int *g = realloc(*ids, sizeof(int) * (size_t)(cap *= 2));
      if (!g) return -1;
      *ids = g;
    }
    (*ids)[(*n)++] = (int)v;
    s = end;
  }
  return *n ? 0 : -1;
}

/* An id file: numbers separated by white space or commas, '#' comments. */
static int read_id_file(const char *path, int **ids, int *n, tb_error *err) {
  FILE *f = fopen(path, "r");
  if (!f) return tb_error_set(err, path, 0, "cannot open");
  int cap = 64;
  *n = 0;
  *ids = malloc(sizeof(int) * (size_t)cap);
  char line[4096];
  long ln = 0;
  int rc = *ids ? 0 : tb_error_set(err, path, 0, "out of memory");
  while (!rc && fgets(line, sizeof line, f)) {
    ln++;
    char *c = strchr(line, '#');
    if (c) *c = 0;
    for (char *s = line; *s;) {
      while (*s && strchr(" \t,\r\n", *s)) s++;
      if (!*s) break;
      char *end;
      errno = 0;
      long v = strtol(s, &end, 10);
      if (end == s || errno || v < 0 || v > 2000000000 || (*end && !strchr(" \t,\r\n", *end))) {
        rc = tb_error_set(err, path, ln, "not a node id (a whole number >= 0): '%.*s'",
                          (int)strcspn(s, " \t,\r\n"), s);
        break;
      }
      if (*n == cap) {
        int *g = realloc(*ids, sizeof(int) * (size_t)(cap *= 2));
        if (!g) {
          rc = tb_error_set(err, path, ln, "out of memory");
          break;
        }
        *ids = g;
      }
      (*ids)[(*n)++] = (int)v;
      s = end;
    }
  }
  fclose(f);
  if (!rc && !*n) rc = tb_error_set(err, path, 0, "no node ids in the file");
  return rc;
}

int tb_selector_parse(tb_selector *sel, int kind, const char *value, const char *path, int line,
                      const char *base_dir, tb_error *err) {
  static const int count[] = {0, 6, 6, 6, 4, 4};
  static const char *const what[] = {"",
                                     "x0,y0,z0, x1,y1,z1",
                                     "fx0,fy0,fz0, fx1,fy1,fz1",
                                     "px,py,pz, nx,ny,nz",
                                     "cx,cy,cz, r",
                                     "dx,dy,dz, fraction"};
  memset(sel, 0, sizeof *sel);
  sel->kind = kind, sel->line = line;
  if (kind == TB_SEL_IDS) {
    if (!base_dir) {
      if (parse_ids(value, &sel->ids, &sel->nids)) {
        free(sel->ids), sel->ids = NULL;
        return tb_error_set(err, path, line,
                            "ids: '%s' is not a list of node ids (whole numbers >= 0)", value);
      }
      return 0;
    }
    char full[1024];
    const char *why;
    if (tb_scene_resolve_path(base_dir, value, full, sizeof full, &why))
      return tb_error_set(err, path, line, "id_file '%s': %s", value, why);
    tb_error in = {{0}}; /* the id file's own "FILE:LINE: reason", after the scene's line */
    if (read_id_file(full, &sel->ids, &sel->nids, &in)) {
      free(sel->ids), sel->ids = NULL;
      return tb_error_set(err, path, line, "id_file: %s", in.msg);
    }
    return 0;
  }
  if (tb_scene_parse_list(value, sel->v, count[kind], count[kind]) < 0)
    return tb_error_set(err, path, line, "'%s' is not %s (numbers or scene parameters)", value,
                        what[kind]);
  return 0;
}

/* ---- paths ---- */

int tb_scene_resolve_path(const char *dir, const char *value, char *out, size_t cap,
                          const char **why) {
  const char *prefix = "data:";
  int n;
  *why = NULL;
  if (!strncmp(value, prefix, strlen(prefix))) {
    const char *env = getenv("TB_DATA_DIR");
    char base[900];
    if (env && *env)
      snprintf(base, sizeof base, "%s", env);
    else
      snprintf(base, sizeof base, "%s", tb_shared_data());
    if (access(base, F_OK))
      return *why = "data: names ../shared/data (or $TB_DATA_DIR), which is not present", -1;
    n = snprintf(out, cap, "%s/%s", base, value + strlen(prefix));
  } else if (value[0] == '/' || !dir[0])
    n = snprintf(out, cap, "%s", value);
  else
    n = snprintf(out, cap, "%s/%s", dir, value);
  if (n < 0 || (size_t)n >= cap) return *why = "path too long", -1;
  if (!value[0] || !strcmp(value, prefix)) return *why = "no file named", -1;
  struct stat st;
  if (access(out, R_OK) || stat(out, &st)) return *why = "cannot read the file", -1;
  if (S_ISDIR(st.st_mode)) return *why = "a folder, not a file", -1;
  return 0;
}
