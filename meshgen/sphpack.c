/* Sphere packing of a closed surface from the inner Voronoi poles of surface
 * samples (Amenta, Choi & Kolluri, "The power crust", 2001; the metaball
 * patent's offline "Voronoi analysis"), greedy selection to a target count,
 * and its coverage report. The algorithm is described in meshgen/tb_sphpack.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_sphpack.h"
#include "core/tb_rng.h"

tb_sphpack_def tb_sphpack_default_def(int count) {
  tb_sphpack_def d = {count, 0, 14};
  return d;
}

typedef struct cand {
  tb_vec3 c;
  double r;
} cand;

/* Largest radius first; equal radii by centre, lexicographically. */
static int cand_cmp(const void *pa, const void *pb) {
  const cand *a = pa, *b = pb;
  if (a->r != b->r) return a->r > b->r ? -1 : 1;
  if (a->c.x != b->c.x) return a->c.x < b->c.x ? -1 : 1;
  if (a->c.y != b->c.y) return a->c.y < b->c.y ? -1 : 1;
  if (a->c.z != b->c.z) return a->c.z < b->c.z ? -1 : 1;
  return 0;
}

static int *used_vertices(const tb_mesh *m, int *nused) {
  int *used = calloc((size_t)m->nv + 1, sizeof *used);
  if (!used) return NULL;
  for (int k = 0; k < 3 * m->ntri; k++) used[m->tri[k]] = 1;
  *nused = 0;
  for (int v = 0; v < m->nv; v++) *nused += used[v];
  return used;
}

/* The used vertices (normals: area-weighted sums of their triangles'), then
 * want - (used vertices) points spread over the triangles by area, each at
 * a seeded uniform random spot (normal: its triangle's). orient = +-1 turns
 * the normals outward. p and n need room for max(want, nv). */
static int sample(const tb_mesh *m, double orient, int want, uint64_t seed, tb_vec3 *p,
                  tb_vec3 *n) {
  int nused, np = 0;
  int *used = used_vertices(m, &nused);
  tb_vec3 *vn = calloc((size_t)m->nv + 1, sizeof *vn);
  if (!used || !vn) {
    free(used), free(vn);
    return -1;
  }
  double area = 0;
  for (int t = 0; t < m->ntri; t++) {
    const int *v = m->tri + 3 * t;
    tb_vec3 c = tb_cross(tb_sub(m->x[v[1]], m->x[v[0]]), tb_sub(m->x[v[2]], m->x[v[0]]));
    for (int k = 0; k < 3; k++) vn[v[k]] = tb_add(vn[v[k]], c);
    area += tb_len(c);
  }
  for (int v = 0; v < m->nv; v++)
    if (used[v]) {
      p[np] = m->x[v];
      n[np++] = tb_scale(vn[v], orient);
    }
  long extra = want > nused ? want - nused : 0;
  tb_rng rng = tb_rng_seed(seed);
  double cum = 0;
  long done = 0;
  for (int t = 0; t < m->ntri && extra > 0; t++) {
    const int *v = m->tri + 3 * t;
    tb_vec3 e1 = tb_sub(m->x[v[1]], m->x[v[0]]), e2 = tb_sub(m->x[v[2]], m->x[v[0]]);
    tb_vec3 c = tb_cross(e1, e2);
    cum += tb_len(c);
    long upto = t == m->ntri - 1 ? extra : (long)floor((double)extra * (cum / area));
    if (upto > extra) upto = extra;
    for (; done < upto; done++) {
      double a = tb_rng_uniform(&rng), b = tb_rng_uniform(&rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      p[np] = tb_add(m->x[v[0]], tb_add(tb_scale(e1, a), tb_scale(e2, b)));
      n[np++] = tb_scale(c, orient);
    }
  }
  free(used), free(vn);
  return np;
}

/* Candidates: the inner poles inside the surface, radius the distance to
 * it, sorted largest first, duplicates dropped. Returns how many. */
static int candidates(const tb_closed_surface *S, const tb_vec3 *pole, const double *pole_r, int np,
                      cand *c) {
  int nc = 0;
  for (int i = 0; i < np; i++) {
    if (!(pole_r[i] > 0) || !tb_closed_surface_inside(S, pole[i])) continue;
    double d = tb_closed_surface_distance(S, pole[i]);
    if (d > 0) c[nc++] = (cand){pole[i], d};
  }
  qsort(c, (size_t)nc, sizeof *c, cand_cmp);
  int k = 0;
  for (int i = 0; i < nc; i++)
    if (k == 0 || cand_cmp(&c[k - 1], &c[i])) c[k++] = c[i];
  return k;
}

/* Largest first, passes of decreasing alpha (meshgen/tb_sphpack.h); the
 * candidates below TINY times the largest radius only when the others do
 * not reach the count. */
#define TINY 0.05
static int choose(const cand *c, int nc, int count, tb_spheres *out, double *alpha_used) {
  static const double alphas[] = {1, 0.75, 0.5, 0.35, 0.25, 0.15, 0.1, 0.05, 0};
  char *taken = calloc((size_t)nc + 1, 1);
  if (!taken) return -1;
  int na = (int)(sizeof alphas / sizeof *alphas);
  double rmin = nc > 0 ? TINY * c[0].r : 0;
  for (int a = 0; a < 2 * na && out->n < count; a++) {
    double al = alphas[a % na];
    *alpha_used = al;
    for (int i = 0; i < nc && out->n < count; i++) {
      if (taken[i] || (a < na && c[i].r < rmin)) continue;
      int near = 0;
      for (int j = 0; j < out->n && !near; j++) {
        tb_vec3 d = tb_sub(c[i].c, out->c[j]);
        double lim = al * out->r[j];
        near = tb_dot(d, d) < lim * lim;
      }
      if (near) continue;
      if (tb_spheres_push(out, c[i].c, c[i].r)) {
        free(taken);
        return -1;
      }
      taken[i] = 1;
    }
  }
  free(taken);
  return 0;
}

int tb_sphere_pack(const tb_mesh *surf, const char *name, const tb_sphpack_def *def,
                   tb_spheres *out, tb_sphpack_stats *stats, tb_error *err) {
  memset(out, 0, sizeof *out);
  out->declared = -1;
  tb_sphpack_stats st = {0, 0, 0, 0};
  if (def->count < 1 || def->count > 10000000 || def->samples < 0 || def->samples > 50000000)
    return tb_error_set(err, name, 0, "bad settings: count %d, samples %d", def->count,
                        def->samples);
  tb_mesh tris = *surf; /* the triangles only, also of a tet mesh */
  tris.ntet = 0, tris.tet = NULL;
  tb_closed_surface S;
  if (tb_closed_surface_init(&S, &tris, name, err)) return -1;
  double vol = tb_mesh_volume(&tris);
  if (!(fabs(vol) > 0)) {
    tb_closed_surface_free(&S);
    return tb_error_set(err, name, 0, "the surface encloses no volume");
  }
  int want = def->samples;
  if (want == 0) want = 20 * def->count > 4000 ? 20 * def->count : 4000;
  int room = want > surf->nv ? want : surf->nv;
  tb_vec3 *p = malloc((size_t)room * sizeof *p), *n = malloc((size_t)room * sizeof *n);
  tb_vec3 *pole = malloc((size_t)room * sizeof *pole);
  double *pole_r = malloc((size_t)room * sizeof *pole_r);
  cand *c = malloc((size_t)room * sizeof *c);
  int rc = 0;
  if (!p || !n || !pole || !pole_r || !c) rc = tb_error_set(err, name, 0, "out of memory");
  if (!rc && (st.samples = sample(&tris, vol > 0 ? 1 : -1, want, def->seed, p, n)) < 0)
    rc = tb_error_set(err, name, 0, "out of memory");
  if (!rc && tb_voronoi_poles(p, n, st.samples, pole, pole_r))
    rc = tb_error_set(err, name, 0, "CGAL's Delaunay triangulation of the samples failed");
  if (!rc) {
    for (int i = 0; i < st.samples; i++) st.poles += pole_r[i] > 0;
    st.candidates = candidates(&S, pole, pole_r, st.samples, c);
    if (choose(c, st.candidates, def->count, out, &st.alpha))
      rc = tb_error_set(err, name, 0, "out of memory");
  }
  if (!rc && out->n == 0)
    rc = tb_error_set(err, name, 0, "no inner Voronoi pole inside the surface");
  if (rc) tb_spheres_free(out);
  if (stats) *stats = st;
  free(p), free(n), free(pole), free(pole_r), free(c);
  tb_closed_surface_free(&S);
  return rc;
}

int tb_sphere_coverage_of(const tb_mesh *surf, const char *name, const tb_spheres *s, int grid,
                          tb_sphere_coverage *cov, tb_error *err) {
  memset(cov, 0, sizeof *cov);
  if (grid < 4 || grid > 2000) return tb_error_set(err, name, 0, "grid %d not in [4, 2000]", grid);
  tb_mesh tris = *surf;
  tris.ntet = 0, tris.tet = NULL;
  tb_closed_surface S;
  if (tb_closed_surface_init(&S, &tris, name, err)) return -1;
  int nused;
  int *used = used_vertices(&tris, &nused);
  double *z = malloc(((size_t)tris.ntri + 1) * sizeof *z);
  if (!used || !z) {
    free(used), free(z);
    tb_closed_surface_free(&S);
    return tb_error_set(err, name, 0, "out of memory");
  }
  tb_vec3 lo, hi;
  tb_mesh_bbox(&tris, &lo, &hi);
  tb_vec3 ext = tb_sub(hi, lo);
  double h = fmax(ext.x, fmax(ext.y, ext.z)) / grid;
  int nx = (int)ceil(ext.x / h), ny = (int)ceil(ext.y / h), nz = (int)ceil(ext.z / h);
  for (int i = 0; i < nx; i++)
    for (int j = 0; j < ny; j++) {
      double px = lo.x + (i + 0.51234) * h, py = lo.y + (j + 0.53719) * h;
      int nc = tb_closed_surface_column(&S, px, py, z), below = 0;
      for (int k = 0; k < nz; k++) {
        tb_vec3 q = tb_v3(px, py, lo.z + (k + 0.52711) * h);
        while (below < nc && z[below] < q.z) below++;
        if (!(below & 1)) continue;
        cov->grid_inside++;
        for (int m = 0; m < s->n; m++) {
          tb_vec3 d = tb_sub(q, s->c[m]);
          if (tb_dot(d, d) <= s->r[m] * s->r[m]) {
            cov->grid_covered++;
            break;
          }
        }
      }
    }
  cov->volume = cov->grid_inside ? (double)cov->grid_covered / cov->grid_inside : 0;
  for (int v = 0; v < tris.nv; v++) {
    if (!used[v]) continue;
    cov->verts++;
    for (int m = 0; m < s->n; m++) {
      double d = tb_dist(tris.x[v], s->c[m]);
      if (d >= s->r[m] * (1 - 1e-9) && d <= 2 * s->r[m]) {
        cov->reached++;
        break;
      }
    }
  }
  cov->reach = cov->verts ? (double)cov->reached / cov->verts : 0;
  double sv = 0, vol = fabs(tb_mesh_volume(&tris));
  cov->max_protrusion = -INFINITY;
  for (int m = 0; m < s->n; m++) {
    sv += 4.0 / 3.0 * M_PI * s->r[m] * s->r[m] * s->r[m];
    cov->centres_outside += !tb_closed_surface_inside(&S, s->c[m]);
    cov->max_protrusion =
        fmax(cov->max_protrusion, s->r[m] - tb_closed_surface_distance(&S, s->c[m]));
  }
  cov->sphere_volume = vol > 0 ? sv / vol : 0;
  free(used), free(z);
  tb_closed_surface_free(&S);
  return 0;
}
