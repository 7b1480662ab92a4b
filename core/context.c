/* The run's context recorded beside every result: UTC date, host, CPU model
 * and clock (/proc/cpuinfo), online cores, compiler and flags (defines set by
 * meson), git commit and dirty flag of the source tree, dependency versions
 * (reference/versions.cpp) and the seed. Fields that cannot be read say
 * "unknown" (numbers 0, dirty -1); git's own errors are not shown, and
 * --no-optional-locks keeps `git status` from touching the index. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "tb_results.h"
#include "tb_versions.h"

#ifndef TB_SOURCE_ROOT
#define TB_SOURCE_ROOT "."
#endif
#ifndef TB_COMPILER
#define TB_COMPILER "unknown"
#endif
#ifndef TB_BUILD_FLAGS
#define TB_BUILD_FLAGS "unknown"
#endif

static void copy(char *dst, size_t cap, const char *src) {
  snprintf(dst, cap, "%s", src && *src ? src : "unknown");
}

/* Trims trailing white space in place. */
static void rtrim(char *s) {
  size_t n = strlen(s);
  while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\n' || s[n - 1] == '\r'))
    s[--n] = 0;
}

/* Value of the first "key : value" line of /proc/cpuinfo whose key starts
 * with `key`; 0 when absent. */
static int cpuinfo(const char *key, char *out, size_t cap) {
  FILE *f = fopen("/proc/cpuinfo", "r");
  if (!f) return 0;
  char line[512];
  int found = 0;
  while (!found && fgets(line, sizeof line, f)) {
    char *colon = strchr(line, ':');
    if (!colon || strncmp(line, key, strlen(key)) != 0) continue;
    const char *v = colon + 1;
    while (*v == ' ' || *v == '\t') v++;
    snprintf(out, cap, "%s", v);
    rtrim(out);
    found = out[0] != 0;
  }
  fclose(f);
  return found;
}

/* Runs `git -C <source root> <args>` with stderr discarded; returns its exit
 * status (-1 when it could not run) and its stdout in out. */
static int git(const char *args, char *out, size_t cap) {
  char cmd[1400], root[1024];
  size_t k = 0;
  root[k++] = '\'';
  for (const char *p = TB_SOURCE_ROOT; *p && k + 6 < sizeof root; p++) {
    if (*p == '\'') {
      memcpy(root + k, "'\\''", 4);
      k += 4;
    } else {
      root[k++] = *p;
    }
  }
  root[k++] = '\'';
  root[k] = 0;
  snprintf(cmd, sizeof cmd, "git -C %s %s 2>/dev/null </dev/null", root, args);
  fflush(NULL);
  FILE *p = popen(cmd, "r");
  if (!p) return -1;
  size_t n = 0;
  int c;
  while ((c = fgetc(p)) != EOF)
    if (n + 1 < cap) out[n++] = (char)c;
  out[n] = 0;
  int st = pclose(p);
  if (st == -1 || !WIFEXITED(st)) return -1;
  return WEXITSTATUS(st);
}

static void collect_git(tb_context *c) {
  char out[4096];
  copy(c->commit, sizeof c->commit, NULL);
  c->dirty = -1;
  if (git("--no-optional-locks status --porcelain", out, sizeof out) == 0) c->dirty = out[0] != 0;
  if (git("rev-parse --verify -q HEAD", out, sizeof out) != 0) return; /* no commit yet */
  rtrim(out);
  size_t n = strlen(out);
  if (n >= 7 && n < sizeof c->commit && strspn(out, "0123456789abcdef") == n)
    memcpy(c->commit, out, n + 1);
}

void tb_context_collect(tb_context *c, uint64_t seed) {
  memset(c, 0, sizeof *c);
  time_t now = time(NULL);
  struct tm tm;
  if (gmtime_r(&now, &tm))
    strftime(c->date, sizeof c->date, "%Y-%m-%dT%H:%M:%SZ", &tm);
  else
    copy(c->date, sizeof c->date, NULL);

  if (gethostname(c->host, sizeof c->host) != 0) c->host[0] = 0;
  c->host[sizeof c->host - 1] = 0;
  if (!c->host[0]) copy(c->host, sizeof c->host, NULL);

  /* x86 names the model "model name"; some ARM kernels only give "Hardware". */
  if (!cpuinfo("model name", c->cpu, sizeof c->cpu) && !cpuinfo("Hardware", c->cpu, sizeof c->cpu))
    copy(c->cpu, sizeof c->cpu, NULL);
  char mhz[64];
  if (cpuinfo("cpu MHz", mhz, sizeof mhz)) c->mhz = (int)(atof(mhz) + 0.5);
  long cores = sysconf(_SC_NPROCESSORS_ONLN);
  c->cores = cores > 0 ? (int)cores : 0;

  copy(c->compiler, sizeof c->compiler, TB_COMPILER);
  copy(c->flags, sizeof c->flags, TB_BUILD_FLAGS);
  collect_git(c);
  tb_versions_get(c->cholmod, c->fcl, c->bullet, c->cgal, c->tetgen, sizeof c->cholmod);
  c->seed = seed;
}
