/* `tissuebench mesh spheres IN --count N --out OUT.sph` and `mesh spheres --info X.sph
 * [--surface IN]` (also `mesh info X.sph`): fill a closed surface with overlapping spheres
 * from its inner Voronoi poles (meshgen/tb_sphpack.h; the metaball patent's offline "Voronoi
 * analysis"), write them as SOFA's .sph (core/tb_spheres.h), and report their
 * count, radii and coverage of the organ. */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"
#include "core/tb_mesh_io.h"
#include "core/tb_spheres.h"
#include "core/tb_timer.h"
#include "meshgen/tb_sphpack.h"

#define USAGE                                                                            \
  "usage: tissuebench mesh spheres IN --count N --out OUT.sph [--samples S] [--seed K] " \
  "[--grid G]\n"                                                                         \
  "       tissuebench mesh spheres --info X.sph [--surface IN] [--grid G]\n"

/* A whole number in [lo, hi] or a message naming the option; 0 or -1. */
static int whole(const char *opt, const char *s, long lo, long hi, long *v) {
  char *end;
  errno = 0;
  long n = strtol(s, &end, 10);
  if (end == s || *end || errno || n < lo || n > hi) {
    fprintf(stderr, "tissuebench mesh spheres: %s '%s': give a whole number in [%ld, %ld]\n", opt,
            s, lo, hi);
    return -1;
  }
  *v = n;
  return 0;
}

void tb_spheres_print_info(FILE *f, const char *name, const tb_spheres *s) {
  double rmin = s->r[0], rmax = s->r[0], sum = 0;
  tb_vec3 lo = s->c[0], hi = s->c[0];
  for (int i = 0; i < s->n; i++) {
    rmin = s->r[i] < rmin ? s->r[i] : rmin;
    rmax = s->r[i] > rmax ? s->r[i] : rmax;
    sum += s->r[i];
    tb_vec3 a = tb_sub(s->c[i], tb_v3(s->r[i], s->r[i], s->r[i]));
    tb_vec3 b = tb_add(s->c[i], tb_v3(s->r[i], s->r[i], s->r[i]));
    lo = tb_v3(fmin(lo.x, a.x), fmin(lo.y, a.y), fmin(lo.z, a.z));
    hi = tb_v3(fmax(hi.x, b.x), fmax(hi.y, b.y), fmax(hi.z, b.z));
  }
  fprintf(f, "spheres     %s\n", name);
  fprintf(f, "count       %d", s->n);
  if (s->declared >= 0 && s->declared != s->n)
    fprintf(f, " (the header's #nums says %d; the listed spheres count)", s->declared);
  fprintf(f, "\nradius      %.6g .. %.6g (mean %.6g)\n", rmin, rmax, sum / s->n);
  fprintf(f, "bbox        [%.6g %.6g %.6g] - [%.6g %.6g %.6g]\n", lo.x, lo.y, lo.z, hi.x, hi.y,
          hi.z);
}

static void print_coverage(const tb_sphere_coverage *c, int grid) {
  printf("volume      %.2f%% covered (%d of %d points of a %d grid inside the surface)\n",
         100 * c->volume, c->grid_covered, c->grid_inside, grid);
  printf("skin reach  %.2f%% of surface vertices (%d of %d have a sphere at r <= d <= 2r)\n",
         100 * c->reach, c->reached, c->verts);
  printf("sum volume  %.3f x the enclosed volume (overlap)\n", c->sphere_volume);
  printf("outside     %d centres outside the surface, max protrusion %.3g\n", c->centres_outside,
         c->max_protrusion);
}

static int read_surface(const char *path, tb_mesh *m) {
  tb_error err;
  if (tb_mesh_read(path, m, &err)) {
    fprintf(stderr, "%s\n", err.msg);
    return -1;
  }
  return 0;
}

static int coverage(const char *surf_path, const tb_spheres *s, int grid) {
  tb_mesh m;
  tb_error err;
  tb_sphere_coverage c;
  if (read_surface(surf_path, &m)) return TB_EXIT_INPUT;
  int rc = tb_sphere_coverage_of(&m, surf_path, s, grid, &c, &err);
  tb_mesh_free(&m);
  if (rc) {
    fprintf(stderr, "%s\n", err.msg);
    return TB_EXIT_INPUT;
  }
  print_coverage(&c, grid);
  return TB_EXIT_OK;
}

int tb_spheres_info(const char *path, const char *surface, int grid) {
  tb_spheres s;
  tb_error err;
  if (tb_spheres_read(path, &s, &err)) {
    fprintf(stderr, "%s\n", err.msg);
    return TB_EXIT_INPUT;
  }
  tb_spheres_print_info(stdout, path, &s);
  int rc = surface ? coverage(surface, &s, grid) : TB_EXIT_OK;
  tb_spheres_free(&s);
  return rc;
}

int tb_cmd_mesh_spheres(int argc, char **argv) {
  const char *in = NULL, *out = NULL, *info = NULL, *surface = NULL;
  long count = 0, samples = 0, seed = 14, grid = 64;
  int have_count = 0;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    int bad = 0;
    if (!strcmp(a, "--count") && v)
      bad = whole(a, argv[++i], 1, 1000000, &count), have_count = 1;
    else if (!strcmp(a, "--samples") && v)
      bad = whole(a, argv[++i], 0, 10000000, &samples);
    else if (!strcmp(a, "--seed") && v)
      bad = whole(a, argv[++i], 0, 2147483647, &seed);
    else if (!strcmp(a, "--grid") && v)
      bad = whole(a, argv[++i], 4, 1000, &grid);
    else if (!strcmp(a, "--out") && v)
      out = argv[++i];
    else if (!strcmp(a, "--info") && v)
      info = argv[++i];
    else if (!strcmp(a, "--surface") && v)
      surface = argv[++i];
    else if (a[0] != '-' && !in)
      in = a;
    else {
      fprintf(stderr, "tissuebench mesh spheres: unknown or incomplete option '%s'\n%s", a, USAGE);
      return TB_EXIT_INPUT;
    }
    if (bad) return TB_EXIT_INPUT;
  }
  if (info && !in && !out && !have_count) return tb_spheres_info(info, surface, (int)grid);
  if (!in || !out || !have_count || info || surface) {
    fprintf(stderr, "%s", USAGE);
    return TB_EXIT_INPUT;
  }
  tb_mesh m;
  if (read_surface(in, &m)) return TB_EXIT_INPUT;
  tb_sphpack_def def = tb_sphpack_default_def((int)count);
  def.samples = (int)samples;
  def.seed = (uint64_t)seed;
  tb_spheres s;
  tb_sphpack_stats st;
  tb_error err;
  tb_clock clock = tb_clock_start();
  int rc = tb_sphere_pack(&m, in, &def, &s, &st, &err);
  double wall_ms, cpu_ms;
  tb_clock_ms(&clock, &wall_ms, &cpu_ms);
  if (rc) {
    fprintf(stderr, "%s\n", err.msg);
    tb_mesh_free(&m);
    return TB_EXIT_INPUT;
  }
  printf("surface     %s (%d vertices, %d triangles)\n", in, m.nv, m.ntri);
  printf("samples     %d (%d inner Voronoi poles, %d distinct inside the surface)\n", st.samples,
         st.poles, st.candidates);
  printf("packed      %d of %ld spheres in %.3f s (%.3f s CPU; last pass alpha %g)\n", s.n, count,
         wall_ms * 1e-3, cpu_ms * 1e-3, st.alpha);
  if (s.n < count)
    printf("note        only %d distinct candidate centres: raise --samples for more spheres\n",
           st.candidates);
  tb_sphere_coverage c;
  rc = tb_sphere_coverage_of(&m, in, &s, (int)grid, &c, &err);
  if (!rc) {
    tb_spheres_print_info(stdout, out, &s);
    print_coverage(&c, (int)grid);
  }
  if (!rc && (rc = tb_spheres_write(out, &s, &err)) == 0) printf("wrote %s\n", out);
  if (rc) fprintf(stderr, "tissuebench mesh spheres: %s\n", err.msg);
  tb_spheres_free(&s);
  tb_mesh_free(&m);
  return rc ? TB_EXIT_FAIL : TB_EXIT_OK;
}
