/* Timing of one metaball deformation frame: the patent's
 * liver (tb_organ_surface "liver", seed 1: exactly 8128 vertices), packed
 * to 570 spheres (tb_sphere_pack), tb_metaball_step with a push on a patch,
 * skin included. Prints links, median / min ms per step over the run (CPU
 * time: the thread's on one thread, else the process's; and wall time) and
 * the convergence measure: the stretch links' residual
 * max |(|c_i - c_j| - l0) / l0| after the push's last frame and the frames
 * to rest after the release (every centre slower than 1e-4 / s). With a
 * third argument, writes the skin's positions after the last step there
 * (one vertex a line, %.17g) to compare two builds.
 *
 *   ./build/metaball_timing [steps] [iterations] [skin-file]
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "meshgen/tb_meshgen.h"
#include "meshgen/tb_sphpack.h"
#include "models/tb_metaball.h"

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The stretch links' largest relative residual; rest: the rest centres. */
static double residual(const tb_metaball *m, const tb_vec3 *rest) {
  const int *link;
  int nl = tb_metaball_links(m, &link);
  const tb_vec3 *c = tb_metaball_centres(m);
  double r = 0;
  for (int e = 0; e < nl; e++) {
    double l0 = tb_dist(rest[link[2 * e]], rest[link[2 * e + 1]]);
    r = fmax(r, fabs(tb_dist(c[link[2 * e]], c[link[2 * e + 1]]) - l0) / l0);
  }
  return r;
}

int main(int argc, char **argv) {
  int steps = argc > 1 ? atoi(argv[1]) : 400, iters = argc > 2 ? atoi(argv[2]) : 10;
  if (steps < 1 || iters < 0)
    return fprintf(stderr, "usage: metaball_timing [steps >= 1] [iterations >= 0] [skin-file]\n"),
           1;
  tb_error err;
  tb_mesh surf;
  if (tb_organ_surface("liver", 0, 1, &surf, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
  tb_sphpack_def pd = tb_sphpack_default_def(570);
  tb_spheres sp = {0};
  if (tb_sphere_pack(&surf, "liver", &pd, &sp, NULL, &err))
    return fprintf(stderr, "%s\n", err.msg), 1;
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  set.iterations = iters;
  tb_metaball *m = tb_metaball_create(sp.n, sp.c, sp.r, &surf, &set, &err);
  if (!m) return fprintf(stderr, "%s\n", err.msg), 1;
  for (int i = 0; i < 10; i++) tb_metaball_fix(m, i, 1); /* the largest ten hold it */
  int n = tb_metaball_count(m), nv = surf.nv;
  const tb_vec3 *c0 = sp.c, *x0 = surf.x; /* the rest centres and skin */
  const double *mass = tb_metaball_masses(m);
  tb_vec3 *f = calloc((size_t)n, sizeof(tb_vec3));
  double *ms = malloc(sizeof(double) * 2 * (size_t)steps), *cpu = ms ? ms + steps : NULL, res = 0;
  if (!f || !ms) return fprintf(stderr, "out of memory\n"), 1;
  int push = steps / 4, rest = -1;
  for (int k = 0; k < steps; k++) {
    for (int i = n - 20; i < n; i++) f[i] = k < push ? tb_v3(0, 0, -50 * mass[i]) : tb_v3(0, 0, 0);
    tb_clock clk = tb_clock_start();
    tb_metaball_step(m, 0.01, tb_v3(0, 0, 0), f);
    tb_clock_ms(&clk, ms + k, cpu + k);
    if (k == push - 1) res = residual(m, c0);
    const tb_vec3 *v = tb_metaball_velocities(m);
    double vmax = 0;
    for (int i = 0; i < n; i++) vmax = fmax(vmax, tb_len(v[i]));
    if (k >= push && rest < 0 && vmax < 1e-4) rest = k - push + 1;
  }
  const tb_vec3 *x = tb_metaball_skin(m);
  const int *link;
  int nl = tb_metaball_links(m, &link);
  double last = 0;
  for (int v = 0; v < nv; v++) last = fmax(last, tb_dist(x[v], x0[v]));
  if (argc > 3) {
    FILE *out = fopen(argv[3], "w");
    if (!out) return fprintf(stderr, "cannot write %s\n", argv[3]), 1;
    for (int v = 0; v < nv; v++) fprintf(out, "%.17g %.17g %.17g\n", x[v].x, x[v].y, x[v].z);
    fclose(out);
  }
  qsort(ms, (size_t)steps, sizeof(double), cmp);
  qsort(cpu, (size_t)steps, sizeof(double), cmp);
  printf("liver: %d vertices, %d spheres, %d links, %d iterations, %d steps, %d thread%s\n", nv, n,
         nl, iters, steps, tb_threads(), tb_threads() > 1 ? "s" : "");
  printf("step incl. skin: CPU median %.4f ms, min %.4f ms; wall median %.4f ms, min %.4f ms\n",
         cpu[steps / 2], cpu[0], ms[steps / 2], ms[0]);
  printf(
      "stretch residual at the push's end %.3e; frames to rest after release %d; skin's "
      "largest offset from rest at the end %.3e\n",
      res, rest, last);
  free(f), free(ms);
  tb_metaball_destroy(m);
  tb_spheres_free(&sp);
  tb_mesh_free(&surf);
  return 0;
}
