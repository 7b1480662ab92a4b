/* The harnesses' table: each reader the CLI uses,
 * fed through its real entry point with a file of the process's own
 * temporary folder, and its result checked against the contract of
 * fuzz_check.c. Used by fuzz_main.c (one libFuzzer binary per entry) and by
 * tests/test_fuzz_regressions.c. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fuzz_check.h"
#include "commands/tb_cli.h"
#include "core/tb_mesh_io.h"
#include "measure/tb_points.h"
#include "report/tb_results.h"
#include "scenes/tb_scene_file.h"

/* ---- the process's temporary folder ---- */

static char dir[512];

static const char *const leftovers[] = {"in.obj",  "in.off", "in.stl", "in.node",         "in.ele",
                                        "in.face", "in.msh", "in.vtk", "in.vtu",          "in.sph",
                                        "in.ini",  "in.txt", "in.csv", "shard/shard.ini", "shard"};

static void cleanup(void) {
  char p[600];
  for (size_t i = 0; i < sizeof leftovers / sizeof *leftovers; i++) {
    snprintf(p, sizeof p, "%s/%s", dir, leftovers[i]);
    remove(p);
  }
  rmdir(dir);
}

static const char *tmpdir(void) {
  if (dir[0]) return dir;
  const char *t = getenv("TMPDIR");
  snprintf(dir, sizeof dir, "%s/tbfuzz-XXXXXX", t && *t ? t : "/tmp");
  if (!mkdtemp(dir)) {
    dir[0] = 0;
    return NULL;
  }
  atexit(cleanup);
  return dir;
}

static int put(const char *path, const uint8_t *data, size_t size) {
  FILE *f = fopen(path, "wb");
  if (!f) return -1;
  int rc = size && fwrite(data, 1, size, f) != size ? -1 : 0;
  return fclose(f) || rc ? -1 : 0;
}

/* *len: the length of the text before the first line that is exactly `mark`.
 * Returns the text after that line, or NULL (and *len = size) when none is. */
static const uint8_t *part(const uint8_t *data, size_t size, const char *mark, size_t *len) {
  size_t m = strlen(mark);
  for (size_t i = 0; i + m <= size; i++)
    if ((i == 0 || data[i - 1] == '\n') && !memcmp(data + i, mark, m) &&
        (i + m == size || data[i + m] == '\n')) {
      *len = i;
      return data + (i + m < size ? i + m + 1 : size);
    }
  *len = size;
  return NULL;
}

/* ---- the readers ---- */

static int accepted; /* the last run's reader took its input */

int tb_fuzz_accepted(void) { return accepted; }

static int run_mesh(const char *path, char *why, size_t cap) {
  tb_mesh m;
  tb_error err = {{0}};
  memset(&m, 0xa5, sizeof m); /* the reader must set every field */
  int rc = tb_mesh_read(path, &m, &err);
  accepted = rc == 0;
  int ok = tb_fuzz_check_mesh(path, rc, &m, &err, why, cap);
  if (rc == 0) tb_mesh_free(&m);
  return ok;
}

static int run_sph(const char *path, char *why, size_t cap) {
  tb_spheres s;
  tb_error err = {{0}};
  memset(&s, 0xa5, sizeof s);
  int rc = tb_spheres_read(path, &s, &err);
  accepted = rc == 0;
  int ok = tb_fuzz_check_spheres(path, rc, &s, &err, why, cap);
  if (rc == 0) tb_spheres_free(&s);
  return ok;
}

static int run_pairs(const char *path, char *why, size_t cap) {
  tb_pairset p;
  tb_error err = {{0}};
  memset(&p, 0xa5, sizeof p);
  int rc = tb_pairs_read_file(path, &p, &err);
  accepted = rc == 0;
  int ok = tb_fuzz_check_pairs(path, rc, &p, &err, why, cap);
  if (rc == 0) tb_pairs_free(&p);
  return ok;
}

/* The JGT Shen-2003 pair files (six "x y z" lines per pair). */
static int run_jgt(const char *path, char *why, size_t cap) {
  tb_pairset p;
  tb_error err = {{0}};
  memset(&p, 0xa5, sizeof p);
  int rc = tb_pairs_read_jgt(path, 1, &p, &err);
  accepted = rc == 0;
  int ok = tb_fuzz_check_pairs(path, rc, &p, &err, why, cap);
  if (rc == 0) tb_pairs_free(&p);
  return ok;
}

static int run_points(const char *path, char *why, size_t cap) {
  tb_point *p = (tb_point *)1;
  int n = -7;
  tb_error err = {{0}};
  int rc = tb_points_read(path, &p, &n, &err);
  accepted = rc == 0;
  int ok = tb_fuzz_check_points(path, rc, p, n, &err, why, cap);
  if (rc == 0) free(p);
  return ok;
}

static int run_scene(const char *path, char *why, size_t cap) {
  tb_scene_desc d;
  tb_error err = {{0}};
  int rc = tb_scene_desc_load(&d, path, &err);
  accepted = rc == 0;
  if (rc) return tb_fuzz_check_error(path, &err, why, cap);
  tb_scene_desc_free(&d);
  return 0;
}

/* cases.ini, as `merge` reads each shard's (replay mode). */
static int run_cases(const char *path, char *why, size_t cap) {
  tb_error err = {{0}};
  if (tb_shard_replay(tmpdir(), &err)) {
    snprintf(why, cap, "tb_shard_replay: %s", err.msg);
    return -1;
  }
  int rc = tb_shard_load(path, "suite", 1, &err);
  accepted = rc == 0;
  if (rc == 0) rc = tb_shard_load(path, "suite", 2, &err); /* a second shard's copy */
  tb_shard_reset();
  return rc ? tb_fuzz_check_error(path, &err, why, cap) : 0;
}

/* shard.ini: its reader takes the folder. */
static int run_shardinfo(const char *path, char *why, size_t cap) {
  char folder[600];
  snprintf(folder, sizeof folder, "%.*s", (int)(strrchr(path, '/') - path), path);
  tb_shard_info s;
  tb_error err = {{0}};
  accepted = tb_shard_info_read(folder, &s, &err) == 0;
  if (!accepted) return tb_fuzz_check_error(path, &err, why, cap);
  if (s.k < 1 || s.k > s.n) {
    snprintf(why, cap, "accepted k=%d n=%d", s.k, s.n);
    return -1;
  }
  for (int i = 0; i < TB_SHARD_SUITES; i++)
    if (s.status[i] < TB_SHARD_NOT_RUN || s.status[i] > TB_SHARD_ELSEWHERE) {
      snprintf(why, cap, "suite %d: status %d", i, s.status[i]);
      return -1;
    }
  return 0;
}

static const tb_fuzz_target targets[] = {
    {"obj", "obj", "OBJ (core/io_obj.c)", run_mesh},
    {"off", "off", "OFF (core/io_off.c)", run_mesh},
    {"stl", "stl", "STL, ASCII and binary (core/io_stl.c)", run_mesh},
    {"tetgen", "node", "TetGen .node + .ele (+ .face), split at \"#@ele\" / \"#@face\" lines",
     run_mesh},
    {"msh", "msh", "Gmsh .msh v1, v2, v4 (core/io_gmsh.c)", run_mesh},
    {"vtk", "vtk", "VTK legacy (core/io_vtk.c)", run_mesh},
    {"vtu", "vtu", "VTK XML .vtu (core/io_vtu_read.c)", run_mesh},
    {"sph", "sph", "SOFA .sph spheres (core/io_sph.c)", run_sph},
    {"scene", "ini", "scene files (scenes/scene_file.c)", run_scene},
    {"pairs", "txt", "tritri pair lines (collision/pairs.c)", run_pairs},
    {"jgt", "txt", "JGT Shen-2003 pair files (collision/pairs.c)", run_jgt},
    {"points", "csv", "advise's points.csv (commands/cmd_advise.c)", run_points},
    {"cases", "ini", "a shard's cases.ini (report/results_shard.c)", run_cases},
    {"shardinfo", "ini", "a shard's shard.ini (commands/cmd_merge.c)", run_shardinfo},
};

const tb_fuzz_target *tb_fuzz_targets(int *n) {
  *n = (int)(sizeof targets / sizeof *targets);
  return targets;
}

const tb_fuzz_target *tb_fuzz_target_find(const char *name) {
  for (size_t i = 0; i < sizeof targets / sizeof *targets; i++)
    if (!strcmp(targets[i].name, name)) return &targets[i];
  return NULL;
}

int tb_fuzz_run(const tb_fuzz_target *t, const uint8_t *data, size_t size, char *why, size_t cap) {
  accepted = 0;
  const char *d = tmpdir();
  char path[600], other[600];
  if (!d) return snprintf(why, cap, "cannot create a temporary folder"), -2;
  if (t->run == run_shardinfo) {
    snprintf(path, sizeof path, "%s/shard", d);
    mkdir(path, 0700);
    snprintf(path, sizeof path, "%s/shard/shard.ini", d);
  } else
    snprintf(path, sizeof path, "%s/in.%s", d, t->ext);
  if (strcmp(t->name, "tetgen")) {
    if (put(path, data, size)) return snprintf(why, cap, "cannot write %s", path), -2;
    return t->run(path, why, cap);
  }
  size_t nn, ne = 0, nf = 0;
  const uint8_t *ele = part(data, size, "#@ele", &nn), *face = NULL;
  if (ele) face = part(ele, size - (size_t)(ele - data), "#@face", &ne);
  if (face) nf = size - (size_t)(face - data);
  int rc = put(path, data, nn);
  snprintf(other, sizeof other, "%s/in.ele", d);
  if (ele)
    rc |= put(other, ele, ne);
  else
    remove(other);
  snprintf(other, sizeof other, "%s/in.face", d);
  if (face)
    rc |= put(other, face, nf);
  else
    remove(other);
  if (rc) return snprintf(why, cap, "cannot write %s", path), -2;
  return t->run(path, why, cap);
}
