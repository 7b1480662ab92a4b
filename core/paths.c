/* Run-time locations (core/tb_paths.h): the root found once from the
 * environment or the executable's own path (/proc/self/exe), paths under it
 * interned so callers can keep them. */
#include "tb_paths.h"

#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef TB_SOURCE_ROOT
#define TB_SOURCE_ROOT "."
#endif

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static char root[PATH_MAX + 64], shared[PATH_MAX + 96], results[PATH_MAX + 80];

static int exists(const char *dir, const char *rel) {
  char p[PATH_MAX + 64];
  struct stat st;
  return snprintf(p, sizeof p, "%s/%s", dir, rel) < (int)sizeof p && stat(p, &st) == 0;
}

/* root, shared and results, once (under lock). */
static void locate(void) {
  if (root[0]) return;
  const char *env = getenv("TB_DATA_DIR");
  char exe[PATH_MAX], up[PATH_MAX + 8], share[PATH_MAX + 32];
  ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  int have_exe = n > 0;
  if (have_exe) {
    exe[n] = 0;
    char *slash = strrchr(exe, '/');
    if (slash) *slash = 0; /* the executable's folder */
    snprintf(up, sizeof up, "%s/..", exe);
    snprintf(share, sizeof share, "%s/../share/tissuebench", exe);
  }
  const char *pick = ".";
  if (env && *env)
    pick = env;
  else if (have_exe && exists(up, "scenes"))
    pick = up;
  else if (have_exe && exists(share, "scenes"))
    pick = share;
  else if (exists(TB_SOURCE_ROOT, "scenes"))
    pick = TB_SOURCE_ROOT;
  char *real = realpath(pick, NULL);
  snprintf(root, sizeof root, "%s", real ? real : pick);
  free(real);
  const char *sd = getenv("TB_SHARED_DATA");
  if (sd && *sd)
    snprintf(shared, sizeof shared, "%s", sd);
  else
    snprintf(shared, sizeof shared, "%s/../shared/data", root);
  if (exists(root, "meson.build"))
    snprintf(results, sizeof results, "%s/results", root);
  else
    snprintf(results, sizeof results, "./results");
}

const char *tb_root(void) {
  pthread_mutex_lock(&lock);
  locate();
  pthread_mutex_unlock(&lock);
  return root;
}

const char *tb_shared_data(void) {
  tb_root();
  return shared;
}

const char *tb_results_dir(void) {
  tb_root();
  return results;
}

/* The interned paths: a list, searched linearly (a run names a few dozen). */
typedef struct interned {
  struct interned *next;
  const char *base, *rel;
  char path[];
} interned;
static interned *table;

const char *tb_path_in(const char *base, const char *rel) {
  pthread_mutex_lock(&lock);
  interned *e = table;
  while (e && !(e->base == base && !strcmp(e->rel, rel))) e = e->next;
  if (!e) {
    size_t len = strlen(base) + strlen(rel) + 2;
    e = malloc(sizeof *e + len + strlen(rel) + 1);
    if (e) {
      snprintf(e->path, len, "%s/%s", base, rel);
      char *r = e->path + len;
      strcpy(r, rel);
      e->base = base, e->rel = r, e->next = table;
      table = e;
    }
  }
  pthread_mutex_unlock(&lock);
  return e ? e->path : rel;
}
