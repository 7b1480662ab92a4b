/* `tissuebench merge DIR... [--out DIR]`: one results folder from the N
 * folders of `reproduce --shard k/N` (k = 1..N, run anywhere: a Slurm array,
 * GNU parallel). Each shard folder holds shard.ini (the run's options,
 * commit and each suite's status, written here by tb_shard_info_write);
 * merge checks that the N folders are the N shards of one run, then, suite
 * by suite in the run's order:
 *   a suite made of cases runs again in replay mode: every case's outcome
 *   comes from the shard that ran it (its folder's cases.ini), so its
 *   tables, charts and data files are made by the suite's own code from the
 *   same numbers as an unsharded run;
 *   a whole suite is copied from the shard that ran it, and its part of the
 *   report (report-section.md) goes into the merged REPORT.md. */
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <ftw.h>
#include <ini.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tb_cli.h"
#include "core/tb_paths.h"
#include "core/tb_parse.h"
#include "report/tb_results.h"

static const char *const status_names[] = {"not-run", "done", "failed", "elsewhere"};

int tb_shard_info_write(const char *dir, const tb_shard_info *s, tb_error *err) {
  char path[PATH_MAX];
  snprintf(path, sizeof path, "%s/shard.ini", dir);
  FILE *f = fopen(path, "w");
  if (!f) return tb_error_set(err, path, 0, "cannot write: %s", strerror(errno));
  tb_context c;
  tb_context_collect(&c, s->seed);
  int n;
  const tb_suite_entry *su = tb_suites(&n);
  fprintf(f,
          "; tissuebench reproduce --shard %d/%d: this folder's share of the run\n"
          "; (tissuebench merge makes one results folder of the %d shards)\n"
          "[shard]\nk = %d\nn = %d\nfull = %d\nscale = %.17g\nseed = %llu\ncommit = %s%s\n"
          "only = %s\nmodel = %s\nscene = %s\nhost = %s\n\n[suites]\n",
          s->k, s->n, s->n, s->k, s->n, s->full, s->scale, (unsigned long long)s->seed, c.commit,
          c.dirty == 1 ? "-dirty" : "", s->only, s->model, s->scene, c.host);
  for (int i = 0; i < n && i < TB_SHARD_SUITES; i++)
    fprintf(f, "%s = %s\n", su[i].name, status_names[s->status[i]]);
  int bad = ferror(f);
  if (fclose(f) || bad) return tb_error_set(err, path, 0, "cannot write: %s", strerror(errno));
  return 0;
}

/* ---- reading shard.ini ---- */

typedef struct reader {
  FILE *f;
  const char *path;
  int line, failed, seen_k, seen_n;
  tb_shard_info *s;
  tb_error *err;
} reader;

static char *read_line(char *str, int num, void *stream) {
  reader *R = stream;
  R->line++;
  return fgets(str, num, R->f);
}

static int bad(reader *R, const char *what, const char *value) {
  if (!R->failed) tb_error_set(R->err, R->path, R->line, "%s '%s'", what, value);
  R->failed = 1;
  return 0;
}

static int whole(const char *v, long lo, long hi, long *out) {
  char *end;
  errno = 0;
  long x = strtol(v, &end, 10);
  if (end == v || *end || errno || x < lo || x > hi) return -1;
  *out = x;
  return 0;
}

static int on_key(void *user, const char *section, const char *key, const char *v) {
  reader *R = user;
  tb_shard_info *s = R->s;
  if (R->failed) return 0;
  long x;
  if (!strcmp(section, "shard")) {
    if (!strcmp(key, "k") || !strcmp(key, "n") || !strcmp(key, "full")) {
      if (whole(v, 0, 10000, &x)) return bad(R, "not a whole number:", v);
      *(!strcmp(key, "k") ? &s->k : !strcmp(key, "n") ? &s->n : &s->full) = (int)x;
      R->seen_k |= !strcmp(key, "k"), R->seen_n |= !strcmp(key, "n");
    } else if (!strcmp(key, "scale")) {
      char *end;
      s->scale = strtod(v, &end);
      if (end == v || *end) return bad(R, "not a number:", v);
    } else if (!strcmp(key, "seed")) {
      char *end;
      s->seed = strtoull(v, &end, 10);
      if (end == v || *end) return bad(R, "not a seed:", v);
    } else if (!strcmp(key, "commit"))
      snprintf(s->commit, sizeof s->commit, "%s", v);
    else if (!strcmp(key, "only"))
      snprintf(s->only, sizeof s->only, "%s", v);
    else if (!strcmp(key, "model"))
      snprintf(s->model, sizeof s->model, "%s", v);
    else if (!strcmp(key, "scene"))
      snprintf(s->scene, sizeof s->scene, "%s", v);
    else if (strcmp(key, "host"))
      return bad(R, "unknown key", key);
    return 1;
  }
  if (!strcmp(section, "suites")) {
    int n;
    const tb_suite_entry *su = tb_suites(&n);
    int i = 0, st = 0;
    while (i < n && strcmp(su[i].name, key)) i++;
    if (i == n) return bad(R, "no such suite:", key);
    while (st < 4 && strcmp(status_names[st], v)) st++;
    if (st == 4) return bad(R, "not a status (done, failed, elsewhere, not-run):", v);
    s->status[i] = st;
    return 1;
  }
  return bad(R, "unknown section", section);
}

int tb_shard_info_read(const char *dir, tb_shard_info *s, tb_error *err) {
  char path[PATH_MAX];
  snprintf(path, sizeof path, "%s/shard.ini", dir);
  memset(s, 0, sizeof *s);
  reader R = {fopen(path, "r"), path, 0, 0, 0, 0, s, err};
  if (!R.f)
    return tb_error_set(err, path, 0, "cannot open (%s): not a `reproduce --shard` folder",
                        strerror(errno));
  tb_ini_setup();
  int rc = ini_parse_stream(read_line, &R, on_key, &R);
  fclose(R.f);
  if (R.failed) return -1;
  if (rc) return tb_error_set(err, path, rc > 0 ? rc : 0, "not INI syntax");
  if (!R.seen_k || !R.seen_n || s->k < 1 || s->k > s->n)
    return tb_error_set(err, path, 0, "needs k and n with 1 <= k <= n");
  return 0;
}

/* ---- walking folders (nftw has no user pointer: one walk at a time) ---- */

static struct {
  const char *from, *to; /* copy: the source and destination roots */
  size_t from_len;
  int shard, failed;
  tb_report *report;
  tb_error *err;
} walk;

static int copy_file(const char *src, const char *dst) {
  FILE *in = fopen(src, "rb"), *out = in ? fopen(dst, "wb") : NULL;
  char buf[1 << 16];
  size_t n;
  int rc = in && out ? 0 : -1;
  while (!rc && (n = fread(buf, 1, sizeof buf, in)) > 0)
    if (fwrite(buf, 1, n, out) != n) rc = -1;
  if (in && ferror(in)) rc = -1;
  if (in) fclose(in);
  if (out && fclose(out)) rc = -1;
  return rc;
}

static int copy_one(const char *path, const struct stat *sb, int type, struct FTW *ftw) {
  (void)sb, (void)ftw;
  char dst[PATH_MAX];
  if (snprintf(dst, sizeof dst, "%s%s", walk.to, path + walk.from_len) >= (int)sizeof dst)
    return tb_error_set(walk.err, path, 0, "path too long"), 1;
  if (type == FTW_D) {
    if (mkdir(dst, 0777) && errno != EEXIST)
      return tb_error_set(walk.err, dst, 0, "cannot create: %s", strerror(errno)), 1;
    return 0;
  }
  if (type != FTW_F) return 0;
  if (copy_file(path, dst)) return tb_error_set(walk.err, dst, 0, "cannot copy %s", path), 1;
  return 0;
}

/* The folder of the file path relative to the walk's root (walk.from_len). */
static void folder_of(const char *path, const struct FTW *ftw, char *out, size_t cap) {
  snprintf(out, cap, "%.*s", (int)(ftw->base - walk.from_len - 2), path + walk.from_len + 1);
}

/* The cases.ini files of a shard's suite folder into the replay's book. */
static int load_cases(const char *path, const struct stat *sb, int type, struct FTW *ftw) {
  (void)sb;
  if (type != FTW_F || strcmp(path + ftw->base, "cases.ini")) return 0;
  char folder[PATH_MAX];
  folder_of(path, ftw, folder, sizeof folder);
  return tb_shard_load(path, folder, walk.shard, walk.err) ? 1 : 0;
}

/* The report sections of a copied suite into the merged report. */
static int place_sections(const char *path, const struct stat *sb, int type, struct FTW *ftw) {
  (void)sb;
  if (type != FTW_F || strcmp(path + ftw->base, TB_REPORT_SECTION)) return 0;
  char folder[PATH_MAX];
  folder_of(path, ftw, folder, sizeof folder);
  if (tb_report_section_file(walk.report, path, folder, walk.err)) return 1;
  unlink(path);
  return 0;
}

/* ---- the command ---- */

static int usage(void) {
  fprintf(stderr,
          "usage: tissuebench merge SHARD_DIR... [--out DIR]\n"
          "  SHARD_DIR: the N folders of `reproduce --shard k/N --results SHARD_DIR`\n");
  return TB_EXIT_INPUT;
}

/* The shards fit together: one run's options and commit, k = 1..n once. */
static int check_shards(char **dirs, const tb_shard_info *info, int nd, tb_error *err) {
  const tb_shard_info *a = &info[0];
  if (nd != a->n)
    return tb_error_set(err, dirs[0], 0, "shard %d of %d, but %d shard folders given", a->k, a->n,
                        nd);
  for (int i = 0; i < nd; i++) {
    const tb_shard_info *b = &info[i];
    const char *what = b->n != a->n                   ? "the shard count"
                       : b->full != a->full           ? "--full"
                       : b->scale != a->scale         ? "--scale"
                       : b->seed != a->seed           ? "--seed"
                       : strcmp(b->commit, a->commit) ? "the commit"
                       : strcmp(b->only, a->only)     ? "--only"
                       : strcmp(b->model, a->model)   ? "--model"
                       : strcmp(b->scene, a->scene)   ? "--scene"
                                                      : NULL;
    if (what)
      return tb_error_set(err, dirs[i], 0, "%s differs from %s's: not shards of one run", what,
                          dirs[0]);
    for (int j = 0; j < i; j++)
      if (info[j].k == b->k)
        return tb_error_set(err, dirs[i], 0, "shard %d/%d again (also %s)", b->k, b->n, dirs[j]);
  }
  return 0;
}

int tb_cmd_merge(int argc, char **argv) {
  const char *out = tb_results_dir();
  char **dirs = calloc((size_t)argc + 1, sizeof *dirs);
  int nd = 0;
  if (!dirs) return TB_EXIT_FAIL;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--out") && i + 1 < argc)
      out = argv[++i];
    else if (argv[i][0] == '-')
      return free(dirs), usage();
    else
      dirs[nd++] = argv[i];
  }
  if (!nd) return free(dirs), usage();
  tb_shard_info *info = calloc((size_t)nd, sizeof *info);
  tb_error err = {{0}};
  int rc = info ? 0 : TB_EXIT_FAIL;
  char real_out[PATH_MAX];
  int have_out = realpath(out, real_out) != NULL;
  for (int i = 0; !rc && i < nd; i++) {
    char real_in[PATH_MAX];
    if (tb_shard_info_read(dirs[i], &info[i], &err))
      rc = TB_EXIT_INPUT;
    else if (have_out && realpath(dirs[i], real_in) && !strcmp(real_in, real_out))
      tb_error_set(&err, out, 0, "the output is one of the shards"), rc = TB_EXIT_INPUT;
  }
  if (!rc && check_shards(dirs, info, nd, &err)) rc = TB_EXIT_INPUT;
  if (rc) {
    if (err.msg[0]) fprintf(stderr, "tissuebench merge: %s\n", err.msg);
    free(info), free(dirs);
    return rc;
  }
  /* by shard number: an every-shard case keeps shard 1's outcome */
  char **by_k = calloc((size_t)nd, sizeof *by_k);
  for (int i = 0; by_k && i < nd; i++) by_k[info[i].k - 1] = dirs[i];
  const tb_shard_info *run = &info[0];
  tb_suite_opts o = {run->full,
                     run->scale,
                     run->seed,
                     out,
                     run->model[0] ? run->model : NULL,
                     run->scene[0] ? run->scene : NULL};
  int n;
  const tb_suite_entry *su = tb_suites(&n);
  int status[TB_SHARD_SUITES], failed = 0;
  tb_report *report = by_k && !tb_shard_replay(out, &err)
                          ? tb_report_begin(out, "tissuebench: the reproduction", run->seed, &err)
                          : NULL;
  if (!report) {
    fprintf(stderr, "tissuebench merge: %s\n", err.msg);
    tb_shard_reset();
    free(by_k), free(info), free(dirs);
    return TB_EXIT_FAIL;
  }
  walk.err = &err, walk.report = report;
  for (int s = 0; s < n && s < TB_SHARD_SUITES; s++) {
    status[s] = TB_REPORT_NOT_RUN;
    if (run->status[s] == TB_SHARD_NOT_RUN) continue;
    int bad = 0, owner = -1;
    for (int k = 0; k < nd; k++) {
      const tb_shard_info *sk = &info[k];
      bad |= sk->status[s] == TB_SHARD_FAILED;
      if (sk->status[s] != TB_SHARD_ELSEWHERE && sk->status[s] != TB_SHARD_NOT_RUN) owner = k;
    }
    char src[PATH_MAX], dst[PATH_MAX];
    err.msg[0] = 0;
    if (su[s].cases) { /* replay: every shard's outcomes */
      for (int k = 0; k < nd && !bad; k++) {
        snprintf(src, sizeof src, "%s/%s", by_k[k], su[s].name);
        walk.from_len = strlen(by_k[k]), walk.shard = k + 1;
        if (access(src, F_OK) == 0 && nftw(src, load_cases, 16, FTW_PHYS)) bad = 1;
      }
      if (!bad) {
        fprintf(stderr, "== %s: from the cases of %d shards\n", su[s].name, nd);
        bad = su[s].run(&o) != 0;
      }
    } else if (owner < 0) {
      tb_error_set(&err, su[s].name, 0, "no shard ran this suite");
      bad = 1;
    } else { /* a whole suite: copied from its shard */
      snprintf(src, sizeof src, "%s/%s", dirs[owner], su[s].name);
      snprintf(dst, sizeof dst, "%s/%s", out, su[s].name);
      walk.from = src, walk.from_len = strlen(src), walk.to = dst;
      if (access(src, F_OK) == 0 && nftw(src, copy_one, 16, FTW_PHYS)) bad = 1;
      walk.from_len = strlen(out);
      if (!bad && access(dst, F_OK) == 0 && nftw(dst, place_sections, 16, FTW_PHYS)) bad = 1;
      fprintf(stderr, "== %s: copied from %s\n", su[s].name, dirs[owner]);
    }
    if (bad && err.msg[0]) fprintf(stderr, "tissuebench merge: %s: %s\n", su[s].name, err.msg);
    status[s] = bad ? TB_REPORT_FAILED : TB_REPORT_DONE;
    failed += bad;
  }
  tb_shard_reset();
  int no_report = tb_reproduce_report(report, status);
  fprintf(stderr, "merge: %d shard(s) into %s, %d suite(s) failed\n", nd, out, failed);
  free(by_k), free(info), free(dirs);
  return failed || no_report ? TB_EXIT_FAIL : TB_EXIT_OK;
}
