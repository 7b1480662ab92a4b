/* Timing of the metaball cut (the goal: a cut frame <= 2 ms) and of the
 * re-packing against the patent's "about twice as many, half the size".
 * The patent's liver (or the organ named by the 4th argument):
 * tb_organ_surface at 8128 vertices, packed to 570 spheres (tb_sphere_pack;
 * the organ's patent counts), the ten largest fixed, under gravity. A
 * blade enters above it and crosses it along y at mid x in `frames`
 * frames, its path bending gently in x (a folded plane of frames + 1
 * points) and reaching below the liver. Per frame: tb_metaball_cut_advance
 * + tb_metaball_cut_step, timed together and apart; then
 * tb_metaball_cut_end. Prints the median and worst ms per cut frame, the
 * cut_end ms and its report, and for reference the median of a plain
 * tb_metaball_step of the same organ uncut (inside every cut frame: the
 * cut's own share is the difference).
 *
 *   ./build/metaball_cut_timing [frames] [per_sphere (0: the shared grid)] [spacing]
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/tb_timer.h"
#include "cutting/tb_fold.h"
#include "meshgen/tb_meshgen.h"
#include "meshgen/tb_sphpack.h"
#include "models/tb_metaball.h"

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

int main(int argc, char **argv) {
  int frames = argc > 1 ? atoi(argv[1]) : 20;
  tb_metaball_cut_settings cs;
  tb_metaball_cut_settings_default(&cs);
  if (argc > 2) cs.per_sphere = atoi(argv[2]);
  if (argc > 3) cs.spacing = atof(argv[3]);
  if (frames < 1 || frames > 1000) return fprintf(stderr, "frames in 1 .. 1000\n"), 2;
  tb_error err;
  tb_mesh surf;
  const char *organ = argc > 4 ? argv[4] : "liver";
  const tb_organ_info *info = tb_organ_find(organ);
  if (!info) return fprintf(stderr, "unknown organ '%s'\n", organ), 2;
  if (tb_organ_surface(organ, 0, 1, &surf, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
  tb_sphpack_def pd = tb_sphpack_default_def(info->spheres);
  tb_spheres sp = {0};
  if (tb_sphere_pack(&surf, organ, &pd, &sp, NULL, &err))
    return fprintf(stderr, "%s\n", err.msg), 1;
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  tb_metaball *m = tb_metaball_create(sp.n, sp.c, sp.r, &surf, &set, &err);
  if (!m) return fprintf(stderr, "%s\n", err.msg), 1;
  for (int i = 0; i < 10; i++) tb_metaball_fix(m, i, 1); /* the largest ten hold it */
  if (tb_metaball_cut_begin(m, &cs, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
  tb_vec3 lo = sp.c[0], hi = sp.c[0];
  for (int i = 0; i < sp.n; i++) {
    tb_vec3 r = tb_v3(sp.r[i], sp.r[i], sp.r[i]);
    lo = tb_vmin(lo, tb_sub(sp.c[i], r)), hi = tb_vmax(hi, tb_add(sp.c[i], r));
  }
  double xm = 0.5 * (lo.x + hi.x), wy = hi.y - lo.y, wx = hi.x - lo.x;
  tb_vec3 *path = malloc(sizeof(tb_vec3) * (size_t)(frames + 1));
  double *ms = malloc(sizeof(double) * (size_t)frames), adv = 0, stp = 0;
  for (int k = 0; k <= frames; k++) {
    double t = (double)k / frames;
    path[k] = tb_v3(xm + 0.08 * wx * sin(M_PI * t), lo.y - 0.1 * wy + t * 1.2 * wy,
                    hi.z + 0.1 * (hi.z - lo.z));
  }
  tb_vec3 depth = tb_v3(0, 0, -1.2 * (hi.z - lo.z));
  int substeps = 0, maxsub = 0;
  for (int k = 1; k <= frames; k++) {
    tb_fold f;
    if (tb_fold_init(&f, path, k + 1, depth, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
    uint64_t t0 = tb_time_ns();
    int rc = tb_metaball_cut_advance(m, &f, &err) < 0;
    uint64_t t1 = tb_time_ns();
    rc = rc || tb_metaball_cut_step(m, 0.01, tb_v3(0, 0, -9.81), NULL, &err);
    uint64_t t2 = tb_time_ns();
    tb_fold_free(&f);
    if (rc) return fprintf(stderr, "frame %d: %s\n", k, err.msg), 1;
    ms[k - 1] = (double)(t2 - t0) * 1e-6, adv += (double)(t1 - t0) * 1e-6;
    stp += (double)(t2 - t1) * 1e-6;
    substeps += tb_metaball_cut_substeps(m);
    if (tb_metaball_cut_substeps(m) > maxsub) maxsub = tb_metaball_cut_substeps(m);
  }
  tb_metaball *plain = tb_metaball_create(sp.n, sp.c, sp.r, &surf, &set, &err);
  if (!plain) return fprintf(stderr, "%s\n", err.msg), 1;
  double *pms = malloc(sizeof(double) * (size_t)frames);
  for (int i = 0; i < 10; i++) tb_metaball_fix(plain, i, 1);
  for (int k = 0; k < frames; k++) {
    uint64_t t0 = tb_time_ns();
    tb_metaball_step(plain, 0.01, tb_v3(0, 0, -9.81), NULL);
    pms[k] = (double)(tb_time_ns() - t0) * 1e-6;
  }
  qsort(pms, (size_t)frames, sizeof(double), cmp);
  tb_metaball_destroy(plain);
  int np = tb_metaball_cut_points(m, NULL), driven = 0;
  for (int p = 0; p < np; p++) driven += tb_metaball_cut_driver(m, p) != -1;
  double omega = tb_metaball_cut_omega(m);
  tb_metaball_cut_report rep;
  uint64_t t0 = tb_time_ns();
  if (tb_metaball_cut_end(m, &rep, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
  double end_ms = (double)(tb_time_ns() - t0) * 1e-6;
  qsort(ms, (size_t)frames, sizeof(double), cmp);
  printf("%s: %d vertices, %d spheres; cut in %d frames, %s\n", organ, surf.nv, sp.n, frames,
         cs.per_sphere > 0 ? "per-sphere sampling" : "shared grid");
  printf(
      "cut frame (advance + cut_step): median %.3f ms, worst %.3f ms; mean advance %.3f ms, "
      "mean cut_step %.3f ms; %d points (%d driven), meshless substeps %.1f a frame (at "
      "most %d; omega %.0f rad/s at the end)\n",
      ms[frames / 2], ms[frames - 1], adv / frames, stp / frames, np, driven,
      (double)substeps / frames, maxsub, omega);
  printf(
      "cut_end %.2f ms: %d spheres removed (mean r %.3f) -> %d created (mean r %.3f): "
      "%.2fx as many, %.2fx the size; %d points, %d boundary, %d candidates, %d uncovered, %d "
      "dropped\n",
      end_ms, rep.removed, rep.removed_r, rep.created, rep.created_r,
      rep.removed ? (double)rep.created / rep.removed : 0,
      rep.removed_r > 0 ? rep.created_r / rep.removed_r : 0, rep.points, rep.boundary,
      rep.candidates, rep.uncovered, rep.dropped);
  printf(
      "for reference, tb_metaball_step uncut: median %.3f ms (the cut's own share of a frame: "
      "%.3f ms)\n",
      pms[frames / 2], ms[frames / 2] - pms[frames / 2]);
  free(path), free(ms), free(pms);
  tb_metaball_destroy(m);
  tb_spheres_free(&sp);
  tb_mesh_free(&surf);
  return 0;
}
