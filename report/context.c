/* The run's context recorded beside every result: UTC date, host, CPU model
 * and clock (/proc/cpuinfo), online cores, compiler and flags (defines set by
 * meson), git commit and dirty flag of the source tree, dependency versions
 * (report/versions.cpp) and the seed; and Google Benchmark's context
 * fields: CPU frequency scaling (cpu0's governor), cpu0's caches, the load
 * averages and the build type. Fields that cannot be read say
 * "unknown" (numbers 0, dirty -1); git's own errors are not shown, and
 * --no-optional-locks keeps `git status` from touching the index. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "tb_results.h"
#include "core/tb_paths.h"
#include "tb_versions.h"
#include "core/tb_threads.h"

#ifndef TB_COMPILER
#define TB_COMPILER "unknown"
#endif
#ifndef TB_BUILD_TYPE
#define TB_BUILD_TYPE "unknown"
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
  for (const char *p = tb_root(); *p && k + 6 < sizeof root; p++) {
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

/* The first line of a file, trimmed; 0 when unreadable or empty. */
static int read_line(const char *path, char *out, size_t cap) {
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  int ok = fgets(out, (int)cap, f) != NULL;
  fclose(f);
  if (ok) rtrim(out);
  return ok && out[0];
}

/* How many CPUs a shared_cpu_map ("00000003" or "ff,ffffffff") names. */
static int map_bits(const char *map) {
  int n = 0;
  for (const char *p = map; *p; p++) {
    int v = *p >= '0' && *p <= '9' ? *p - '0' : *p >= 'a' && *p <= 'f' ? *p - 'a' + 10 : 0;
    for (; v; v >>= 1) n += v & 1;
  }
  return n;
}

/* Google Benchmark's cache list: /sys/devices/system/cpu/cpu0/cache/index*. */
static void collect_caches(tb_context *c) {
  const int max = (int)(sizeof c->caches / sizeof c->caches[0]);
  for (int i = 0; c->ncaches < max && i < 16; i++) {
    char path[128], v[128];
    struct tb_cache *k = &c->caches[c->ncaches];
    snprintf(path, sizeof path, "/sys/devices/system/cpu/cpu0/cache/index%d/type", i);
    if (!read_line(path, k->type, sizeof k->type)) break;
    snprintf(path, sizeof path, "/sys/devices/system/cpu/cpu0/cache/index%d/level", i);
    k->level = read_line(path, v, sizeof v) ? atoi(v) : 0;
    snprintf(path, sizeof path, "/sys/devices/system/cpu/cpu0/cache/index%d/size", i);
    if (read_line(path, v, sizeof v)) {
      char *end;
      long size = strtol(v, &end, 10);
      k->size = size * (*end == 'K' ? 1024 : *end == 'M' ? 1024 * 1024 : 1);
    }
    snprintf(path, sizeof path, "/sys/devices/system/cpu/cpu0/cache/index%d/shared_cpu_map", i);
    k->num_sharing = read_line(path, v, sizeof v) ? map_bits(v) : 0;
    c->ncaches++;
  }
}

/* 1, 5 and 15 minute load: getloadavg, else /proc/loadavg. */
static void collect_load(tb_context *c) {
  if (getloadavg(c->load, 3) == 3) {
    c->have_load = 1;
    return;
  }
  char line[128];
  c->have_load = read_line("/proc/loadavg", line, sizeof line) &&
                 sscanf(line, "%lf %lf %lf", &c->load[0], &c->load[1], &c->load[2]) == 3;
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
  char gov[64]; /* no cpufreq (virtual machines): scaling is not enabled */
  c->cpu_scaling =
      read_line("/sys/devices/system/cpu/cpu0/cpufreq/scaling_governor", gov, sizeof gov) &&
      strcmp(gov, "performance") != 0;
  collect_caches(c);
  collect_load(c);
  snprintf(c->build_type, sizeof c->build_type, "%s",
           strcmp(TB_BUILD_TYPE, "release") == 0 ? "release" : "debug");

  copy(c->compiler, sizeof c->compiler, TB_COMPILER);
  copy(c->flags, sizeof c->flags, TB_BUILD_FLAGS);
  collect_git(c);
  tb_versions_get(c->cholmod, c->fcl, c->bullet, c->cgal, c->tetgen, sizeof c->cholmod);
  c->seed = seed;
  c->threads = tb_threads();
}
