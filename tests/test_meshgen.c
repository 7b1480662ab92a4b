/* Generators: geodesic spheres, beams, the instrument, TetGen, the liver's
 * tet mesh, and the generator table behind `tissuebench mesh`. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_generators.h"
#include "tb_meshgen.h"
#include "tb_test.h"

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
    {"instrument_counts", instrument_counts},
    {"tetgen_sphere", tetgen_sphere},
    {"liver_tets_thesis", liver_tets_thesis},
    {"generator_table", generator_table},
    {0, 0},
};
