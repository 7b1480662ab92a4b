/* A simulation's frames for ParaView: per frame one .vtu file per object
 * (body_N.vtu: the body's tets with point data `displacement`, `velocity`,
 * `fixed` and `driven` and cell data `equivalent_green_strain`,
 * `von_mises_stress` and `inverted`, or a surface model's current surface
 * with the point data alone; surface_N.vtu: a tet model's current surface;
 * instrument_N.vtu and ground_N.vtu) and frame_N.vtm naming them as blocks;
 * frames.pvd collects the .vtm files with their times, and NAME.pvd each
 * object's files, so ParaView shows each object as its own data set.
 *
 * equivalent_green_strain: the equivalent (von Mises) strain of the Green-Lagrange strain
 * E = (F^T F - I) / 2, F = D_s D_m^-1 per tet, sqrt(2/3 dev(E):dev(E));
 * rotation-free, so meaningful for every model. von_mises: of the second
 * Piola-Kirchhoff stress S = lambda tr(E) I + 2 mu E (St. Venant-Kirchhoff
 * with the model's E and nu), written only for models that have both
 * settings (fem, fem-corot); NaN otherwise would mislead, so the array is
 * left out. inverted: 1 where a tet's signed volume is <= 0. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sim_priv.h"
#include "core/tb_mesh_io.h"
#include "core/tb_vtu.h"

/* Green strain of one tet (rest positions X, current x). */
static tb_mat3 green_strain(const tb_vec3 *X, const tb_vec3 *x, const int *e, int *ok) {
  tb_mat3 Dm, Ds, inv;
  tb_vec3 dm[3] = {tb_sub(X[e[1]], X[e[0]]), tb_sub(X[e[2]], X[e[0]]), tb_sub(X[e[3]], X[e[0]])};
  tb_vec3 ds[3] = {tb_sub(x[e[1]], x[e[0]]), tb_sub(x[e[2]], x[e[0]]), tb_sub(x[e[3]], x[e[0]])};
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) Dm.m[r][c] = tb_comp(dm[c], r), Ds.m[r][c] = tb_comp(ds[c], r);
  *ok = tb_m3_inverse(Dm, &inv);
  tb_mat3 F = tb_m3_mul(Ds, inv), C = tb_m3_mul(tb_m3_transpose(F), F);
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) C.m[r][c] = 0.5 * (C.m[r][c] - (r == c));
  return C;
}

/* sqrt(3/2 dev(A):dev(A)) (scale = 1) or sqrt(2/3 ...) for strains. */
static double von_mises(tb_mat3 a, double scale) {
  double tr = (a.m[0][0] + a.m[1][1] + a.m[2][2]) / 3, s = 0;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      double d = a.m[r][c] - (r == c ? tr : 0);
      s += d * d;
    }
  return sqrt(scale * s);
}

int tb_sim_tet_fields(const tb_sim *s, double *strain, double *vm, unsigned char *inv) {
  const tb_mesh *m = &s->mesh;
  const tb_vec3 *x = tb_model_positions(&s->model);
  size_t nt = (size_t)m->ntet;
  double E = 0, nu = 0;
  const char *name = s->model.cls->name;
  int stress =
      tb_model_setting(name, NULL, "E", &E) == 0 && tb_model_setting(name, NULL, "nu", &nu) == 0;
  if (stress) {
    /* the run's own values, when the scene or the caller set them */
    tb_model_setting(name, &s->settings, "E", &E);
    tb_model_setting(name, &s->settings, "nu", &nu);
  }
  double lam, mu;
  tb_lame(E, nu, &lam, &mu);
  for (size_t t = 0; t < nt; t++) {
    const int *e = m->tet + 4 * t;
    int ok;
    tb_mat3 G = green_strain(m->x, x, e, &ok);
    if (strain) strain[t] = ok ? von_mises(G, 2.0 / 3.0) : NAN;
    double tr = G.m[0][0] + G.m[1][1] + G.m[2][2];
    tb_mat3 S = G;
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) S.m[r][c] = 2 * mu * G.m[r][c] + (r == c ? lam * tr : 0);
    if (vm) vm[t] = ok && stress ? von_mises(S, 1.5) : NAN;
    if (inv) inv[t] = !(tb_tet_volume(x[e[0]], x[e[1]], x[e[2]], x[e[3]]) > 0);
  }
  return stress;
}

/* The frame's objects, in block order; which a scene has. */
enum { BODY, SURFACE, INSTRUMENT, GROUND, NOBJECTS };
static const char *const object_name[NOBJECTS] = {"body", "surface", "instrument", "ground"};
static int has_object(const tb_sim *s, int k) {
  return k == BODY || (k == SURFACE && s->mesh.ntet > 0) || (k == INSTRUMENT && s->has_tool) ||
         (k == GROUND && s->has_ground);
}

static int object_path(char *path, size_t cap, const char *dir, int k, int frame, tb_error *err) {
  if (snprintf(path, cap, "%s/%s_%05d.vtu", dir, object_name[k], frame) >= (int)cap)
    return tb_error_set(err, dir, 0, "path too long");
  return 0;
}

/* The body: its tets with cell data (cut ones left out), or a surface model's current surface
 * (which may have more points than the rest mesh; those have velocity 0). Point data:
 * displacement, velocity, fixed (the scene's anchors) and driven (its moves and forces). */
static int write_body(tb_sim *s, const char *path, tb_error *err) {
  const tb_mesh *m = &s->mesh;
  const tb_vec3 *x = tb_model_positions(&s->model), *v = tb_model_velocities(&s->model);
  size_t nv = (size_t)m->nv, nt = (size_t)m->ntet;
  tb_surface su = tb_model_surface(&s->model);
  int np = tb_model_npoints(&s->model);
  tb_vec3 *vel = NULL;
  if (!nt && su.nv > 0) {
    x = su.x, nv = (size_t)su.nv;
    vel = calloc(nv, sizeof *vel);
    if (vel) memcpy(vel, v, sizeof(tb_vec3) * (size_t)(np < su.nv ? np : su.nv));
    v = vel;
  }
  tb_vec3 *disp = malloc(sizeof(tb_vec3) * (nv ? nv : 1));
  double *strain = malloc(sizeof(double) * (nt ? nt : 1)),
         *vm = malloc(sizeof(double) * (nt ? nt : 1));
  unsigned char *inv = malloc(nt ? nt : 1), *fixed = calloc(nv ? nv : 1, 2);
  int *left = NULL, nleft = (int)nt;
  const unsigned char *alive = tb_model_tets_alive(&s->model);
  if (nt && alive) left = malloc(sizeof(int) * 4 * nt);
  if (!disp || !strain || !vm || !inv || !fixed || (!nt && !vel) || (nt && alive && !left)) {
    free(disp), free(strain), free(vm), free(inv), free(fixed), free(vel), free(left);
    return tb_error_set(err, path, 0, "out of memory");
  }
  unsigned char *driven = fixed + nv;
  for (int k = 0; k < s->nanchor; k++) fixed[s->anchor[k]] = 1;
  for (int k = 0; k < s->ndriven; k++) driven[s->driven[k]] = 1;
  const tb_vec3 *x0 = !nt && su.x0 ? su.x0 : m->x;
  for (size_t i = 0; i < nv; i++)
    disp[i] = i < (size_t)m->nv || x0 != m->x ? tb_sub(x[i], x0[i]) : tb_v3(0, 0, 0);
  int stress = tb_sim_tet_fields(s, strain, vm, inv);
  tb_vtu_array arrays[7] = {{"displacement", 3, &disp[0].x, NULL, 0},
                            {"velocity", 3, &v[0].x, NULL, 0},
                            {"fixed", 1, NULL, fixed, 0},
                            {"driven", 1, NULL, driven, 0},
                            {"equivalent_green_strain", 1, strain, NULL, 1},
                            {"inverted", 1, NULL, inv, 1},
                            {"von_mises_stress", 1, vm, NULL, 1}};
  if (left) { /* a tet model a cut carved: the tets left, with their cell data */
    nleft = 0;
    for (size_t t = 0; t < nt; t++) {
      if (!alive[t]) continue;
      memcpy(left + 4 * nleft, m->tet + 4 * t, 4 * sizeof(int));
      strain[nleft] = strain[t], vm[nleft] = vm[t], inv[nleft] = inv[t];
      nleft++;
    }
  }
  tb_vtu_piece piece =
      nt ? (tb_vtu_piece){m->nv, x, 0, NULL, nleft, left ? left : m->tet, stress ? 7 : 6, arrays}
         : (tb_vtu_piece){(int)nv, x, su.ntri, su.tri, 0, NULL, 4, arrays};
  int rc = tb_vtu_write(path, &piece, 1, err);
  free(disp), free(strain), free(vm), free(inv), free(fixed), free(vel), free(left);
  return rc;
}

/* A tet model's current surface (its boundary, or what a cut or a refinement made of it), with
 * the displacement of its points. */
static int write_surface(const tb_sim *s, const char *path, tb_error *err) {
  tb_surface su = tb_model_surface(&s->model);
  const tb_vec3 *x0 = su.x0 ? su.x0 : s->mesh.x;
  tb_vec3 *disp = malloc(sizeof(tb_vec3) * (size_t)(su.nv ? su.nv : 1));
  if (!disp) return tb_error_set(err, path, 0, "out of memory");
  for (int i = 0; i < su.nv; i++)
    disp[i] = i < s->mesh.nv || su.x0 ? tb_sub(su.x[i], x0[i]) : tb_v3(0, 0, 0);
  tb_vtu_array a = {"displacement", 3, &disp[0].x, NULL, 0};
  tb_vtu_piece piece = {su.nv, su.x, su.ntri, su.tri, 0, NULL, 1, &a};
  int rc = tb_vtu_write(path, &piece, 1, err);
  free(disp);
  return rc;
}

/* The ground: a square of twice the body's size around the body's foot on the plane. */
static int write_ground(const tb_sim *s, const char *path, tb_error *err) {
  static const int quad_tri[6] = {0, 1, 2, 0, 2, 3};
  const tb_vec3 *x = tb_model_positions(&s->model);
  tb_vec3 n = s->ground.n, a = fabs(n.x) < 0.9 ? tb_v3(1, 0, 0) : tb_v3(0, 1, 0);
  tb_vec3 u = tb_normalize(tb_cross(n, a)), w = tb_cross(n, u), c = tb_v3(0, 0, 0);
  for (int i = 0; i < s->mesh.nv; i++) c = tb_add(c, x[i]);
  c = tb_scale(c, 1.0 / (s->mesh.nv ? s->mesh.nv : 1));
  c = tb_madd(c, -tb_dot(tb_sub(c, s->ground.p), n), n);
  double r = s->size;
  tb_vec3 quad[4] = {tb_add(c, tb_add(tb_scale(u, -r), tb_scale(w, -r))),
                     tb_add(c, tb_add(tb_scale(u, r), tb_scale(w, -r))),
                     tb_add(c, tb_add(tb_scale(u, r), tb_scale(w, r))),
                     tb_add(c, tb_add(tb_scale(u, -r), tb_scale(w, r)))};
  tb_vtu_piece piece = {4, quad, 2, quad_tri, 0, NULL, 0, NULL};
  return tb_vtu_write(path, &piece, 1, err);
}

int tb_sim_write_frame(tb_sim *s, const char *dir, int frame, tb_error *err) {
  if (mkdir(dir, 0777) && errno != EEXIST)
    return tb_error_set(err, dir, 0, "cannot create the folder: %s", strerror(errno));
  char paths[NOBJECTS][1100], vtm[1100];
  const char *names[NOBJECTS], *files[NOBJECTS];
  int n = 0;
  for (int k = 0; k < NOBJECTS; k++) {
    if (!has_object(s, k)) continue;
    if (object_path(paths[k], sizeof paths[k], dir, k, frame, err)) return -1;
    int rc = 0;
    if (k == BODY)
      rc = write_body(s, paths[k], err);
    else if (k == SURFACE)
      rc = write_surface(s, paths[k], err);
    else if (k == GROUND)
      rc = write_ground(s, paths[k], err);
    else {
      tb_mesh tool; /* posed at the current time, frame 0 included */
      tb_sim_instrument(s, &tool);
      tb_vtu_piece piece = {tool.nv, tool.x, tool.ntri, tool.tri, 0, NULL, 0, NULL};
      rc = tb_vtu_write(paths[k], &piece, 1, err);
    }
    if (rc) return -1;
    names[n] = object_name[k], files[n++] = strrchr(paths[k], '/') + 1;
  }
  if (snprintf(vtm, sizeof vtm, "%s/frame_%05d.vtm", dir, frame) >= (int)sizeof vtm)
    return tb_error_set(err, dir, 0, "path too long");
  return tb_vtm_write(vtm, n, names, files, err);
}

int tb_sim_write_surface(const tb_sim *s, const char *path, tb_error *err) {
  tb_surface su = tb_model_surface(&s->model);
  tb_mesh m = {0};
  m.nv = su.nv, m.x = (tb_vec3 *)su.x, m.ntri = su.ntri, m.tri = (int *)su.tri;
  return tb_mesh_write(path, &m, err);
}

/* dir/NAME.pvd over frames 0..n-1 of the files FORMAT (with the frame number). */
static int write_collection(const char *dir, const char *name, const char *format, int nframes,
                            const double *times, tb_error *err) {
  char path[1100];
  if (snprintf(path, sizeof path, "%s/%s.pvd", dir, name) >= (int)sizeof path)
    return tb_error_set(err, dir, 0, "path too long");
  char(*names)[48] = malloc(sizeof *names * (size_t)(nframes > 0 ? nframes : 1));
  const char **files = malloc(sizeof *files * (size_t)(nframes > 0 ? nframes : 1));
  if (!names || !files) {
    free(names), free(files);
    return tb_error_set(err, path, 0, "out of memory");
  }
  for (int k = 0; k < nframes; k++) {
    snprintf(names[k], sizeof names[k], format, k);
    files[k] = names[k];
  }
  int rc = tb_pvd_write(path, nframes, times, files, err);
  free(names), free(files);
  return rc;
}

int tb_sim_write_pvd(const tb_sim *s, const char *dir, int nframes, const double *times,
                     tb_error *err) {
  if (write_collection(dir, "frames", "frame_%05d.vtm", nframes, times, err)) return -1;
  for (int k = 0; k < NOBJECTS; k++) {
    char format[32];
    snprintf(format, sizeof format, "%s_%%05d.vtu", object_name[k]);
    if (has_object(s, k) && write_collection(dir, object_name[k], format, nframes, times, err))
      return -1;
  }
  return 0;
}
