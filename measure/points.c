/* The points file (points.csv): one row per measured run of `figure pareto`
 * (suites/suite_pareto.c writes it, `advise` reads it): measure/tb_points.h. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_points.h"

#define NFIELDS 13

/* ---- the points file ---- */

static void clean(char *dst, size_t cap, const char *src) {
  snprintf(dst, cap, "%s", src);
  for (char *p = dst; *p; p++)
    if (*p == ',' || *p == '\n' || *p == '\r') *p = ';';
}

static int num(char *buf, int cap, double v) {
  return isfinite(v) ? snprintf(buf, (size_t)cap, "%.6g", v) : snprintf(buf, (size_t)cap, "nan");
}

int tb_point_format(const tb_point *p, char *buf, int cap) {
  char model[32], params[160], state[192], v[8][32];
  clean(model, sizeof model, p->model);
  clean(params, sizeof params, p->params);
  clean(state, sizeof state, p->state);
  /* a time of 0 is no measurement (tb_points_read refuses it): written as nan */
  const double vals[8] = {p->steps_per_s,   p->ms_step > 0 ? p->ms_step : NAN,
                          p->rms_err,       p->max_err,
                          p->volume_change, p->reaction_err,
                          p->settle_time,   p->recovery_err};
  for (int k = 0; k < 8; k++) num(v[k], 32, vals[k]);
  return snprintf(buf, (size_t)cap, "%s,%d,%d,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s", model, p->resolution,
                  p->nodes, params, v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], state);
}

static int parse_num(const char *s, double *out) {
  char *end;
  errno = 0;
  if (!strcmp(s, "nan") || !strcmp(s, "-")) return *out = NAN, 0;
  *out = strtod(s, &end);
  return *s && !*end && errno != ERANGE ? 0 : -1;
}

static int parse_line(char *line, tb_point *p, const char *path, long ln, tb_error *err) {
  char *f[NFIELDS];
  int n = 0;
  for (char *s = line;;) {
    if (n == NFIELDS) return tb_error_set(err, path, ln, "more than %d fields", NFIELDS);
    f[n++] = s;
    char *c = strchr(s, ',');
    if (!c) break;
    *c = 0, s = c + 1;
  }
  if (n != NFIELDS) return tb_error_set(err, path, ln, "%d fields, expected %d", n, NFIELDS);
  memset(p, 0, sizeof *p);
  p->line = (int)ln;
  if (!*f[0] || strlen(f[0]) >= sizeof p->model)
    return tb_error_set(err, path, ln, "bad model name '%s'", f[0]);
  strcpy(p->model, f[0]);
  double r, nd;
  if (parse_num(f[1], &r) || r != floor(r) || r < 0 || r > 1e9 || parse_num(f[2], &nd) ||
      nd != floor(nd) || nd < 0 || nd > 1e9)
    return tb_error_set(err, path, ln, "resolution and nodes must be whole numbers");
  p->resolution = (int)r, p->nodes = (int)nd;
  snprintf(p->params, sizeof p->params, "%s", f[3]);
  double *vals[8] = {&p->steps_per_s,   &p->ms_step,      &p->rms_err,     &p->max_err,
                     &p->volume_change, &p->reaction_err, &p->settle_time, &p->recovery_err};
  static const char *names[8] = {"steps/s",         "ms/step",       "rms error",
                                 "max error",       "volume change", "reaction error",
                                 "settle time (s)", "recovery error"};
  /* What each value may be besides nan (not measured): speeds and times > 0,
   * errors and the settle time >= 0, the volume change any sign (an inverted
   * mesh's is below -1); all finite. */
  static const char *const why[8] = {"must be > 0",  "must be > 0",    "must be >= 0",
                                     "must be >= 0", "must be finite", "must be >= 0",
                                     "must be >= 0", "must be >= 0"};
  for (int k = 0; k < 8; k++) {
    if (parse_num(f[4 + k], vals[k]))
      return tb_error_set(err, path, ln, "%s: '%s' is not a number", names[k], f[4 + k]);
    double x = *vals[k];
    if (isnan(x)) continue;
    int ok = isfinite(x) && (k < 2 ? x > 0 : k == 4 || x >= 0);
    if (!ok)
      return tb_error_set(err, path, ln, "%s: '%s' %s (finite; nan when not measured)", names[k],
                          f[4 + k], why[k]);
  }
  /* one measurement in two units: steps/s = 1000 / (ms/step), within 1% (3 digits);
   * both nan when the run has no measured step */
  if (isnan(p->steps_per_s) != isnan(p->ms_step) ||
      (!isnan(p->ms_step) && fabs(p->steps_per_s * p->ms_step / 1e3 - 1) > 1e-2))
    return tb_error_set(err, path, ln, "steps/s %s and ms/step %s disagree (steps/s = 1000 / ms)",
                        f[4], f[5]);
  if (!*f[12]) return tb_error_set(err, path, ln, "empty state");
  snprintf(p->state, sizeof p->state, "%s", f[12]);
  return 0;
}

int tb_points_read(const char *path, tb_point **out, int *n, tb_error *err) {
  *out = NULL, *n = 0;
  FILE *fp = fopen(path, "r");
  if (!fp) return tb_error_set(err, path, 0, "cannot read: %s", strerror(errno));
  char *line = NULL;
  size_t linecap = 0;
  ssize_t got;
  long ln = 0;
  int cap = 0, rc = 0;
  tb_point *pts = NULL;
  while ((got = getline(&line, &linecap, fp)) >= 0) {
    ln++;
    size_t len = (size_t)got;
    if (memchr(line, 0, len)) {
      rc = tb_error_set(err, path, ln, "NUL byte in the line (a binary file?)");
      break;
    }
    if (len > 4096) {
      rc = tb_error_set(err, path, ln, "line too long (over 4096 bytes)");
      break;
    }
    while (len && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = 0;
    if (ln == 1) {
      if (strcmp(line, TB_POINTS_HEADER)) {
        rc = tb_error_set(err, path, ln, "not a points file (expected the header \"%s\")",
                          TB_POINTS_HEADER);
        break;
      }
      continue;
    }
    if (!len) continue;
    if (*n == cap) {
      cap = cap ? 2 * cap : 64;
      tb_point *q = realloc(pts, sizeof *pts * (size_t)cap);
      if (!q) {
        rc = tb_error_set(err, path, ln, "out of memory");
        break;
      }
      pts = q;
    }
    if ((rc = parse_line(line, &pts[*n], path, ln, err))) break;
    (*n)++;
  }
  if (!rc && ferror(fp)) rc = tb_error_set(err, path, ln, "read error");
  if (!rc && ln == 0) rc = tb_error_set(err, path, 0, "empty file (no header)");
  free(line);
  fclose(fp);
  if (rc) {
    free(pts);
    *n = 0;
    return -1;
  }
  *out = pts;
  return 0;
}

int tb_point_usable(const tb_point *p) {
  return !strcmp(p->state, "settled") && isfinite(p->rms_err) && isfinite(p->steps_per_s) &&
         p->steps_per_s > 0 && isfinite(p->ms_step);
}
