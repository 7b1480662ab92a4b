/* Helpers the models share: lumped masses, the symmetric 3x3
 * eigen-decomposition (cyclic Jacobi), the polar decomposition's rotation
 * (through the eigenvectors of A^T A, det R = +1 even for inverted A, as in
 * Irving et al. 2004), the 3x3 inverse, the blow-up detector, and a
 * spatial order of points (recursive coordinate bisection, Berger & Bokhari
 * 1987). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_model.h"

int tb_check_tets(const tb_mesh *mesh, tb_error *err) {
  for (int t = 0; t < mesh->ntet; t++) {
    const int *n = mesh->tet + 4 * t;
    for (int k = 0; k < 4; k++)
      if (n[k] < 0 || n[k] >= mesh->nv)
        return tb_error_set(err, "mesh", 0, "tet %d refers to node %d (nv = %d)", t, n[k],
                            mesh->nv);
    double vol = tb_tet_volume(mesh->x[n[0]], mesh->x[n[1]], mesh->x[n[2]], mesh->x[n[3]]);
    if (!(vol > 0)) return tb_error_set(err, "mesh", 0, "tet %d has volume %g <= 0", t, vol);
  }
  return 0;
}

int tb_lumped_masses(const tb_mesh *mesh, double density, double node_mass, double *mass,
                     tb_error *err) {
  if (node_mass > 0) {
    for (int i = 0; i < mesh->nv; i++) mass[i] = node_mass;
    return 0;
  }
  memset(mass, 0, sizeof(double) * (size_t)mesh->nv);
  for (int t = 0; t < mesh->ntet; t++) {
    const int *e = mesh->tet + 4 * t;
    double vol = tb_tet_volume(mesh->x[e[0]], mesh->x[e[1]], mesh->x[e[2]], mesh->x[e[3]]);
    if (!(vol > 0)) return tb_error_set(err, "mesh", 0, "tet %d has volume %g <= 0", t, vol);
    for (int k = 0; k < 4; k++) mass[e[k]] += density * vol / 4.0;
  }
  for (int i = 0; i < mesh->nv; i++)
    if (!(mass[i] > 0))
      return tb_error_set(err, "mesh", 0, "node %d belongs to no tet (no mass; set node_mass)", i);
  return 0;
}

void tb_m3_sym_eigen(tb_mat3 a, double w[3], tb_mat3 *v) {
  tb_mat3 V = tb_m3_identity();
  for (int sweep = 0; sweep < 50; sweep++) {
    double off = a.m[0][1] * a.m[0][1] + a.m[0][2] * a.m[0][2] + a.m[1][2] * a.m[1][2];
    double diag = a.m[0][0] * a.m[0][0] + a.m[1][1] * a.m[1][1] + a.m[2][2] * a.m[2][2];
    if (off <= 1e-30 * diag || off == 0.0) break;
    for (int p = 0; p < 2; p++)
      for (int q = p + 1; q < 3; q++) {
        double apq = a.m[p][q];
        if (apq == 0.0) continue;
        double theta = (a.m[q][q] - a.m[p][p]) / (2.0 * apq);
        double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
        double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; k++) { /* a <- a J (columns p, q) */
          double akp = a.m[k][p], akq = a.m[k][q];
          a.m[k][p] = c * akp - s * akq, a.m[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; k++) { /* a <- J^T a (rows p, q) */
          double apk = a.m[p][k], aqk = a.m[q][k];
          a.m[p][k] = c * apk - s * aqk, a.m[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; k++) {
          double vkp = V.m[k][p], vkq = V.m[k][q];
          V.m[k][p] = c * vkp - s * vkq, V.m[k][q] = s * vkp + c * vkq;
        }
      }
  }
  int idx[3] = {0, 1, 2};
  for (int i = 0; i < 2; i++) /* sort ascending */
    for (int j = i + 1; j < 3; j++)
      if (a.m[idx[j]][idx[j]] < a.m[idx[i]][idx[i]]) {
        int t = idx[i];
        idx[i] = idx[j], idx[j] = t;
      }
  for (int j = 0; j < 3; j++) {
    w[j] = a.m[idx[j]][idx[j]];
    for (int k = 0; k < 3; k++) v->m[k][j] = V.m[k][idx[j]];
  }
}

static tb_vec3 column(tb_mat3 a, int j) { return tb_v3(a.m[0][j], a.m[1][j], a.m[2][j]); }

/* Any unit vector orthogonal to a unit vector n. */
static tb_vec3 orthogonal(tb_vec3 n) {
  tb_vec3 t = fabs(n.x) < 0.6 ? tb_v3(1, 0, 0) : tb_v3(0, 1, 0);
  return tb_normalize(tb_cross(n, t));
}

tb_mat3 tb_m3_polar(tb_mat3 a) {
  /* A = U S V^T: V from A^T A, U's columns A v_j / s_j, completed when s_j is tiny. */
  double w[3];
  tb_mat3 v;
  tb_m3_sym_eigen(tb_m3_mul(tb_m3_transpose(a), a), w, &v);
  double scale = sqrt(fmax(w[2], 0.0));
  if (!(scale > 0) || !isfinite(scale)) return tb_m3_identity();
  tb_vec3 u[3];
  for (int j = 2; j >= 0; j--) u[j] = tb_m3_mulv(a, column(v, j)); /* s_j u_j */
  double eps = 1e-12 * scale;
  /* largest two from A when they are well defined, the rest by cross products */
  if (tb_len(u[2]) <= eps) return tb_m3_identity();
  u[2] = tb_normalize(u[2]);
  u[1] = tb_sub(u[1], tb_scale(u[2], tb_dot(u[1], u[2])));
  u[1] = tb_len(u[1]) > eps ? tb_normalize(u[1]) : orthogonal(u[2]);
  u[0] = tb_cross(u[1], u[2]); /* right-handed with v's orientation fixed below */
  /* U V^T with det +1: make V right-handed first, then u0 follows from u1 x u2. */
  tb_vec3 v0 = column(v, 0), v1 = column(v, 1), v2 = column(v, 2);
  if (tb_dot(tb_cross(v1, v2), v0) < 0) v0 = tb_scale(v0, -1.0);
  tb_mat3 r;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      r.m[i][j] = tb_comp(u[0], i) * tb_comp(v0, j) + tb_comp(u[1], i) * tb_comp(v1, j) +
                  tb_comp(u[2], i) * tb_comp(v2, j);
  return r;
}

/* Rotation of the polar decomposition A = R S by Higham's scaled Newton
 * iteration X <- (g X + X^-T / g) / 2, g = sqrt(|X^-1| / |X|) (Frobenius),
 * about 3x faster than tb_m3_polar's eigen-decomposition; it converges to
 * the orthogonal factor, which is the rotation when det A > 0. Inverted,
 * singular or non-finite A go to tb_m3_polar (det R = +1 always). */
tb_mat3 tb_m3_polar_newton(tb_mat3 a) {
  if (!(tb_m3_det(a) > 0)) return tb_m3_polar(a);
  tb_mat3 x = a;
  int scaled = 1; /* near convergence g -> 1: plain Newton (Higham 1986 §3) */
  for (int it = 0; it < 40; it++) {
    double(*m)[3] = x.m;
    tb_mat3 c = tb_m3_cofactor(x); /* X^-T = c / det X */
    double det = m[0][0] * c.m[0][0] + m[0][1] * c.m[0][1] + m[0][2] * c.m[0][2];
    if (!(det > 0)) return tb_m3_polar(a);
    double g = 1;
    if (scaled) {
      double nx = 0, nc = 0;
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) nx += m[i][j] * m[i][j], nc += c.m[i][j] * c.m[i][j];
      g = sqrt(sqrt(nc) / (det * sqrt(nx))); /* sqrt(|X^-1| / |X|) */
      if (!isfinite(g)) return tb_m3_polar(a);
    }
    double fx = 0.5 * g, fc = 0.5 / (g * det), delta = 0;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        double y = fx * m[i][j] + fc * c.m[i][j], d = y - m[i][j];
        delta += d * d;
        x.m[i][j] = y;
      }
    if (delta < 1e-18) return x; /* converged quadratically: error ~ delta */
    if (delta < 1e-4) scaled = 0;
  }
  return tb_m3_polar(a);
}

int tb_m3_inverse(tb_mat3 a, tb_mat3 *inv) {
  double det = tb_m3_det(a), s = 0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) s = fmax(s, fabs(a.m[i][j]));
  if (!(fabs(det) > 1e-14 * s * s * s)) return 0;
  tb_mat3 c = tb_m3_cofactor(a), r;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) r.m[i][j] = c.m[j][i] / det;
  *inv = r;
  return 1;
}

/* One thread, whatever the count: on threads the check pulled half of the
 * state into the other core's cache after every step, and the next step of
 * a model running on one thread paid for it (scaling suite, 2 threads
 * against 1: msm-vvs 0.82x at 100k tets, fem 0.93x at 12.8k; 1.00x with
 * the check on one thread). It reads each node and tet once. */
tb_health tb_model_health(const tb_mesh *rest, const tb_vec3 *x, const tb_vec3 *v, double vmax,
                          int inversion) {
  tb_health h;
  h.ok = 1, h.reason[0] = 0;
  const int nv = rest->nv, ntet = inversion ? rest->ntet : 0;
  int bad = nv, fast = nv, inverted = 0, first = ntet;
  for (int i = 0; i < nv && bad == nv; i++)
    if (!tb_isfinite3(x[i]) || (v && !tb_isfinite3(v[i]))) bad = i;
  if (bad < nv) {
    h.ok = 0;
    snprintf(h.reason, sizeof h.reason, "NaN or inf (node %d)", bad);
    return h;
  }
  if (v && vmax > 0) {
    for (int i = 0; i < nv && fast == nv; i++)
      if (tb_len(v[i]) > vmax) fast = i;
    if (fast < nv) {
      h.ok = 0;
      snprintf(h.reason, sizeof h.reason, "velocity %.3g beyond bound %.3g (node %d)",
               tb_len(v[fast]), vmax, fast);
      return h;
    }
  }
  for (int t = 0; t < ntet; t++) {
    const int *e = rest->tet + 4 * t;
    double v0 = tb_tet_volume(rest->x[e[0]], rest->x[e[1]], rest->x[e[2]], rest->x[e[3]]);
    double v1 = tb_tet_volume(x[e[0]], x[e[1]], x[e[2]], x[e[3]]);
    if (v0 > 0 && !(v1 > 0)) {
      if (t < first) first = t;
      inverted++;
    }
  }
  if (inverted) {
    h.ok = 0;
    snprintf(h.reason, sizeof h.reason, "inverted elements (%d, first tet %d)", inverted, first);
  }
  return h;
}

int tb_model_surface_triangles(const tb_mesh *mesh, const char *model, int **tri, tb_error *err) {
  if (mesh->ntet > 0) {
    if (tb_check_tets(mesh, err)) return -1;
    int n = tb_mesh_tet_boundary(mesh, tri);
    if (n < 0) return tb_error_set(err, model, 0, "out of memory");
    return n;
  }
  if (mesh->ntri < 1)
    return tb_error_set(err, "mesh", 0,
                        "%s needs a closed triangle surface or a tet mesh (the mesh has %d nodes, "
                        "no triangles, no tets)",
                        model, mesh->nv);
  for (int k = 0; k < 3 * mesh->ntri; k++)
    if (mesh->tri[k] < 0 || mesh->tri[k] >= mesh->nv)
      return tb_error_set(err, "mesh", 0, "triangle %d refers to node %d (nv = %d)", k / 3,
                          mesh->tri[k], mesh->nv);
  tb_mesh_topo t = tb_mesh_topology(mesh);
  if (t.boundary_edges || t.nonmanifold_edges || t.nonmanifold_verts || t.misoriented_edges ||
      t.degenerate_tris)
    return tb_error_set(err, "mesh", 0,
                        "%s needs a closed manifold surface: %d open (boundary) edges, %d "
                        "non-manifold edges, %d non-manifold vertices, %d misoriented edges, %d "
                        "degenerate triangles",
                        model, t.boundary_edges, t.nonmanifold_edges, t.nonmanifold_verts,
                        t.misoriented_edges, t.degenerate_tris);
  *tri = malloc(sizeof(int) * 3 * (size_t)mesh->ntri);
  if (!*tri) return tb_error_set(err, model, 0, "out of memory");
  memcpy(*tri, mesh->tri, sizeof(int) * 3 * (size_t)mesh->ntri);
  return mesh->ntri;
}

/* ---- spatial order (recursive coordinate bisection) ---- */

/* Points at or below this count stay in the order their parent gave them. */
#define ORDER_LEAF 8

typedef struct keyed {
  double key;
  int id;
} keyed;

static int keyed_cmp(const void *pa, const void *pb) {
  const keyed *a = pa, *b = pb;
  if (a->key != b->key) return a->key < b->key ? -1 : 1;
  return (a->id > b->id) - (a->id < b->id);
}

/* Sorts ids[0..n) along the longest side of their box, then each half. */
static void bisect(const tb_vec3 *x, int *ids, int n, keyed *tmp) {
  while (n > ORDER_LEAF) {
    tb_vec3 lo = x[ids[0]], hi = lo;
    for (int k = 1; k < n; k++) {
      const tb_vec3 p = x[ids[k]];
      lo = tb_v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
      hi = tb_v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
    const tb_vec3 d = tb_sub(hi, lo);
    const int axis = d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
    for (int k = 0; k < n; k++) tmp[k].key = tb_comp(x[ids[k]], axis), tmp[k].id = ids[k];
    qsort(tmp, (size_t)n, sizeof *tmp, keyed_cmp);
    for (int k = 0; k < n; k++) ids[k] = tmp[k].id;
    const int h = n / 2;
    bisect(x, ids, h, tmp);
    ids += h, n -= h; /* the second half without recursion */
  }
}

int tb_spatial_order(const tb_vec3 *x, int n, int *order) {
  keyed *tmp = malloc(sizeof *tmp * (size_t)(n > 0 ? n : 1));
  if (!tmp) return -1;
  for (int k = 0; k < n; k++) order[k] = k;
  bisect(x, order, n, tmp);
  free(tmp);
  return 0;
}
