/* Data files and charts of a suite run: tb_suite_write_data writes a CSV
 * for gnuplot into the suite folder; tb_suite_chart runs
 * `gnuplot -e "datafile='...'; outbase='...'; suitedir='.../'" scripts/<script>`
 * (suitedir: the suite folder, for the other files a script reads; posix_spawnp,
 * its output captured for the error message) and checks that <outbase>.png
 * and .svg were written. */
#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "results_priv.h"
#include "core/tb_paths.h"

extern char **environ;

/* A file name inside the suite folder: not empty, not absolute, no "..". */
static int safe_name(const char *s) { return s && *s && s[0] != '/' && !strstr(s, ".."); }

/* ---- data files ---- */

static FILE *open_out(const char *path, tb_error *err) {
  FILE *f = fopen(path, "w");
  if (!f) tb_error_set(err, path, 0, "cannot write: %s", strerror(errno));
  return f;
}

static int close_out(FILE *f, const char *path, tb_error *err) {
  int bad = ferror(f);
  if (fclose(f) != 0 || bad) return tb_error_set(err, path, 0, "write failed");
  return 0;
}

int tb_suite_write_data(tb_suite *s, const char *csv_name, const char *header, const char *body,
                        tb_error *err) {
  if (!s || !safe_name(csv_name))
    return tb_error_set(err, csv_name ? csv_name : "(null)", 0,
                        "a data file needs a suite and a relative name without \"..\"");
  if (tb_results_partial(s)) return 0; /* a shard: the merge writes it */
  char *path = tb_results_join(s->dir, csv_name);
  if (!path) return tb_error_set(err, csv_name, 0, "out of memory");
  FILE *f = open_out(path, err);
  int rc = -1;
  if (f) {
    size_t n = body ? strlen(body) : 0;
    fprintf(f, "%s\n%s%s", header ? header : "", body ? body : "",
            n && body[n - 1] != '\n' ? "\n" : "");
    rc = close_out(f, path, err);
  }
  free(path);
  return rc;
}

/* ---- charts ---- */

/* Quotes a gnuplot single-quoted string ('' stands for '). */
static void gp_quote(char *out, size_t cap, const char *s) {
  size_t k = 0;
  out[k++] = '\'';
  for (; *s && k + 3 < cap; s++) {
    if (*s == '\'') out[k++] = '\'';
    out[k++] = *s;
  }
  out[k++] = '\'';
  out[k] = 0;
}

static long file_size(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0 && S_ISREG(sb.st_mode) ? (long)sb.st_size : -1;
}

/* Runs gnuplot -e expr script; its stdout and stderr go to out. Returns the
 * exit status, or -1 with out explaining why it could not run. */
static int run_gnuplot(const char *expr, const char *script, char *out, size_t cap) {
  int fd[2];
  out[0] = 0;
  if (pipe(fd) != 0) return snprintf(out, cap, "pipe: %s", strerror(errno)), -1;
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&fa, fd[1], 1);
  posix_spawn_file_actions_adddup2(&fa, fd[1], 2);
  posix_spawn_file_actions_addclose(&fa, fd[0]);
  posix_spawn_file_actions_addclose(&fa, fd[1]);
  char *argv[] = {"gnuplot", "-e", (char *)expr, (char *)script, NULL};
  pid_t pid;
  fflush(NULL);
  int e = posix_spawnp(&pid, "gnuplot", &fa, NULL, argv, environ);
  posix_spawn_file_actions_destroy(&fa);
  close(fd[1]);
  if (e != 0) {
    close(fd[0]);
    snprintf(out, cap, "cannot run gnuplot (%s); install gnuplot-nox", strerror(e));
    return -1;
  }
  size_t n = 0;
  char buf[512];
  ssize_t got;
  while ((got = read(fd[0], buf, sizeof buf)) != 0) {
    if (got < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (ssize_t i = 0; i < got && n + 1 < cap; i++) out[n++] = buf[i];
  }
  out[n] = 0;
  close(fd[0]);
  int st;
  while (waitpid(pid, &st, 0) < 0)
    if (errno != EINTR) return snprintf(out, cap, "waitpid: %s", strerror(errno)), -1;
  if (WIFEXITED(st) && WEXITSTATUS(st) == 127 && !out[0])
    snprintf(out, cap, "cannot run gnuplot; install gnuplot-nox");
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
}

int tb_suite_chart_vars(tb_suite *s, const char *script, const char *datafile, const char *outbase,
                        const char *vars, tb_error *err) {
  if (!s || !script || !*script || strchr(script, '/') || !safe_name(datafile) ||
      !safe_name(outbase))
    return tb_error_set(err, script ? script : "(null)", 0,
                        "a chart needs a suite, a script in scripts/ and relative file names");
  if (tb_results_partial(s)) return 0;
  char spath[1024], data[1024], base[1024], png[1100], svg[1100];
  snprintf(spath, sizeof spath, "%s/scripts/%s", tb_root(), script);
  snprintf(data, sizeof data, "%s/%s", s->dir, datafile);
  snprintf(base, sizeof base, "%s/%s", s->dir, outbase);
  snprintf(png, sizeof png, "%s.png", base);
  snprintf(svg, sizeof svg, "%s.svg", base);
  if (access(spath, R_OK) != 0) return tb_error_set(err, spath, 0, "no such gnuplot script");
  if (file_size(data) < 0) return tb_error_set(err, data, 0, "chart data file not found");
  remove(png);
  remove(svg);

  size_t cap = strlen(vars ? vars : "") + 3 * (sizeof data + sizeof base) + 64;
  char *expr = malloc(cap), qdata[2100], qbase[2100], sdir[1100], qdir[2300];
  if (!expr) return tb_error_set(err, spath, 0, "out of memory");
  gp_quote(qdata, sizeof qdata, data);
  gp_quote(qbase, sizeof qbase, base);
  snprintf(sdir, sizeof sdir, "%s/", s->dir);
  gp_quote(qdir, sizeof qdir, sdir);
  snprintf(expr, cap, "datafile=%s; outbase=%s; suitedir=%s%s%s", qdata, qbase, qdir,
           vars && *vars ? "; " : "", vars ? vars : "");
  char out[1024];
  int st = run_gnuplot(expr, spath, out, sizeof out);
  free(expr);
  if (st != 0) { /* gnuplot's message on one line, runs of blanks squeezed */
    size_t k = 0;
    for (const char *p = out; *p; p++)
      if (!strchr(" \t\r\n", *p))
        out[k++] = *p;
      else if (k > 0 && out[k - 1] != ' ')
        out[k++] = ' ';
    while (k > 0 && out[k - 1] == ' ') k--;
    out[k] = 0;
    return tb_error_set(err, spath, 0, "gnuplot failed%s%s", out[0] ? ": " : "", out);
  }
  if (file_size(png) <= 0 || file_size(svg) <= 0)
    return tb_error_set(err, spath, 0, "gnuplot wrote no %s.png or .svg", outbase);
  char *text = tb_results_dup(outbase);
  if (!text || tb_results_add(s, TB_ITEM_CHART, text, NULL)) {
    free(text);
    tb_results_fail(s, "chart %s: out of memory", outbase);
  }
  return 0;
}

int tb_suite_chart(tb_suite *s, const char *script, const char *datafile, const char *outbase,
                   tb_error *err) {
  return tb_suite_chart_vars(s, script, datafile, outbase, NULL, err);
}
