/* Tests of the surface cut (cutting/tb_cut_surface.h; the metaball patent's
 * step 3 (5): surface splitting and the crack): straight and folded cuts
 * through a slab and a geodesic sphere, cuts stopping inside, degenerate
 * blades (along an edge, through a vertex, tangent, missing), determinism
 * and the layout of the result. Oracles: the closed-manifold check, the
 * component count, the volume (the divergence theorem over the new surface
 * against the old one and against the box's exact parts), the sides of the
 * parts and of the crack vertices against the plane. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "cutting/tb_cut_surface.h"
#include "meshgen/tb_meshgen.h"

/* A closed box [0,lx]x[0,ly]x[0,lz], its faces gridded n? cells, outward. */
typedef struct surf {
  int nv, ntri;
  tb_vec3 *x;
  int *tri;
} surf;

static void surf_free(surf *s) {
  free(s->x), free(s->tri);
  memset(s, 0, sizeof *s);
}

static void make_box(surf *s, double lx, double ly, double lz, int nx, int ny, int nz) {
  int n[3] = {nx, ny, nz};
  double l[3] = {lx, ly, lz};
  int total = (nx + 1) * (ny + 1) * (nz + 1);
  int *id = malloc((size_t)total * sizeof *id);
  s->x = malloc((size_t)total * sizeof *s->x);
  s->tri = malloc((size_t)4 * (nx * ny + ny * nz + nz * nx) * 3 * sizeof *s->tri);
  s->nv = s->ntri = 0;
  for (int k = 0; k <= nz; k++)
    for (int j = 0; j <= ny; j++)
      for (int i = 0; i <= nx; i++) {
        int g = i + (nx + 1) * (j + (ny + 1) * k);
        id[g] = -1;
        if (i == 0 || j == 0 || k == 0 || i == nx || j == ny || k == nz) {
          id[g] = s->nv;
          s->x[s->nv++] = tb_v3(lx * i / nx, ly * j / ny, lz * k / nz);
        }
      }
  (void)l;
  for (int a = 0; a < 3; a++) {
    int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int side = 0; side < 2; side++)
      for (int u = 0; u < n[b]; u++)
        for (int v = 0; v < n[c]; v++) {
          int q[4];
          const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
          for (int m = 0; m < 4; m++) {
            int ijk[3];
            ijk[a] = side ? n[a] : 0, ijk[b] = u + du[m], ijk[c] = v + dv[m];
            q[m] = id[ijk[0] + (nx + 1) * (ijk[1] + (ny + 1) * ijk[2])];
          }
          /* (b, c) counter-clockwise has normal +a: keep on the max side. */
          int *t = s->tri + 3 * s->ntri;
          if (side)
            t[0] = q[0], t[1] = q[1], t[2] = q[2], t[3] = q[0], t[4] = q[2], t[5] = q[3];
          else
            t[0] = q[0], t[1] = q[2], t[2] = q[1], t[3] = q[0], t[4] = q[3], t[5] = q[2];
          s->ntri += 2;
        }
  }
  free(id);
}

static void make_sphere(surf *s, int nv) {
  tb_mesh m;
  tb_error err;
  memset(&m, 0, sizeof m);
  TB_CHECK(tb_geosphere(nv, 1.0, &m, &err) == 0);
  s->nv = m.nv, s->ntri = m.ntri, s->x = m.x, s->tri = m.tri;
  m.x = NULL, m.tri = NULL;
  tb_mesh_free(&m);
}

/* Volume of each component (by a vertex flood), into vol[0..n). Returns n. */
static int component_volumes(const tb_cut_result *r, double *vol, int max, int *comp_of) {
  for (int v = 0; v < r->nv; v++) comp_of[v] = -1;
  int n = 0, changed = 1;
  /* label propagation: simple and enough for tests */
  for (int v = 0; v < r->nv; v++) comp_of[v] = v;
  while (changed) {
    changed = 0;
    for (int t = 0; t < r->ntri; t++) {
      int *q = r->tri + 3 * t, m = comp_of[q[0]];
      if (comp_of[q[1]] < m) m = comp_of[q[1]];
      if (comp_of[q[2]] < m) m = comp_of[q[2]];
      for (int k = 0; k < 3; k++)
        if (comp_of[q[k]] != m) comp_of[q[k]] = m, changed = 1;
    }
  }
  int *label = malloc((size_t)r->nv * sizeof *label);
  for (int v = 0; v < r->nv; v++) label[v] = -1;
  for (int v = 0; v < r->nv; v++)
    if (comp_of[v] == v) label[v] = n++;
  for (int v = 0; v < r->nv; v++) comp_of[v] = label[comp_of[v]];
  free(label);
  for (int i = 0; i < max; i++) vol[i] = 0;
  for (int t = 0; t < r->ntri; t++) {
    int *q = r->tri + 3 * t, c = comp_of[q[0]];
    if (c >= 0 && c < max) vol[c] += tb_dot(r->x[q[0]], tb_cross(r->x[q[1]], r->x[q[2]])) / 6.0;
  }
  return n;
}

/* The checks every result must pass. */
static void check_valid(const char *what, const surf *s, const tb_cut_result *r) {
  TB_CHECK_MSG(tb_cut_is_closed_manifold(r->nv, r->ntri, r->tri), "%s: not a closed manifold",
               what);
  TB_CHECK_MSG(r->nv >= s->nv, "%s: %d vertices < %d", what, r->nv, s->nv);
  for (int v = 0; v < s->nv && v < r->nv; v++)
    TB_CHECK_MSG(!memcmp(&r->x[v], &s->x[v], sizeof(tb_vec3)), "%s: old vertex %d moved", what, v);
  for (int v = s->nv; v < r->nv; v++)
    TB_CHECK_MSG(r->origin[v] < s->nv &&
                     (r->origin[v] < 0 || !memcmp(&r->x[v], &s->x[r->origin[v]], sizeof(tb_vec3))),
                 "%s: copy %d of %d is elsewhere", what, v, r->origin[v]);
  double v0 = tb_cut_volume(s->x, s->ntri, s->tri), v1 = tb_cut_volume(r->x, r->ntri, r->tri);
  TB_CHECK_MSG(fabs(v1 - v0) <= 1e-9 * fabs(v0), "%s: volume %.17g, was %.17g", what, v1, v0);
  TB_CHECK_MSG(r->components_before == tb_cut_components(s->nv, s->ntri, s->tri) &&
                   r->components_after == tb_cut_components(r->nv, r->ntri, r->tri),
               "%s: component counts %d %d", what, r->components_before, r->components_after);
  /* Untouched triangles keep their slots; their corners are old vertices or copies of them. */
  for (int t = 0; t < s->ntri && t < r->ntri; t++) {
    TB_CHECK_MSG(r->tri_from[t] == t, "%s: slot %d comes from %d", what, t, r->tri_from[t]);
    int same = 1;
    for (int k = 0; k < 3; k++) {
      int a = r->tri[3 * t + k], o = s->tri[3 * t + k];
      same &= a == o || (a >= s->nv && r->origin[a] == o);
    }
    int splitlike = 0;
    for (int u = s->ntri; u < r->ntri && !splitlike; u++) splitlike = r->tri_from[u] == t;
    TB_CHECK_MSG(same || splitlike, "%s: triangle %d changed without being split", what, t);
    for (int k = 0; k < 3 && same && !splitlike; k++) {
      int a = r->tri[3 * t + k];
      if (a != s->tri[3 * t + k])
        TB_CHECK_MSG(r->side[a] == -1, "%s: copy %d of %d on side %d", what, a, r->origin[a],
                     r->side[a]);
    }
  }
}

/* Old triangles not split whose corners were renamed to copies (the - side of old cut
 * vertices). */
static int renamed_corners(const surf *s, const tb_cut_result *r) {
  int n = 0;
  for (int t = 0; t < s->ntri; t++)
    for (int k = 0; k < 3; k++) {
      int a = r->tri[3 * t + k];
      n += a != s->tri[3 * t + k] && a >= s->nv && r->origin[a] == s->tri[3 * t + k];
    }
  return n;
}

static tb_fold make_fold(const tb_vec3 *p, int n, tb_vec3 d) {
  tb_fold f;
  tb_error err;
  TB_CHECK(tb_fold_init(&f, p, n, d, &err) == 0);
  return f;
}

/* 1. The slab cut straight through at x = 1.3. */
static void test_slab_straight(void) {
  surf s;
  make_box(&s, 4, 3, 1, 24, 18, 5);
  TB_CHECK(tb_cut_is_closed_manifold(s.nv, s.ntri, s.tri));
  TB_CHECK_NEAR(tb_cut_volume(s.x, s.ntri, s.tri), 12.0, 1e-12);
  const tb_vec3 p[2] = {{1.3, -1, 2}, {1.3, 4, 2}};
  tb_fold f = make_fold(p, 2, tb_v3(0, 0, -4));
  tb_cut_result r;
  tb_error err;
  TB_CHECK_MSG(tb_cut_surface(s.nv, s.x, s.ntri, s.tri, &f, NULL, &r, &err) == 0, "%s", err.msg);
  check_valid("slab", &s, &r);
  TB_CHECK(r.cut == 1 && r.components_before == 1 && r.components_after == 2);
  TB_CHECK(r.split_tris > 0 && r.crack_tris > 0 && r.perturbed == 0);
  int *comp = malloc((size_t)r.nv * sizeof *comp);
  double vol[4];
  TB_CHECK(component_volumes(&r, vol, 4, comp) == 2);
  /* the parts: x <= 1.3 (+ side of n = -x) and x >= 1.3, volumes 3.9 and 8.1 */
  double lo = vol[0] < vol[1] ? vol[0] : vol[1], hi = vol[0] < vol[1] ? vol[1] : vol[0];
  TB_CHECK_NEAR(lo, 1.3 * 3, 1e-9 * 12);
  TB_CHECK_NEAR(hi, 2.7 * 3, 1e-9 * 12);
  for (int v = 0; v < r.nv; v++) {
    int c = comp[v];
    double xv = r.x[v].x;
    int left = vol[c] < 6;
    TB_CHECK_MSG(left ? xv <= 1.3 + 1e-12 : xv >= 1.3 - 1e-12, "vertex %d at x %g in part %d", v,
                 xv, c);
    if (r.side[v] == 1) TB_CHECK_MSG(left, "vertex %d: side +1 on the right", v);
    if (r.side[v] == -1) TB_CHECK_MSG(!left, "vertex %d: side -1 on the left", v);
  }
  /* the crack triangles lie on the plane */
  int ncrack = 0;
  for (int t = 0; t < r.ntri; t++) {
    if (r.tri_from[t] >= 0) continue;
    ncrack++;
    for (int k = 0; k < 3; k++) TB_CHECK_NEAR(r.x[r.tri[3 * t + k]].x, 1.3, 1e-12);
  }
  TB_CHECK(ncrack == r.crack_tris);
  /* the reskin list: ascending, every new vertex in it */
  for (int i = 1; i < r.nreskin; i++) TB_CHECK(r.reskin[i] > r.reskin[i - 1]);
  TB_CHECK(r.nreskin >= r.nv - s.nv);
  free(comp);
  tb_cut_result_free(&r);
  tb_fold_free(&f);
  surf_free(&s);
}

/* Cuts s with f; checks validity, the component count and that the surface changed. */
static void cut_expect(const char *what, const surf *s, const tb_fold *f, int comps, int changed,
                       tb_cut_result *keep) {
  tb_cut_result r;
  tb_error err;
  int rc = tb_cut_surface(s->nv, s->x, s->ntri, s->tri, f, NULL, &r, &err);
  TB_CHECK_MSG(rc == 0, "%s: %s", what, err.msg);
  if (keep) memset(keep, 0, sizeof *keep);
  if (rc) return;
  check_valid(what, s, &r);
  TB_CHECK_MSG(r.components_after == comps && r.cut == changed,
               "%s: %d components (want %d), cut %d (want %d)", what, r.components_after, comps,
               r.cut, changed);
  if (!changed)
    TB_CHECK_MSG(r.nv == s->nv && r.ntri == s->ntri &&
                     !memcmp(r.tri, s->tri, sizeof(int) * 3 * (size_t)s->ntri) && r.nreskin == 0,
                 "%s: a miss changed the surface", what);
  if (keep)
    *keep = r;
  else
    tb_cut_result_free(&r);
}

/* 2. A 3-piece fold through a geodesic sphere: through, and stopping inside. */
static void test_sphere_folded(void) {
  surf s;
  make_sphere(&s, 2562);
  const tb_vec3 p[4] = {{-2, -0.2, -2}, {-0.3, 0.1, -2}, {0.4, -0.15, -2}, {2, 0.2, -2}};
  tb_fold f = make_fold(p, 4, tb_v3(0, 0, 4));
  tb_cut_result r;
  cut_expect("sphere through", &s, &f, 2, 1, &r);
  /* every crack vertex on the fold */
  for (int t = 0; t < r.ntri; t++)
    if (r.tri_from[t] < 0)
      for (int k = 0; k < 3; k++) {
        tb_fold_near nr;
        tb_fold_nearest(&f, r.x[r.tri[3 * t + k]], &nr);
        TB_CHECK_MSG(nr.dist <= 1e-12, "crack vertex %d off the fold by %g", r.tri[3 * t + k],
                     nr.dist);
      }
  TB_CHECK(r.crack_tris > 0 && r.split_tris > 0);
  tb_cut_result_free(&r);
  tb_fold_free(&f);
  /* the depth edge at z = 0.5 inside the sphere: a slit, one component */
  f = make_fold(p, 4, tb_v3(0, 0, 2.5));
  cut_expect("sphere slit", &s, &f, 1, 1, &r);
  int shared = 0, plus = 0, minus = 0;
  for (int v = 0; v < r.nv; v++) {
    shared += r.side[v] == 0 && fabs(r.x[v].z - 0.5) < 1e-12;
    plus += r.side[v] == 1, minus += r.side[v] == -1;
  }
  TB_CHECK_MSG(shared >= 4 && plus > 0 && plus == minus, "slit: %d shared, %d +, %d -", shared,
               plus, minus);
  /* the floor (the depth edge inside) and the creases split like the rest of the crack: no
   * crack triangle much longer than the surface's edges */
  double mean = 0, longest = 0;
  for (int k = 0; k < 3 * s.ntri; k++)
    mean += tb_dist(s.x[s.tri[k]], s.x[s.tri[k - k % 3 + (k + 1) % 3]]) / (3.0 * s.ntri);
  for (int t = 0; t < r.ntri; t++)
    for (int k = 0; k < 3 && r.tri_from[t] < 0; k++)
      longest = fmax(longest, tb_dist(r.x[r.tri[3 * t + k]], r.x[r.tri[3 * t + (k + 1) % 3]]));
  TB_CHECK_MSG(longest < 2 * mean, "slit: a crack edge %.3f long, the mean edge %.3f", longest,
               mean);
  tb_cut_result_free(&r);
  tb_fold_free(&f);
  /* a slit from the side: the blade enters along x and its end edge stays inside */
  const tb_vec3 q[3] = {{-2, -0.1, -2}, {-0.5, 0.2, -2}, {0.3, 0.0, -2}};
  f = make_fold(q, 3, tb_v3(0, 0, 4));
  cut_expect("sphere end inside", &s, &f, 1, 1, NULL);
  tb_fold_free(&f);
  surf_free(&s);
}

/* 3. Degenerate blades. */
static void test_degenerate(void) {
  surf box;
  make_box(&box, 2, 2, 2, 8, 8, 8); /* spacing 0.25: the planes below hit vertices exactly */
  const tb_vec3 pe[2] = {{0.5, -1, 3}, {0.5, 3, 3}};
  tb_fold f = make_fold(pe, 2, tb_v3(0, 0, -4));
  tb_cut_result r;
  tb_error err;
  cut_expect("along edges", &box, &f, 2, 1, &r);
  /* nothing split: the cut runs along edges; its old vertices got - copies */
  TB_CHECK_MSG(r.split_tris == 0 && renamed_corners(&box, &r) > 0 && r.nv > box.nv,
               "along edges: %d split, %d renamed", r.split_tris, renamed_corners(&box, &r));
  for (int v = box.nv; v < r.nv; v++)
    TB_CHECK(r.side[v] != 0 || r.x[v].x == 0.5); /* new: copies (-) or crack points */
  tb_cut_result_free(&r);
  tb_fold_free(&f);
  /* along a face diagonal: the plane x = y contains the diagonals of some faces */
  const tb_vec3 pd[2] = {{-1, -1, 3}, {3, 3, 3}};
  f = make_fold(pd, 2, tb_v3(0, 0, -4));
  cut_expect("along diagonals", &box, &f, 2, 1, NULL);
  tb_fold_free(&f);
  /* the blade in the plane of a face (x = 2): refused or unchanged, never broken */
  const tb_vec3 pc[2] = {{2, -1, 3}, {2, 3, 3}};
  f = make_fold(pc, 2, tb_v3(0, 0, -4));
  if (tb_cut_surface(box.nv, box.x, box.ntri, box.tri, &f, NULL, &r, &err) == 0) {
    check_valid("in a face", &box, &r);
    TB_CHECK(r.components_after <= 2);
    tb_cut_result_free(&r);
  } else {
    TB_CHECK(strstr(err.msg, "tb_cut_surface") != NULL && r.nv == 0 && r.tri == NULL);
  }
  tb_fold_free(&f);
  /* the whole length of the slab, partly deep (a slit) and through */
  const tb_vec3 pl[3] = {{-1, 0.8, 3}, {1, 1.1, 3}, {3, 0.9, 3}};
  f = make_fold(pl, 3, tb_v3(0, 0, -2.5));
  cut_expect("whole length, slit", &box, &f, 1, 1, NULL);
  tb_fold_free(&f);
  f = make_fold(pl, 3, tb_v3(0, 0, -4));
  cut_expect("whole length, through", &box, &f, 2, 1, NULL);
  tb_fold_free(&f);
  surf_free(&box);

  surf s;
  make_sphere(&s, 642);
  /* through a vertex: a vertical plane containing vertex 7 */
  tb_vec3 xv = s.x[7], e = tb_v3(cos(0.3), sin(0.3), 0);
  const tb_vec3 pv[2] = {tb_madd(tb_madd(xv, -3, e), -3, tb_v3(0, 0, 1)),
                         tb_madd(tb_madd(xv, 3, e), -3, tb_v3(0, 0, 1))};
  f = make_fold(pv, 2, tb_v3(0, 0, 6));
  cut_expect("through a vertex", &s, &f, 2, 1, NULL);
  tb_fold_free(&f);
  /* tangent: the plane through vertex 7 perpendicular to its radius touches only it */
  tb_vec3 nrm = tb_normalize(xv), a = tb_normalize(tb_cross(nrm, tb_v3(0.3, 0.5, 0.8)));
  tb_vec3 b = tb_cross(nrm, a);
  const tb_vec3 pt[2] = {tb_madd(tb_madd(xv, -2, a), -2, b), tb_madd(tb_madd(xv, 2, a), -2, b)};
  f = make_fold(pt, 2, tb_scale(b, 4));
  cut_expect("tangent", &s, &f, 1, 0, NULL);
  tb_fold_free(&f);
  /* missing entirely */
  const tb_vec3 pm[2] = {{5, -1, -1}, {5, 1, -1}};
  f = make_fold(pm, 2, tb_v3(0, 0, 2));
  cut_expect("miss", &s, &f, 1, 0, NULL);
  tb_fold_free(&f);
  surf_free(&s);
}

/* 4. Same input, same output, bit for bit. */
static void test_deterministic(void) {
  surf s;
  make_sphere(&s, 1002);
  const tb_vec3 p[4] = {{-2, -0.2, -2}, {-0.3, 0.1, -2}, {0.4, -0.15, -2}, {2, 0.2, -2}};
  tb_fold f = make_fold(p, 4, tb_v3(0, 0, 2.7));
  tb_cut_result r[2];
  tb_error err;
  for (int i = 0; i < 2; i++)
    TB_CHECK_MSG(tb_cut_surface(s.nv, s.x, s.ntri, s.tri, &f, NULL, &r[i], &err) == 0, "%s",
                 err.msg);
  TB_CHECK(r[0].nv == r[1].nv && r[0].ntri == r[1].ntri && r[0].nreskin == r[1].nreskin);
  if (r[0].nv == r[1].nv && r[0].ntri == r[1].ntri && r[0].nreskin == r[1].nreskin) {
    TB_CHECK(!memcmp(r[0].x, r[1].x, sizeof(tb_vec3) * (size_t)r[0].nv));
    TB_CHECK(!memcmp(r[0].origin, r[1].origin, sizeof(int) * (size_t)r[0].nv));
    TB_CHECK(!memcmp(r[0].side, r[1].side, sizeof(int) * (size_t)r[0].nv));
    TB_CHECK(!memcmp(r[0].tri, r[1].tri, sizeof(int) * 3 * (size_t)r[0].ntri));
    TB_CHECK(!memcmp(r[0].tri_from, r[1].tri_from, sizeof(int) * (size_t)r[0].ntri));
    TB_CHECK(!memcmp(r[0].reskin, r[1].reskin, sizeof(int) * (size_t)r[0].nreskin));
  }
  tb_cut_result_free(&r[0]), tb_cut_result_free(&r[1]);
  tb_fold_free(&f);
  surf_free(&s);
}

/* 5. The layout: old vertices and untouched triangles where they were (check_valid checks
 * positions and slots); here, that cut vertices are the only ones renamed and that the
 * extra crack points and a coarser grid still give a valid result. */
static void test_layout_and_options(void) {
  surf s;
  make_box(&s, 4, 3, 1, 12, 9, 3);
  const tb_vec3 p[2] = {{1.3, -1, 2}, {1.7, 4, 2}};
  tb_fold f = make_fold(p, 2, tb_v3(0, 0, -1.6)); /* depth edge at z = 0.4: a slit */
  tb_cut_def d = tb_cut_default_def();
  tb_vec3 extra[40];
  for (int i = 0; i < 40; i++) /* points near the plane, inside the slab */
    extra[i] = tb_v3(1.3 + 0.4 * (0.05 + 0.9 * (i % 8) / 7.0) + 0.01,
                     3 * (0.05 + 0.9 * (i % 8) / 7.0), 0.45 + 0.5 * (i / 8) / 4.0);
  d.extra = extra, d.nextra = 40;
  tb_cut_result r;
  tb_error err;
  TB_CHECK_MSG(tb_cut_surface(s.nv, s.x, s.ntri, s.tri, &f, &d, &r, &err) == 0, "%s", err.msg);
  check_valid("extra points", &s, &r);
  TB_CHECK(r.components_after == 1);
  /* some extra points became crack vertices, at their projections onto the fold */
  int used = 0;
  for (int i = 0; i < 40; i++) {
    tb_fold_near nr;
    tb_fold_nearest(&f, extra[i], &nr);
    for (int v = s.nv; v < r.nv; v++) used += tb_dist(r.x[v], nr.point) <= 1e-12;
  }
  TB_CHECK_MSG(used >= 10, "%d extra points used", used);
  tb_cut_result_free(&r);
  d.extra = NULL, d.nextra = 0, d.spacing = -1; /* no grid: the crack from the cut vertices */
  TB_CHECK_MSG(tb_cut_surface(s.nv, s.x, s.ntri, s.tri, &f, &d, &r, &err) == 0, "%s", err.msg);
  check_valid("no grid", &s, &r);
  tb_cut_result_free(&r);
  /* bad input: an open surface */
  TB_CHECK(tb_cut_surface(s.nv, s.x, s.ntri - 1, s.tri, &f, NULL, &r, &err) != 0);
  TB_CHECK(strstr(err.msg, "closed") != NULL && r.tri == NULL);
  tb_fold_free(&f);
  surf_free(&s);
}

/* Inside the closed surface: the parity of the triangles a ray from p along +z crosses
 * (in doubles; the test points are far from the surface's edges). */
static int inside_z(const surf *s, tb_vec3 p) {
  int n = 0;
  for (int t = 0; t < s->ntri; t++) {
    tb_vec3 a = s->x[s->tri[3 * t]], b = s->x[s->tri[3 * t + 1]], c = s->x[s->tri[3 * t + 2]];
    double d = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (d == 0) continue;
    double u = ((p.x - a.x) * (c.y - a.y) - (p.y - a.y) * (c.x - a.x)) / d;
    double v = ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) / d;
    if (u < 0 || v < 0 || u + v > 1) continue;
    n += a.z + u * (b.z - a.z) + v * (c.z - a.z) > p.z;
  }
  return n & 1;
}

/* Folded blades whose edge runs inside the steak near its underside, with a crease wholly
 * inside (blades 16, 18, 30, 36 of /work/repro/random_folds.c, rounded): the + and - crack
 * sheets meet along the path inside but must part along the crease. Before the crease got
 * its own points, every shift of these folds failed the final manifold check. */
static void test_crease_inside(void) {
  tb_mesh m;
  tb_error err;
  TB_CHECK_MSG(tb_organ_surface("steak", 600, 1, &m, &err) == 0, "%s", err.msg);
  surf s = {m.nv, m.ntri, m.x, m.tri};
  static const struct {
    int n;
    tb_vec3 p[4], d;
  } blade[] = {
      {3,
       {{0.913, -3.5, -0.773}, {-1.083, -0.574, -0.773}, {0.049, 2.353, -0.773}},
       {0.148, 0, 1.436}},
      {3,
       {{-1.168, -3.5, -0.537}, {-1.422, -1.713, -0.537}, {-0.401, 0.075, -0.537}},
       {0.094, 0, 0.830}},
      {3,
       {{0.672, -3.5, -0.696}, {1.684, -1.116, -0.696}, {0.353, 1.268, -0.696}},
       {0.109, 0, 1.346}},
      {4,
       {{-0.946, -3.5, -0.574},
        {-0.801, -1.490, -0.574},
        {-1.337, 0.520, -0.574},
        {0.134, 2.530, -0.574}},
       {0.115, 0, 1.023}},
  };
  for (int b = 0; b < (int)(sizeof blade / sizeof blade[0]); b++) {
    tb_fold f = make_fold(blade[b].p, blade[b].n, blade[b].d);
    /* the crease at p_1 lies inside the organ, both its ends too */
    tb_vec3 mid = tb_madd(blade[b].p[1], 0.5, blade[b].d);
    TB_CHECK(inside_z(&s, blade[b].p[1]));
    TB_CHECK(inside_z(&s, mid));
    TB_CHECK(inside_z(&s, f.q[1]));
    tb_cut_result r;
    char what[32];
    snprintf(what, sizeof what, "crease inside %d", b);
    TB_CHECK_MSG(tb_cut_surface(s.nv, s.x, s.ntri, s.tri, &f, NULL, &r, &err) == 0, "%s: %s", what,
                 err.msg);
    if (r.tri) {
      check_valid(what, &s, &r);
      TB_CHECK_MSG(r.cut == 1 && r.components_after == 1, "%s: %d components", what,
                   r.components_after);
      /* the crease's inner points: one + and one - copy each, on the crease */
      int plus = 0, minus = 0;
      for (int v = s.nv; v < r.nv; v++) {
        tb_vec3 u = tb_sub(r.x[v], blade[b].p[1]);
        double t = tb_dot(u, blade[b].d) / tb_dot(blade[b].d, blade[b].d);
        if (!(t > 0.01 && t < 0.99) || tb_len(tb_madd(u, -t, blade[b].d)) > 1e-12) continue;
        plus += r.side[v] == 1, minus += r.side[v] == -1;
      }
      TB_CHECK_MSG(plus > 0 && plus == minus, "%s: %d + and %d - copies on the crease", what, plus,
                   minus);
      tb_cut_result_free(&r);
    }
    tb_fold_free(&f);
  }
  tb_mesh_free(&m);
}

const tb_test_case tb_tests_cut_surface[] = {
    {"slab_straight", test_slab_straight},
    {"sphere_folded", test_sphere_folded},
    {"degenerate", test_degenerate},
    {"deterministic", test_deterministic},
    {"layout_and_options", test_layout_and_options},
    {"crease_inside", test_crease_inside},
    {NULL, NULL},
};
