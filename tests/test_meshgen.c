/* Generators: geodesic spheres, beams, the instrument, TetGen, the liver's
 * tet mesh, and the generator table behind `tissuebench mesh`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "meshgen/tb_generators.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_model.h"

static void spheres_bao2006(void) {
  static const int nv[2] = {252, 1002}, nt[2] = {500, 2000};
  for (int k = 0; k < 2; k++) {
    tb_mesh m;
    tb_error err;
    TB_CHECK(tb_geosphere(nv[k], 2.0, &m, &err) == 0);
    TB_CHECK(m.nv == nv[k] && m.ntri == nt[k]);
    tb_mesh_topo t = tb_mesh_topology(&m);
    TB_CHECK(t.closed && t.manifold && t.euler == 2 && t.components == 1 && !t.misoriented_edges);
    for (int i = 0; i < m.nv; i++) TB_CHECK_NEAR(tb_len(m.x[i]), 2.0, 1e-12);
    double v = tb_mesh_volume(&m), exact = 4.0 / 3 * M_PI * 8;
    TB_CHECK(v > 0.93 * exact && v < exact); /* outward, inscribed */
    tb_mesh_free(&m);
  }
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_geosphere(250, 1, &m, &err) != 0 && strstr(err.msg, "10 f^2 + 2"));
  TB_CHECK(tb_geosphere(252, -1, &m, &err) != 0);
}

static void beam_conforming(void) {
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_beam(10, 1, 2, 10, 2, 3, &m, &err) == 0);
  TB_CHECK(m.nv == 11 * 3 * 4 && m.ntet == 6 * 60);
  TB_CHECK(tb_mesh_min_tet_volume(&m) > 0);
  TB_CHECK_NEAR(tb_mesh_volume(&m), 20, 1e-12);
  tb_mesh_topo t = tb_mesh_topology(&m);
  TB_CHECK(t.closed && t.manifold && t.euler == 2 && !t.misoriented_edges);
  int *e = NULL, *f = NULL;
  int ne = tb_mesh_edges(&m, &e), nf = tb_mesh_tet_faces(&m, &f);
  TB_CHECK(m.nv - ne + nf - m.ntet == 1); /* a ball: conforming, no cracks */
  tb_mesh s = m;
  s.ntet = 0;
  TB_CHECK_NEAR(tb_mesh_volume(&s), 20, 1e-12); /* boundary outward */
  free(e), free(f);
  tb_mesh_free(&m);
  TB_CHECK(tb_beam(1, 1, 1, 0, 1, 1, &m, &err) != 0);
  TB_CHECK(tb_beam(1, NAN, 1, 1, 1, 1, &m, &err) != 0);
}

/* ---- the symmetric beam split ---- */

static int cmp3(const void *a, const void *b) {
  const long *p = a, *q = b;
  for (int k = 0; k < 3; k++)
    if (p[k] != q[k]) return p[k] < q[k] ? -1 : 1;
  return 0;
}

/* Conforming: every face of the tets is used once (then it lies on a face of
 * the box) or twice; positive volumes summing to the box; closed boundary. */
static void check_conforming(const tb_mesh *m, double lx, double ly, double lz) {
  long nf = 4L * m->ntet, *f = malloc(sizeof(long) * 3 * (size_t)nf);
  if (!f) return;
  for (int t = 0; t < m->ntet; t++)
    for (int o = 0; o < 4; o++) {
      long *g = f + 3 * (4L * t + o);
      for (int k = 0, n = 0; k < 4; k++)
        if (k != o) g[n++] = m->tet[4 * t + k];
      for (int a = 0; a < 2; a++) /* sort the three indices */
        for (int b = 0; b < 2 - a; b++)
          if (g[b] > g[b + 1]) {
            long tmp = g[b];
            g[b] = g[b + 1], g[b + 1] = tmp;
          }
    }
  qsort(f, (size_t)nf, 3 * sizeof(long), cmp3);
  int bad = 0, bnd = 0;
  for (long i = 0; i < nf;) {
    long j = i;
    while (j < nf && !cmp3(f + 3 * i, f + 3 * j)) j++;
    if (j - i > 2) bad++;
    if (j - i == 1) {
      bnd++;
      /* a boundary face: its three vertices share a side of the box */
      tb_vec3 p[3] = {m->x[f[3 * i]], m->x[f[3 * i + 1]], m->x[f[3 * i + 2]]};
      int side = 0;
      for (int a = 0; a < 3; a++) {
        double lo = 0, hi = a == 0 ? lx : a == 1 ? ly : lz, v[3];
        for (int k = 0; k < 3; k++) v[k] = a == 0 ? p[k].x : a == 1 ? p[k].y : p[k].z;
        side |=
            (v[0] == lo && v[1] == lo && v[2] == lo) || (v[0] == hi && v[1] == hi && v[2] == hi);
      }
      if (!side) bad++;
    }
    i = j;
  }
  TB_CHECK_MSG(bad == 0, "%d faces used by more than two tets or open inside the box", bad);
  TB_CHECK_MSG(bnd == m->ntri, "%d boundary faces, %d boundary triangles", bnd, m->ntri);
  free(f);
  TB_CHECK(tb_mesh_min_tet_volume(m) > 0);
  TB_CHECK_NEAR(tb_mesh_volume(m), lx * ly * lz, 1e-12 * lx * ly * lz);
  tb_mesh_topo t = tb_mesh_topology(m);
  TB_CHECK(t.closed && t.manifold && t.euler == 2 && !t.misoriented_edges);
}

/* Whether the tet centroids map onto themselves under y -> ly - y (axis 1)
 * or z -> lz - z (axis 2). Centroids in units of a quarter cell are
 * integers: 4 c / h is the sum of the four corners' grid indices. */
static int mirror_symmetric(const tb_mesh *m, const double *h, const int *n, int axis) {
  long *c = malloc(sizeof(long) * 3 * (size_t)m->ntet),
       *r = malloc(sizeof(long) * 3 * (size_t)m->ntet);
  int same = c && r;
  for (int t = 0; same && t < m->ntet; t++)
    for (int a = 0; a < 3; a++) {
      long s = 0;
      for (int k = 0; k < 4; k++) {
        tb_vec3 p = m->x[m->tet[4 * t + k]];
        s += lround((a == 0 ? p.x : a == 1 ? p.y : p.z) / h[a]);
      }
      c[3 * t + a] = s;
      r[3 * t + a] = a == axis ? 4L * n[a] - s : s;
    }
  if (same) {
    qsort(c, (size_t)m->ntet, 3 * sizeof(long), cmp3);
    qsort(r, (size_t)m->ntet, 3 * sizeof(long), cmp3);
    same = memcmp(c, r, sizeof(long) * 3 * (size_t)m->ntet) == 0;
  }
  free(c), free(r);
  return same;
}

static void beam_symmetric_split(void) {
  static const int cells[2][3] = {{10, 2, 4}, {5, 4, 2}};
  for (int q = 0; q < 2; q++) {
    const int *n = cells[q];
    double L[3] = {10, 1, 2}, h[3] = {L[0] / n[0], L[1] / n[1], L[2] / n[2]};
    tb_mesh m, k;
    tb_error err;
    TB_CHECK_MSG(
        tb_beam_with_split(L[0], L[1], L[2], n[0], n[1], n[2], TB_SPLIT_SYMMETRIC, &m, &err) == 0,
        "%s", err.msg);
    TB_CHECK(m.nv == (n[0] + 1) * (n[1] + 1) * (n[2] + 1) && m.ntet == 6 * n[0] * n[1] * n[2]);
    check_conforming(&m, L[0], L[1], L[2]);
    TB_CHECK_MSG(mirror_symmetric(&m, h, n, 1), "not symmetric about y = %g", L[1] / 2);
    TB_CHECK_MSG(mirror_symmetric(&m, h, n, 2), "not symmetric about z = %g", L[2] / 2);
    /* the default split conforms too, but is lopsided: the check can fail */
    TB_CHECK(tb_beam(L[0], L[1], L[2], n[0], n[1], n[2], &k, &err) == 0);
    check_conforming(&k, L[0], L[1], L[2]);
    TB_CHECK(!mirror_symmetric(&k, h, n, 1) && !mirror_symmetric(&k, h, n, 2));
    tb_mesh_free(&k);
    tb_mesh_free(&m);
  }
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_beam_with_split(4, 1, 1, 4, 3, 2, TB_SPLIT_SYMMETRIC, &m, &err) != 0 &&
           strstr(err.msg, "even ny and nz"));
  /* the generator setting */
  const tb_generator *g = tb_generator_find("beam");
  double p[TB_GEN_MAX_PARAMS];
  tb_generator_defaults(g, p);
  TB_CHECK(p[6] == TB_SPLIT_KUHN);
  TB_CHECK(tb_generator_set(g, p, "split=symmetric") == 0 && p[6] == TB_SPLIT_SYMMETRIC);
  TB_CHECK(tb_generator_set(g, p, "split=mirror") != 0 && tb_generator_set(g, p, "split=2") != 0);
  TB_CHECK(tb_generator_set(g, p, "split=0") == 0 && p[6] == TB_SPLIT_KUHN);
}

/* Linear FEM (models/fem.c, quasi-static) on a 40x4x4-cube cantilever,
 * clamped at x = 0, loaded straight down at x = L: the mean sideways (y)
 * deflection of the tip over the vertical one, per split. */
static double sideways_ratio(tb_beam_split split) {
  tb_mesh m;
  tb_error err;
  double L = 10, ratio = NAN;
  if (tb_beam_with_split(L, 1, 1, 40, 4, 4, split, &m, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return NAN;
  }
  int *fixed = malloc(sizeof(int) * (size_t)m.nv), nfixed = 0, ntip = 0;
  tb_vec3 *fx = malloc(sizeof(tb_vec3) * (size_t)m.nv),
          *force = calloc((size_t)m.nv, sizeof *force);
  for (int i = 0; i < m.nv; i++) {
    if (m.x[i].x == 0) fixed[nfixed] = i, fx[nfixed++] = m.x[i];
    ntip += m.x[i].x == L;
  }
  for (int i = 0; i < m.nv; i++)
    if (m.x[i].x == L) force[i] = tb_v3(0, 0, -1.0 / ntip);
  tb_settings d;
  tb_settings_init(&d);
  tb_settings_set(&d, "quasistatic=1", &err);
  tb_model mod;
  if (tb_model_create(&mod, "fem", &m, &d, &err) == 0) {
    tb_step st = {0};
    memset(&st, 0, sizeof st);
    st.dt = 0.01, st.force = force, st.nfixed = nfixed, st.fixed = fixed, st.fixed_x = fx;
    if (tb_model_step(&mod, &st, &err) == 0) {
      const tb_vec3 *x = tb_model_positions(&mod);
      double uy = 0, uz = 0;
      for (int i = 0; i < m.nv; i++)
        if (m.x[i].x == L) uy += x[i].y - m.x[i].y, uz += x[i].z - m.x[i].z;
      ratio = fabs(uy / uz);
      printf("  %s split: tip deflection %.6g down, %.3g sideways (ratio %.3g)\n",
             split == TB_SPLIT_KUHN ? "kuhn" : "symmetric", -uz / ntip, uy / ntip, ratio);
      TB_CHECK(uz < 0);
    } else {
      TB_CHECK_MSG(0, "%s", err.msg);
    }
    tb_model_destroy(&mod);
  } else {
    TB_CHECK_MSG(0, "%s", err.msg);
  }
  free(fixed), free(fx), free(force);
  tb_mesh_free(&m);
  return ratio;
}

static void beam_symmetric_bends_straight(void) {
  double kuhn = sideways_ratio(TB_SPLIT_KUHN), sym = sideways_ratio(TB_SPLIT_SYMMETRIC);
  TB_CHECK_MSG(kuhn > 0.05, "kuhn split sideways/vertical %g: the lopsided split should show",
               kuhn);
  TB_CHECK_MSG(sym < 1e-6, "symmetric split sideways/vertical %g", sym);
}

static void instrument_counts(void) {
  tb_instrument_def d = tb_instrument_default_def();
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_instrument(&d, &m, &err) == 0);
  TB_CHECK(m.nv == 628 && m.ntri == 1248); /* the thesis's instrument */
  tb_mesh_topo t = tb_mesh_topology(&m);
  TB_CHECK(t.closed && t.manifold && t.components == 2 && t.euler == 4 && !t.misoriented_edges);
  TB_CHECK(tb_mesh_volume(&m) > 0);
  /* the shaft volume dominates: pi r^2 L within 10% */
  double shaft = M_PI * d.radius * d.radius * d.length;
  TB_CHECK(tb_mesh_volume(&m) > 0.9 * shaft && tb_mesh_volume(&m) < 1.1 * shaft);
  tb_mesh_free(&m);
  d.segments = 2;
  TB_CHECK(tb_instrument(&d, &m, &err) != 0);
}

static void tetgen_sphere(void) {
  tb_mesh s, t;
  tb_error err;
  TB_CHECK(tb_geosphere(252, 1.0, &s, &err) == 0);
  TB_CHECK(tb_tetgen(&s, "pq1.4Y", &t, &err) == 0);
  TB_CHECK(t.ntet > 0 && tb_mesh_min_tet_volume(&t) > 0);
  TB_CHECK(t.ntri == s.ntri); /* Y: the boundary is kept */
  TB_CHECK_NEAR(tb_mesh_volume(&t), tb_mesh_volume(&s), 1e-9);
  tb_mesh_topo topo = tb_mesh_topology(&t);
  TB_CHECK(topo.closed && topo.manifold && topo.euler == 2);
  tb_mesh_free(&t);
  /* two overlapping spheres in one surface: TetGen fails (it crashes in
   * its own clean-up); that comes back as a tb_error, not our crash */
  tb_mesh two = {2 * s.nv,   malloc(sizeof(tb_vec3) * 2 * s.nv),
                 2 * s.ntri, malloc(sizeof(int) * 6 * s.ntri),
                 0,          NULL,
                 0};
  for (int i = 0; i < s.nv; i++)
    two.x[i] = s.x[i], two.x[s.nv + i] = tb_add(s.x[i], tb_v3(0.5, 0.1, 0.05));
  for (int i = 0; i < 3 * s.ntri; i++)
    two.tri[i] = s.tri[i], two.tri[3 * s.ntri + i] = s.tri[i] + s.nv;
  TB_CHECK(tb_tetgen(&two, "pq1.4Y", &t, &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "self-intersecting") || strstr(err.msg, "self-intersection"), "%s",
               err.msg);
  TB_CHECK(t.nv == 0 && t.x == NULL);
  tb_mesh_free(&two);
  tb_mesh_free(&s);
}

static void liver_tets_thesis(void) {
  tb_liver_def d = tb_liver_default_def();
  tb_mesh s, t, t2;
  tb_error err;
  TB_CHECK(tb_liver_surface(&d, &s, &err) == 0);
  TB_CHECK(tb_liver_tets(&d, &s, &t, &err) == 0);
  TB_CHECK_MSG(abs(t.nv - 1206) <= 121, "tet-mesh vertices %d", t.nv);
  TB_CHECK_MSG(abs(t.ntet - 4230) <= 423, "tets %d", t.ntet);
  TB_CHECK(tb_mesh_min_tet_volume(&t) > 0);
  TB_CHECK_NEAR(tb_mesh_volume(&t), tb_mesh_volume(&s), 1e-9 * tb_mesh_volume(&s));
  tb_mesh_topo topo = tb_mesh_topology(&t);
  TB_CHECK(topo.closed && topo.manifold && topo.euler == 2 && topo.components == 1);
  int *e = NULL, *f = NULL;
  int ne = tb_mesh_edges(&t, &e), nf = tb_mesh_tet_faces(&t, &f);
  TB_CHECK(t.nv - ne + nf - t.ntet == 1);
  TB_CHECK_MSG(abs(nf - 9313) <= 932 && abs(ne - 6288) <= 629, "faces %d edges %d", nf, ne);
  free(e), free(f);
  TB_CHECK(tb_liver_tets(&d, &s, &t2, &err) == 0 && tb_mesh_equal(&t, &t2));
  tb_mesh_free(&t2);
  tb_mesh_free(&t);
  tb_mesh_free(&s);
}

/* Tets only (tet_verts 0): the 2022 patent's two smaller livers, 596 and
 * 5395 tets, within 2%, valid and closed, the same mesh twice. */
static void liver_tets_count(void) {
  static const int targets[] = {596, 5395};
  for (int k = 0; k < 2; k++) {
    tb_liver_def d = tb_liver_default_def();
    d.surface_verts = 0, d.tet_verts = 0, d.tets = targets[k];
    tb_mesh s, t, t2;
    tb_error err;
    TB_CHECK_MSG(tb_liver_surface(&d, &s, &err) == 0, "%s", err.msg);
    TB_CHECK_MSG(abs(s.nv - tb_liver_surface_for(targets[k])) * 20 <= s.nv, "surface %d", s.nv);
    TB_CHECK_MSG(tb_liver_tets(&d, &s, &t, &err) == 0, "%d tets: %s", targets[k], err.msg);
    TB_CHECK_MSG(abs(t.ntet - targets[k]) <= TB_LIVER_TET_TOL * targets[k], "%d tets for %d",
                 t.ntet, targets[k]);
    TB_CHECK(tb_mesh_min_tet_volume(&t) > 0);
    TB_CHECK_NEAR(tb_mesh_volume(&t), tb_mesh_volume(&s), 1e-9 * tb_mesh_volume(&s));
    tb_mesh_topo topo = tb_mesh_topology(&t);
    TB_CHECK(topo.closed && topo.manifold && topo.components == 1);
    if (k == 0) TB_CHECK(tb_liver_tets(&d, &s, &t2, &err) == 0 && tb_mesh_equal(&t, &t2));
    if (k == 0) tb_mesh_free(&t2);
    tb_mesh_free(&t);
    tb_mesh_free(&s);
  }
  /* tets only needs a tet target */
  tb_liver_def d = tb_liver_default_def();
  tb_mesh s, t;
  tb_error err;
  TB_CHECK(tb_liver_surface(&d, &s, &err) == 0);
  d.tet_verts = 0, d.tets = 0;
  TB_CHECK(tb_liver_tets(&d, &s, &t, &err) != 0 && strstr(err.msg, "tets"));
  tb_mesh_free(&s);
}

static void generator_table(void) {
  const tb_generator *g = tb_generator_find("sphere");
  TB_CHECK(g && !tb_generator_find("nonsense"));
  double p[TB_GEN_MAX_PARAMS];
  tb_generator_defaults(g, p);
  TB_CHECK(tb_generator_set(g, p, "verts=1002") == 0 && p[0] == 1002);
  TB_CHECK(tb_generator_set(g, p, "verts=10.5") != 0);
  TB_CHECK(tb_generator_set(g, p, "radius=nan") != 0);
  TB_CHECK(tb_generator_set(g, p, "colour=3") != 0);
  tb_gen_result r;
  tb_error err;
  TB_CHECK(tb_generator_run(g, p, &r, &err) == 0);
  tb_gen_counts c = tb_gen_result_counts(&r);
  TB_CHECK(c.surface_verts == 1002 && c.surface_tris == 2000 && c.tets == 0);
  tb_mesh part;
  TB_CHECK(tb_gen_result_part(&r, TB_PART_TETS, &part, &err) != 0);
  TB_CHECK(tb_gen_result_part(&r, TB_PART_SURFACE, &part, &err) == 0 && part.ntri == 2000);
  tb_mesh_free(&part);
  tb_gen_result_free(&r);
  g = tb_generator_find("beam");
  tb_generator_defaults(g, p);
  TB_CHECK(tb_generator_run(g, p, &r, &err) == 0);
  c = tb_gen_result_counts(&r);
  TB_CHECK(c.tets == 6 * 20 * 2 * 2 && c.verts - c.edges + c.faces - c.tets == 1);
  TB_CHECK(tb_gen_result_part(&r, TB_PART_FACES, &part, &err) == 0 && part.ntri == c.faces &&
           part.ntet == 0);
  tb_mesh_free(&part);
  tb_gen_result_free(&r);
}

const tb_test_case tb_tests_meshgen[] = {
    {"spheres_bao2006", spheres_bao2006},
    {"beam_conforming", beam_conforming},
    {"beam_symmetric_split", beam_symmetric_split},
    {"beam_symmetric_bends_straight", beam_symmetric_bends_straight},
    {"instrument_counts", instrument_counts},
    {"tetgen_sphere", tetgen_sphere},
    {"liver_tets_thesis", liver_tets_thesis},
    {"liver_tets_count", liver_tets_count},
    {"generator_table", generator_table},
    {0, 0},
};
