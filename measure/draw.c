/* Drawing a simulation (measure/tb_draw.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_draw.h"
#include "meshgen/tb_meshgen.h"

const float tb_draw_body_rgb[3] = {0.86f, 0.45f, 0.40f},
            tb_draw_tool_rgb[3] = {0.62f, 0.64f, 0.68f};

void tb_draw_sim(tb_renderer *r, tb_sim *s, const double *value, double lo, double hi,
                 const char *label, int wireframe) {
  if (!(hi > lo)) hi = lo + 1;
  tb_surface su = tb_model_surface(&s->model);
  if (s->has_ground || s->ground_off) {
    tb_vec3 c = tb_v3(0, 0, 0);
    for (int i = 0; i < su.nv; i++) c = tb_madd(c, 1.0 / su.nv, su.x[i]);
    tb_renderer_ground(r, s->ground.p, s->ground.n, c, s->size);
  }
  const float *b = tb_draw_body_rgb, *t = tb_draw_tool_rgb;
  tb_render_mesh body = {.nv = su.nv,
                         .ntri = su.ntri,
                         .x = su.x,
                         .tri = su.tri,
                         .rgb = {b[0], b[1], b[2]},
                         .value = value,
                         .lo = lo,
                         .hi = hi,
                         .wireframe = wireframe};
  tb_renderer_mesh(r, &body);
  tb_mesh tool;
  if (tb_sim_instrument(s, &tool)) {
    tb_render_mesh m = {
        .nv = tool.nv, .ntri = tool.ntri, .x = tool.x, .tri = tool.tri, .rgb = {t[0], t[1], t[2]}};
    tb_renderer_mesh(r, &m);
  }
  if (value) tb_renderer_colorbar(r, lo, hi, label);
}

double tb_draw_displacement(const tb_sim *s, double *value) {
  tb_surface su = tb_model_surface(&s->model);
  const tb_vec3 *x0 = su.x0 ? su.x0 : s->mesh.x;
  int n = su.x0 || su.nv <= s->mesh.nv ? su.nv : s->mesh.nv;
  double hi = 0;
  for (int i = 0; i < su.nv; i++) value[i] = i < n ? tb_dist(su.x[i], x0[i]) : 0;
  for (int i = 0; i < su.nv; i++) hi = fmax(hi, value[i]);
  return hi;
}

void tb_draw_edges(tb_renderer *r, const tb_mesh *m, const tb_vec3 *x) {
  static const float ink[3] = {0.15f, 0.2f, 0.35f};
  int *e = NULL, n = tb_mesh_edges(m, &e);
  tb_vec3 *ends = n > 0 ? malloc(sizeof(tb_vec3) * 2 * (size_t)n) : NULL;
  for (int k = 0; ends && k < n; k++) ends[2 * k] = x[e[2 * k]], ends[2 * k + 1] = x[e[2 * k + 1]];
  if (ends) tb_renderer_lines(r, n, ends, ink, 1);
  free(ends), free(e);
}

int tb_draw_structure(tb_renderer *r, const tb_sim *s, tb_error *err) {
  const tb_vec3 *x = tb_model_positions(&s->model);
  if (s->model.cls->spheres) { /* spheres at half their radius, and their links */
    tb_model_spheres sp = s->model.cls->spheres(s->model.self);
    static const float dark[3] = {0.15f, 0.15f, 0.2f};
    if (tb_draw_spheres(r, sp.n, sp.c, sp.r, sp.alive, 0.5, tb_draw_body_rgb, err)) return -1;
    tb_draw_links(r, sp.nlinks, sp.links, sp.c, dark, 1.0f);
    return 0;
  }
  if (!s->model.cls->groups) {
    tb_draw_edges(r, &s->mesh, x);
    return 0;
  }
  tb_model_groups g = s->model.cls->groups(s->model.self);
  float *rgb = malloc(sizeof(float) * 3 * (size_t)g.n);
  if (!rgb) return tb_error_set(err, "draw", 0, "out of memory (%d points)", g.n);
  /* group q's colour: a qualitative palette (neighbouring numbers far apart in colour) */
  for (int i = 0; i < g.n; i++)
    if (g.group[i] >= 0)
      tb_palette(g.group[i], rgb + 3 * i);
    else
      rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = 0.5f;
  tb_renderer_points(r, g.n, x, rgb, 4);
  free(rgb);
  return 0;
}

int tb_draw_contacts(tb_renderer *r, const tb_sim *s) {
  int *tri, n = tb_sim_contact_triangles(s, &tri);
  if (n <= 0) return 0;
  tb_render_mesh m = {.nv = s->mesh.nv,
                      .ntri = n,
                      .x = tb_model_positions(&s->model),
                      .tri = tri,
                      .rgb = {0.9f, 0.05f, 0.05f},
                      .on_top = 1,
                      .any_side = 1,
                      .flat = 1};
  tb_renderer_mesh(r, &m);
  free(tri);
  return n;
}

/* One geodesic sphere of 42 vertices at the origin with radius 1, made
 * once per call (cheap), instanced into one mesh. */
int tb_draw_spheres(tb_renderer *r, int n, const tb_vec3 *c, const double *rad,
                    const unsigned char *show, double scale, const float rgb[3], tb_error *err) {
  tb_mesh unit;
  if (tb_geosphere(42, 1.0, &unit, err)) return -1;
  int count = 0;
  for (int i = 0; i < n; i++) count += !show || show[i];
  size_t nv = (size_t)count * (size_t)unit.nv, nt = (size_t)count * (size_t)unit.ntri;
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (nv ? nv : 1));
  int *tri = malloc(sizeof(int) * 3 * (nt ? nt : 1));
  if (!x || !tri) {
    free(x), free(tri), tb_mesh_free(&unit);
    return tb_error_set(err, "draw", 0, "out of memory (%d spheres)", count);
  }
  int k = 0;
  for (int i = 0; i < n; i++) {
    if (show && !show[i]) continue;
    for (int v = 0; v < unit.nv; v++) x[k * unit.nv + v] = tb_madd(c[i], scale * rad[i], unit.x[v]);
    for (int t = 0; t < 3 * unit.ntri; t++) tri[3 * k * unit.ntri + t] = k * unit.nv + unit.tri[t];
    k++;
  }
  tb_render_mesh m = {.nv = (int)nv,
                      .ntri = (int)nt,
                      .x = x,
                      .tri = tri,
                      .rgb = {rgb[0], rgb[1], rgb[2]},
                      .flat = 0};
  if (count) tb_renderer_mesh(r, &m);
  free(x), free(tri), tb_mesh_free(&unit);
  return 0;
}

void tb_draw_links(tb_renderer *r, int n, const int *pairs, const tb_vec3 *c, const float rgb[3],
                   float width) {
  tb_vec3 *ends = malloc(sizeof(tb_vec3) * 2 * (size_t)(n > 0 ? n : 1));
  if (!ends) return;
  for (int e = 0; e < 2 * n; e++) ends[e] = c[pairs[e]];
  tb_renderer_lines(r, n, ends, rgb, width);
  free(ends);
}
