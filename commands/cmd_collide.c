/* `tissuebench collide`: every intersecting triangle pair of two meshes with
 * one method (scenes/tb_collider.h); B moved by a row-major 3x4 matrix. The
 * build and query times on stderr are CPU time (every thread's when more
 * than one is in effect) with wall time beside. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"
#include "core/tb_mesh_io.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "report/tb_results.h"
#include "scenes/tb_collider.h"

static int parse_xform(const char *s, tb_mat3 *R, tb_vec3 *t) {
  double v[12];
  char *end;
  for (int k = 0; k < 12; k++) {
    errno = 0;
    v[k] = strtod(s, &end);
    if (end == s || errno == ERANGE || !isfinite(v[k])) return -1;
    s = end;
  }
  while (*s == ' ' || *s == '\t') s++;
  if (*s) return -1;
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) R->m[i][j] = v[4 * i + j];
  }
  *t = tb_v3(v[3], v[7], v[11]);
  return 0;
}

int tb_cmd_collide(int argc, char **argv) {
  const char *method = NULL, *tritest = NULL, *xform = NULL, *files[2] = {NULL, NULL};
  int pairs = 0, nfiles = 0;
  long repeat = 1;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--bvh") && i + 1 < argc)
      method = argv[++i];
    else if (!strcmp(argv[i], "--tritest") && i + 1 < argc)
      tritest = argv[++i];
    else if (!strcmp(argv[i], "--xform-b") && i + 1 < argc)
      xform = argv[++i];
    else if (!strcmp(argv[i], "--pairs"))
      pairs = 1;
    else if (!strcmp(argv[i], "--repeat") && i + 1 < argc) {
      char *end;
      repeat = strtol(argv[++i], &end, 10);
      if (*end || repeat < 1 || repeat > 100000) {
        fprintf(stderr, "tissuebench collide: --repeat needs a whole number in [1, 1e5]\n");
        return TB_EXIT_INPUT;
      }
    } else if (argv[i][0] != '-' && nfiles < 2)
      files[nfiles++] = argv[i];
    else
      return tb_cli_bad_option("collide", argv[i]);
  }
  int nm, known = 0;
  const char *const *names = tb_collider_methods(&nm);
  for (int k = 0; method && k < nm; k++) known |= !strcmp(names[k], method);
  if (!known || nfiles != 2) {
    fprintf(stderr,
            "usage: tissuebench collide --bvh NAME [--tritest NAME] A B [--xform-b M] [--pairs]\n"
            "  NAME:");
    for (int k = 0; k < nm; k++) fprintf(stderr, " %s", names[k]);
    fprintf(stderr, "\n");
    return TB_EXIT_INPUT;
  }
  const tb_tritri_method *tm = tb_tritri_find(tritest ? tritest : "exact");
  if (!tm || (tritest && !tb_collider_is_ours(method) && strcmp(method, "brute"))) {
    fprintf(stderr, "tissuebench collide: %s\n",
            tm ? "--tritest applies to sphere, aabb, composite and brute"
               : "unknown --tritest (tissuebench tritri --method list)");
    return TB_EXIT_INPUT;
  }
  tb_mat3 R = tb_m3_identity();
  tb_vec3 t = tb_v3(0, 0, 0);
  if (xform && parse_xform(xform, &R, &t)) {
    fprintf(stderr,
            "tissuebench collide: --xform-b needs 12 finite numbers (a row-major 3x4 matrix)\n");
    return TB_EXIT_INPUT;
  }
  tb_mesh raw[2], m[2] = {{0}, {0}};
  tb_error err;
  for (int k = 0; k < 2; k++) {
    if (tb_mesh_read(files[k], &raw[k], &err) ||
        (tb_collision_mesh(&raw[k], &m[k], &err) ? (tb_mesh_free(&raw[k]), 1) : 0)) {
      fprintf(stderr, "%s\n", err.msg);
      if (k) tb_mesh_free(&raw[0]), tb_mesh_free(&m[0]);
      return TB_EXIT_INPUT;
    }
    tb_mesh_free(&raw[k]);
  }
  tb_clock bc = tb_clock_start();
  tb_collider *c = tb_collider_new(method, &m[0], &m[1], NULL, NULL, tm->test, &err);
  int rc = TB_EXIT_OK;
  tb_pairlist pl = {0, 0, NULL};
  tb_collide_stats st;
  double build_wall, build_cpu;
  tb_clock_ms(&bc, &build_wall, &build_cpu);
  double *cpu = malloc(sizeof(double) * 2 * (size_t)repeat), *wall = cpu ? cpu + repeat : NULL;
  if (!c || !cpu || tb_collider_pose(c, R, t, &err)) {
    fprintf(stderr, "tissuebench collide: %s\n", cpu ? err.msg : "out of memory");
    rc = TB_EXIT_FAIL;
  }
  for (long r = 0; rc == TB_EXIT_OK && r < repeat; r++) {
    tb_clock qc = tb_clock_start();
    if (tb_collider_query(c, &pl, &st, &err)) {
      fprintf(stderr, "tissuebench collide: %s\n", err.msg);
      rc = TB_EXIT_FAIL;
    }
    tb_clock_ms(&qc, &wall[r], &cpu[r]);
  }
  if (rc == TB_EXIT_OK) {
    if (pairs)
      for (int i = 0; i < pl.n; i++) printf("%d %d\n", pl.ij[2 * i], pl.ij[2 * i + 1]);
    fprintf(stderr,
            "%s: %d pairs, %ld volume tests, %ld triangle tests (%s), build %.3f ms CPU (%.3f "
            "wall), query %.6f ms CPU (%.6f wall)%s, %d thread(s)\n",
            method, pl.n, st.bv_tests, st.tri_tests,
            tb_collider_is_ours(method) || !strcmp(method, "brute") ? tm->name : "the library's",
            build_cpu, build_wall, tb_stats_of(cpu, (int)repeat).median,
            tb_stats_of(wall, (int)repeat).median, repeat > 1 ? " (medians)" : "", tb_threads());
  }
  free(cpu);
  tb_pairlist_free(&pl);
  tb_collider_free(c);
  tb_mesh_free(&m[0]), tb_mesh_free(&m[1]);
  return rc;
}
