/* Metaballs driven by position-based dynamics, with a skinned surface
 * (the metaball patent, SPEC §2.6, step 2 (1)-(2); tb_metaball.h).
 *
 * Constraints, per step after the prediction v += dt (g + f / m),
 * p = c + dt v (fixed and removed spheres stay):
 *  - stretch (the patent's 拉伸约束, "fast convergence"): overlapping
 *    spheres (|c_i - c_j| < overlap (r_i + r_j) at rest) keep their rest
 *    distance, the distance constraint of Müller et al. 2007 with stiffness
 *    `stretch`, `iterations` Gauss-Seidel sweeps in link order;
 *  - unit (单元约束, "recovers the state when fully converged"; the patent
 *    derives it from each sphere's position and radius and defines no
 *    more): one per sphere, over the sphere and the spheres it overlaps, a
 *    shape-matching constraint (Müller et al. 2005, "Meshless deformations
 *    based on shape matching"; as a PBD constraint, Macklin et al. 2014,
 *    "Unified particle physics", §5): the members move the share `unit`
 *    towards cm + R q_j (a fixed sphere's constraint keeps its R: it
 *    holds its neighbours' orientation, not only their distance), R the rotation of the polar
 * decomposition of sum m_j (p_j - cm) q_jᵀ (found iteratively, tb_metaball_turns), q_j their rest
 * offsets from the rest centre of mass. Its only fixed points are rigid images of the rest shape,
 * hence the recovery. Applied once per step after the sweeps (a polar decomposition per sphere is
 * the step's largest cost); its R is also the sphere's rotation for the skin;
 *  - energy (能量约束, the coupling to the cut's point set) is the
 *    per-sphere force input here; fixed spheres hold;
 *  - contact across a crack (after a cut, models/metaball_pieces.c): sphere
 *    pairs the blade parted keep at least their distance at the cut's end,
 *    in each sweep and once after the unit constraints; and after the skin,
 *    its two faces (models/metaball_contact.c).
 * Then v = (p - c) / dt, damped by exp(-damping dt), c = p.
 *
 * Skin (step 2 (2), 高斯绑定): each surface vertex is bound to the (at
 * most) three spheres with the smallest k = d / r among those with k in
 * [1, 2] (d: vertex to centre at rest), weighted by exp(-k^2 / (2 sigma^2))
 * and normalised; a vertex with none in range takes the sphere of the
 * smallest k (counted: tb_metaball_fallbacks). It moves as
 * x = sum_s w_s (c_s + R_s (x0 - c0_s)), so a rigid motion of the spheres
 * moves it rigidly. Removing a sphere renormalises the weights of its
 * vertices over their other spheres, or binds them anew. */
#include "metaball_priv.h"

#include <math.h>
#include <stdlib.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include <string.h>

#include "tb_model.h"

void tb_metaball_settings_default(tb_metaball_settings *s) {
  s->density = 1, s->stretch = 1, s->unit = 0.5, s->damping = 1, s->sigma = 1, s->overlap = 1;
  s->iterations = 10;
}

void tb_metaball_destroy(tb_metaball *m) {
  if (!m) return;
  tb_metaball_cut_release(m);
  free(m->c0), free(m->c), free(m->p), free(m->v), free(m->r), free(m->m), free(m->w);
  free(m->alive), free(m->fixed), free(m->link), free(m->len0), free(m->cstart), free(m->cmember);
  free(m->cm0), free(m->rot), free(m->x0), free(m->x), free(m->bind), free(m->bw);
  free(m->em), free(m->eq), free(m->smq), free(m->wf), free(m->xo);
  free(m->contact), free(m->cdist), free(m->cnormal), free(m->piece), free(m->blend);
  tb_metaball_zone_free(m);
  free(m);
}

/* Unit constraint i's rest centre of mass over its alive members, and its
 * members' flat data for the step: mass (0 once removed), rest offset from
 * that centre, and their mass-weighted sum. */
static void rest_centre(tb_metaball *m, int i) {
  double mass = 0;
  tb_vec3 s = tb_v3(0, 0, 0);
  for (int k = m->cstart[i]; k < m->cstart[i + 1]; k++) {
    int j = m->cmember[k];
    if (m->alive[j]) mass += m->m[j], s = tb_madd(s, m->m[j], m->c0[j]);
  }
  m->cm0[i] = mass > 0 ? tb_scale(s, 1 / mass) : m->c0[i];
  m->smq[i] = tb_v3(0, 0, 0);
  for (int k = m->cstart[i]; k < m->cstart[i + 1]; k++) {
    int j = m->cmember[k];
    m->em[k] = m->alive[j] ? m->m[j] : 0, m->eq[k] = tb_sub(m->c0[j], m->cm0[i]);
    m->smq[i] = tb_madd(m->smq[i], m->em[k], m->eq[k]);
  }
}

/* The links' rest lengths and the unit constraints from the links: unit
 * constraint i holds the sphere, then its linked spheres in link order;
 * each with its rest centre of mass. Replaces len0 and cmember; the links
 * are first ordered by colour (colour_links). */
static int colour_links(tb_metaball *m, int n);
static int build_units(tb_metaball *m) {
  int n = m->n, nl = m->nl;
  if (colour_links(m, n)) return -1;
  free(m->len0), free(m->cmember), free(m->em), free(m->eq), free(m->smq), free(m->wf);
  size_t entries = (size_t)n + 2 * (size_t)nl;
  m->len0 = malloc(sizeof(double) * (size_t)(nl > 0 ? nl : 1));
  m->cmember = malloc(sizeof(int) * entries);
  m->em = malloc(sizeof(double) * entries), m->eq = malloc(sizeof(tb_vec3) * entries);
  m->smq = malloc(sizeof(tb_vec3) * (size_t)n), m->wf = malloc(sizeof(double) * (size_t)n);
  int *deg = calloc((size_t)n, sizeof(int));
  if (!m->len0 || !m->cmember || !m->em || !m->eq || !m->smq || !m->wf || !deg)
    return free(deg), -1;
  for (int e = 0; e < nl; e++)
    m->len0[e] = tb_dist(m->c0[m->link[2 * e]], m->c0[m->link[2 * e + 1]]);
  for (int e = 0; e < 2 * nl; e++) deg[m->link[e]]++;
  m->cstart[0] = 0;
  for (int i = 0; i < n; i++) m->cstart[i + 1] = m->cstart[i] + deg[i] + 1;
  for (int i = 0; i < n; i++) m->cmember[m->cstart[i]] = i, deg[i] = 1;
  for (int e = 0; e < nl; e++) {
    int a = m->link[2 * e], b = m->link[2 * e + 1];
    m->cmember[m->cstart[a] + deg[a]++] = b, m->cmember[m->cstart[b] + deg[b]++] = a;
  }
  free(deg);
  for (int i = 0; i < n; i++) rest_centre(m, i);
  return 0;
}

/* Vertex v bound anew over the alive spheres (see the head). */
static void bind_vertex(tb_metaball *m, int v, int ncand, const int *cand) {
  int best[3] = {-1, -1, -1}, any = -1;
  double kb[3] = {INFINITY, INFINITY, INFINITY}, kany = INFINITY;
  tb_vec3 x = m->x0[v];
  for (int t = 0; t < (cand ? ncand : m->n); t++) { /* k^2, no root: the same order */
    int s = cand ? cand[t] : t;
    if (!m->alive[s]) continue;
    tb_vec3 d = tb_sub(x, m->c0[s]);
    double k = tb_dot(d, d) / (m->r[s] * m->r[s]);
    if (k < kany) kany = k, any = s;
    if (k < 1 || k > 4 || !(k < kb[2])) continue;
    int at = 2; /* insert into the three smallest, ties by index */
    while (at > 0 && k < kb[at - 1]) kb[at] = kb[at - 1], best[at] = best[at - 1], at--;
    kb[at] = k, best[at] = s;
  }
  if (any < 0 && cand) { /* no candidate alive: all spheres */
    bind_vertex(m, v, 0, NULL);
    return;
  }
  if (best[0] < 0) best[0] = any, kb[0] = kany, m->nfallback++;
  double sum = 0;
  for (int q = 0; q < 3; q++) {
    m->bind[v][q] = best[q];
    m->bw[v][q] = best[q] < 0 ? 0 : exp(-kb[q] / (2 * m->set.sigma * m->set.sigma));
    sum += m->bw[v][q];
  }
  for (int q = 0; q < 3; q++) m->bw[v][q] = sum > 0 ? m->bw[v][q] / sum : (q == 0);
  tb_metaball_bind_offsets(m, v);
}

void tb_metaball_bind_offsets(tb_metaball *m, int v) {
  for (int q = 0; q < 3; q++) {
    int s = m->bind[v][q];
    m->xo[v][q] = s >= 0 ? tb_sub(m->x0[v], m->c0[s]) : tb_v3(0, 0, 0);
  }
}

/* x = sum_s w_s (c_s + R_s (x0 - c0_s)), the offsets x0 - c0_s stored;
 * plus what is left of a blend (see tb_metaball). */
void tb_metaball_reskin(tb_metaball *m) {
  double share = m->blend && m->blend_left > 0 ? m->blend_left / TB_METABALL_BLEND : 0;
  /* each vertex alone: any count */
#pragma omp parallel for schedule(static) if (m->nv >= TB_METABALL_PARALLEL_MIN)
  for (int v = 0; v < m->nv; v++) {
    tb_vec3 x = tb_v3(0, 0, 0);
    for (int q = 0; q < 3; q++) {
      int s = m->bind[v][q];
      if (s < 0) continue;
      tb_vec3 o = tb_m3_mulv(m->rot[s], m->xo[v][q]);
      x = tb_madd(x, m->bw[v][q], tb_add(m->c[s], o));
    }
    m->x[v] = share > 0 ? tb_madd(x, share, m->blend[v]) : x;
  }
}

/* Orders the links by colour (greedy, in link order: a link takes the
 * first colour none of whose links touches its spheres), links of one
 * colour in their old order. The sweeps stay Gauss-Seidel in this order;
 * consecutive links then share no sphere, so a projection need not wait
 * for the one before it (on the 570-sphere liver this more than halved
 * the sweeps' time; same convergence: microbench/metaball_timing.c). */
static int colour_links(tb_metaball *m, int n) {
  int nl = m->nl, ncol = 0;
  int *col = malloc(sizeof(int) * (size_t)(nl > 0 ? nl : 1)), *start = NULL, *out = NULL;
  unsigned char *used = NULL; /* used[c * n + s]: colour c touches sphere s */
  int cap = 0;
  if (!col) return -1;
  for (int e = 0; e < nl; e++) {
    int a = m->link[2 * e], b = m->link[2 * e + 1], c = 0;
    while (c < ncol && (used[(size_t)c * n + a] || used[(size_t)c * n + b])) c++;
    if (c == ncol) {
      if (ncol == cap) {
        cap = cap ? 2 * cap : 16;
        unsigned char *g = realloc(used, (size_t)cap * (size_t)n);
        if (!g) return free(col), free(used), -1;
        used = g;
      }
      memset(used + (size_t)ncol * n, 0, (size_t)n), ncol++;
    }
    used[(size_t)c * n + a] = used[(size_t)c * n + b] = 1, col[e] = c;
  }
  free(used);
  start = calloc((size_t)ncol + 1, sizeof(int)),
  out = malloc(sizeof(int) * 2 * (size_t)(nl > 0 ? nl : 1));
  if (!start || !out) return free(col), free(start), free(out), -1;
  for (int e = 0; e < nl; e++) start[col[e] + 1]++;
  for (int c = 0; c < ncol; c++) start[c + 1] += start[c];
  for (int e = 0; e < nl; e++) {
    int at = start[col[e]]++;
    out[2 * at] = m->link[2 * e], out[2 * at + 1] = m->link[2 * e + 1];
  }
  memcpy(m->link, out, sizeof(int) * 2 * (size_t)nl);
  free(col), free(start), free(out);
  return 0;
}

tb_metaball *tb_metaball_create(int n, const tb_vec3 *c, const double *r, const tb_mesh *surface,
                                const tb_metaball_settings *set, tb_error *err) {
  if (n < 1) return tb_error_set(err, "metaball", 0, "no spheres"), NULL;
  for (int i = 0; i < n; i++)
    if (!(r[i] > 0) || !isfinite(r[i]) || !isfinite(c[i].x) || !isfinite(c[i].y) ||
        !isfinite(c[i].z))
      return tb_error_set(err, "metaball", 0, "sphere %d: centre or radius not finite, or r <= 0",
                          i),
             NULL;
  tb_metaball *m = calloc(1, sizeof *m);
  if (!m) return tb_error_set(err, "metaball", 0, "out of memory"), NULL;
  m->set = *set, m->n = n, m->nv = surface ? surface->nv : 0;
  size_t N = (size_t)n, V = (size_t)(m->nv > 0 ? m->nv : 1);
  m->c0 = malloc(sizeof(tb_vec3) * N), m->c = malloc(sizeof(tb_vec3) * N);
  m->p = malloc(sizeof(tb_vec3) * N), m->v = calloc(N, sizeof(tb_vec3));
  m->r = malloc(sizeof(double) * N), m->m = malloc(sizeof(double) * N);
  m->w = malloc(sizeof(double) * N), m->alive = malloc(N), m->fixed = calloc(N, 1);
  m->cstart = malloc(sizeof(int) * (N + 1)), m->cm0 = malloc(sizeof(tb_vec3) * N);
  m->rot = malloc(sizeof(tb_mat3) * N);
  m->x0 = malloc(sizeof(tb_vec3) * V), m->x = malloc(sizeof(tb_vec3) * V);
  m->bind = malloc(sizeof *m->bind * V), m->bw = malloc(sizeof *m->bw * V);
  m->xo = malloc(sizeof *m->xo * V);
  int cap = 64, nl = 0;
  m->link = malloc(sizeof(int) * 2 * (size_t)cap);
  if (!m->c0 || !m->c || !m->p || !m->v || !m->r || !m->m || !m->w || !m->alive || !m->fixed ||
      !m->cstart || !m->cm0 || !m->rot || !m->x0 || !m->x || !m->bind || !m->bw || !m->xo ||
      !m->link)
    goto oom;
  memcpy(m->c0, c, sizeof(tb_vec3) * N), memcpy(m->c, c, sizeof(tb_vec3) * N);
  memcpy(m->r, r, sizeof(double) * N);
  memset(m->alive, 1, N);
  for (int i = 0; i < n; i++) {
    m->m[i] = set->density * 4.0 / 3.0 * M_PI * r[i] * r[i] * r[i];
    m->w[i] = m->m[i] > 0 ? 1 / m->m[i] : 0;
    m->rot[i] = tb_m3_identity();
  }
  for (int i = 0; i < n; i++) /* overlapping pairs, i < j (quadratic: hundreds of spheres) */
    for (int j = i + 1; j < n; j++) {
      if (!(tb_dist(c[i], c[j]) < set->overlap * (r[i] + r[j]))) continue;
      if (nl == cap) {
        int *grown = realloc(m->link, sizeof(int) * 4 * (size_t)cap);
        if (!grown) goto oom;
        m->link = grown, cap *= 2;
      }
      m->link[2 * nl] = i, m->link[2 * nl + 1] = j, nl++;
    }
  m->nl = nl;
  if (build_units(m)) goto oom;
  if (surface) {
    memcpy(m->x0, surface->x, sizeof(tb_vec3) * (size_t)m->nv);
    for (int v = 0; v < m->nv; v++) bind_vertex(m, v, 0, NULL);
    tb_metaball_reskin(m);
  }
  return m;
oom:
  tb_metaball_destroy(m);
  return tb_error_set(err, "metaball", 0, "out of memory (%d spheres)", n), NULL;
}

/* ---- growing the model (the cut's new spheres; metaball_priv.h) ---- */

int tb_metaball_add(tb_metaball *m, int k, const tb_vec3 *c0, const tb_vec3 *c, const tb_mat3 *rot,
                    const double *r, const tb_vec3 *v) {
  size_t N = (size_t)m->n + (size_t)k;
#define TB_GROW(field, type)                            \
  do {                                                  \
    type *grown_ = realloc(m->field, sizeof(type) * N); \
    if (!grown_) return -1;                             \
    m->field = grown_;                                  \
  } while (0)
  TB_GROW(c0, tb_vec3);
  TB_GROW(c, tb_vec3);
  TB_GROW(p, tb_vec3);
  TB_GROW(v, tb_vec3);
  TB_GROW(cm0, tb_vec3);
  TB_GROW(r, double);
  TB_GROW(m, double);
  TB_GROW(w, double);
  TB_GROW(alive, unsigned char);
  TB_GROW(fixed, unsigned char);
  TB_GROW(rot, tb_mat3);
  if (m->piece) TB_GROW(piece, int);
#undef TB_GROW
  int *cs = realloc(m->cstart, sizeof(int) * (N + 1));
  if (!cs) return -1;
  m->cstart = cs;
  for (int q = 0; q < k; q++) {
    int i = m->n + q;
    m->c0[i] = c0[q], m->c[i] = m->p[i] = c[q], m->v[i] = v ? v[q] : tb_v3(0, 0, 0);
    m->r[i] = r[q], m->m[i] = m->set.density * 4.0 / 3.0 * M_PI * r[q] * r[q] * r[q];
    m->w[i] = m->m[i] > 0 ? 1 / m->m[i] : 0;
    m->alive[i] = 1, m->fixed[i] = 0, m->rot[i] = rot ? rot[q] : tb_m3_identity();
    if (m->piece) m->piece[i] = -1;
  }
  m->n = (int)N;
  return build_units(m);
}

int tb_metaball_set_links(tb_metaball *m, int nl, const int *pairs) {
  int *link = malloc(sizeof(int) * 2 * (size_t)(nl > 0 ? nl : 1));
  if (!link) return -1;
  memcpy(link, pairs, sizeof(int) * 2 * (size_t)nl);
  free(m->link);
  m->link = link, m->nl = nl;
  return build_units(m);
}

void tb_metaball_fix(tb_metaball *m, int i, int fixed) {
  if (i < 0 || i >= m->n) return;
  m->fixed[i] = fixed != 0;
  if (fixed) m->v[i] = tb_v3(0, 0, 0);
}

/* The alive spheres nearest to the spheres `from` in the
 * sphere graph, through gone ones, at most GRAPH_HOPS links away (the unit
 * constraints' member lists are the graph: removal keeps them), into cand
 * (room for 2 m->n); mark[] holds `stamp` for the spheres seen. Their
 * count. */
#define GRAPH_HOPS 3
static int graph_near(const tb_metaball *m, const int *from, int nfrom, int *cand, int *mark,
                      int stamp) {
  int *queue = cand + m->n, nq = 0, nc = 0;
  for (int k = 0; k < nfrom; k++)
    if (mark[from[k]] != stamp) mark[from[k]] = stamp, queue[nq++] = from[k];
  for (int hop = 0, head = 0; hop < GRAPH_HOPS && nc == 0 && head < nq; hop++) {
    int end = nq;
    for (; head < end; head++) {
      int i = queue[head];
      for (int e = m->cstart[i] + 1; e < m->cstart[i + 1]; e++) {
        int j = m->cmember[e];
        if (mark[j] == stamp) continue;
        mark[j] = stamp;
        if (m->alive[j])
          cand[nc++] = j;
        else
          queue[nq++] = j;
      }
    }
  }
  return nc;
}

void tb_metaball_remove_set(tb_metaball *m, int k, const int *ids) {
  unsigned char *gone = calloc((size_t)m->n, 1);
  if (!gone) { /* one at a time: the same result, slower */
    for (int q = 0; q < k; q++) tb_metaball_remove(m, ids[q]);
    return;
  }
  int any = 0;
  for (int q = 0; q < k; q++) {
    int i = ids[q];
    if (i < 0 || i >= m->n || !m->alive[i]) continue;
    m->alive[i] = 0, m->v[i] = tb_v3(0, 0, 0), gone[i] = 1, any = 1;
  }
  if (!any) {
    free(gone);
    return;
  }
  int nl = 0;
  for (int e = 0; e < m->nl; e++) { /* their links go; the others keep their order */
    int a = m->link[2 * e], b = m->link[2 * e + 1];
    if (gone[a] || gone[b]) continue;
    m->link[2 * nl] = a, m->link[2 * nl + 1] = b, m->len0[nl++] = m->len0[e];
  }
  m->nl = nl;
  for (int q = 0; q < k; q++) { /* each unit constraint that held one of them, once */
    int i = ids[q];
    if (i < 0 || i >= m->n || gone[i] != 1) continue;
    for (int e = m->cstart[i] + 1; e < m->cstart[i + 1]; e++) {
      int j = m->cmember[e];
      if (!gone[j]) gone[j] = 2, rest_centre(m, j);
    }
  }
  /* their vertices: the other spheres, or bound anew among the alive
   * spheres nearest to the lost ones in the sphere graph (through removed
   * ones, up to GRAPH_HOPS links away): a vertex stays with its piece and
   * its side of every earlier cut, which the links never cross */
  int *cand = malloc(sizeof(int) * 2 * (size_t)m->n), *mark = calloc((size_t)m->n, sizeof(int));
  int fallbacks = m->nfallback;
  for (int v = 0; v < m->nv; v++) {
    double left = 1;
    int lost[3], nlost = 0;
    for (int q = 0; q < 3; q++) {
      int b = m->bind[v][q];
      if (b < 0 || gone[b] != 1) continue;
      left -= m->bw[v][q], m->bind[v][q] = -1, m->bw[v][q] = 0, lost[nlost++] = b;
    }
    if (!nlost) continue;
    if (left > 1e-12) {
      for (int q = 0; q < 3; q++) m->bw[v][q] /= left;
      continue;
    }
    int nc = cand && mark ? graph_near(m, lost, nlost, cand, mark, v + 1) : 0;
    bind_vertex(m, v, nc, nc ? cand : NULL);
  }
  m->nfallback = fallbacks; /* not fallbacks of the packing */
  free(cand), free(mark), free(gone);
}

void tb_metaball_remove(tb_metaball *m, int i) { tb_metaball_remove_set(m, 1, &i); }

void tb_metaball_transform(tb_metaball *m, const double R[9], tb_vec3 t) {
  tb_mat3 rot = {{{R[0], R[1], R[2]}, {R[3], R[4], R[5]}, {R[6], R[7], R[8]}}};
  for (int i = 0; i < m->n; i++) {
    m->c[i] = tb_add(tb_m3_mulv(rot, m->c[i]), t), m->v[i] = tb_m3_mulv(rot, m->v[i]);
    m->rot[i] = tb_m3_mul(rot, m->rot[i]);
  }
  tb_metaball_reskin(m);
}

/* The rotation of the polar decomposition of a, iterated from r (Müller,
 * Bender, Chentanez & Macklin 2016, "A robust method to extract the
 * rotational part of deformations"): r turns about sum_k r_k x a_k / |sum_k
 * r_k . a_k| (r_k, a_k the columns) until a turn is below tol, at most
 * `turns` times. The unit constraints take 1e-12 rad and 4 turns a step:
 * warm-started from the last step's rotation it
 * converges over the steps (560 spheres on a grid, 10 sweeps: 0.68 ms per
 * step against 0.74 with a Jacobi polar decomposition per sphere), and a
 * degenerate cluster (two or three members in a line or a plane) keeps its
 * last rotation about the free axis instead of an arbitrary one. */
tb_mat3 tb_metaball_turns(tb_mat3 a, tb_mat3 r, int turns, double tol) {
  for (int it = 0; it < turns; it++) {
    tb_vec3 num = tb_v3(0, 0, 0);
    double den = 0;
    for (int k = 0; k < 3; k++) {
      tb_vec3 rk = tb_v3(r.m[0][k], r.m[1][k], r.m[2][k]),
              ak = tb_v3(a.m[0][k], a.m[1][k], a.m[2][k]);
      num = tb_add(num, tb_cross(rk, ak)), den += tb_dot(rk, ak);
    }
    if (!(fabs(den) > 0)) break;
    tb_vec3 w = tb_scale(num, 1 / fabs(den));
    double angle = tb_len(w);
    if (!(angle > tol)) break;
    r = tb_m3_mul(tb_m3_rotation(tb_scale(w, 1 / angle), angle), r);
  }
  return r;
}

#ifdef __SSE2__
static inline __m128d pair3(const tb_vec3 *p, int j0, int j1, int c) { /* (p[j0].c, p[j1].c) */
  const double *a = &p[j0].x, *b = &p[j1].x;
  return _mm_loadh_pd(_mm_load_sd(a + c), b + c);
}
static inline double hsum(__m128d v) { return _mm_cvtsd_f64(_mm_add_sd(v, _mm_unpackhi_pd(v, v))); }
#endif

/* Constraint i's sums over its members (see unit_constraints): M, sum m_j d_j
 * and A = sum m_j d_j q_j^T, d_j = p_j - p_i. With SSE2 two members at a
 * time, one in each lane, the lanes added at the end. */
static double unit_sums(const tb_metaball *m, int i, double s[3], double A[9]) {
  const int *member = m->cmember;
  const double *em = m->em;
  const tb_vec3 *eq = m->eq, *p = m->p;
  int k = m->cstart[i], k1 = m->cstart[i + 1];
  tb_vec3 pi = p[i];
  double mass = 0, sx = 0, sy = 0, sz = 0;
  double a00 = 0, a01 = 0, a02 = 0, a10 = 0, a11 = 0, a12 = 0, a20 = 0, a21 = 0, a22 = 0;
#ifdef __SSE2__
  __m128d vm = _mm_setzero_pd(), vx = vm, vy = vm, vz = vm;
  __m128d b00 = vm, b01 = vm, b02 = vm, b10 = vm, b11 = vm, b12 = vm, b20 = vm, b21 = vm, b22 = vm;
  const __m128d px = _mm_set1_pd(pi.x), py = _mm_set1_pd(pi.y), pz = _mm_set1_pd(pi.z);
  for (; k + 1 < k1; k += 2) {
    int j0 = member[k], j1 = member[k + 1];
    __m128d e = _mm_loadu_pd(em + k);
    __m128d dx = _mm_mul_pd(_mm_sub_pd(pair3(p, j0, j1, 0), px), e);
    __m128d dy = _mm_mul_pd(_mm_sub_pd(pair3(p, j0, j1, 1), py), e);
    __m128d dz = _mm_mul_pd(_mm_sub_pd(pair3(p, j0, j1, 2), pz), e);
    __m128d qx = pair3(eq, k, k + 1, 0), qy = pair3(eq, k, k + 1, 1), qz = pair3(eq, k, k + 1, 2);
    vm = _mm_add_pd(vm, e), vx = _mm_add_pd(vx, dx), vy = _mm_add_pd(vy, dy);
    vz = _mm_add_pd(vz, dz);
    b00 = _mm_add_pd(b00, _mm_mul_pd(dx, qx)), b01 = _mm_add_pd(b01, _mm_mul_pd(dx, qy));
    b02 = _mm_add_pd(b02, _mm_mul_pd(dx, qz)), b10 = _mm_add_pd(b10, _mm_mul_pd(dy, qx));
    b11 = _mm_add_pd(b11, _mm_mul_pd(dy, qy)), b12 = _mm_add_pd(b12, _mm_mul_pd(dy, qz));
    b20 = _mm_add_pd(b20, _mm_mul_pd(dz, qx)), b21 = _mm_add_pd(b21, _mm_mul_pd(dz, qy));
    b22 = _mm_add_pd(b22, _mm_mul_pd(dz, qz));
  }
  mass = hsum(vm), sx = hsum(vx), sy = hsum(vy), sz = hsum(vz);
  a00 = hsum(b00), a01 = hsum(b01), a02 = hsum(b02), a10 = hsum(b10), a11 = hsum(b11);
  a12 = hsum(b12), a20 = hsum(b20), a21 = hsum(b21), a22 = hsum(b22);
#endif
  for (; k < k1; k++) { /* the sums in scalars, not an array: they stay in registers */
    tb_vec3 md = tb_scale(tb_sub(p[member[k]], pi), em[k]), q = eq[k];
    mass += em[k], sx += md.x, sy += md.y, sz += md.z;
    a00 += md.x * q.x, a01 += md.x * q.y, a02 += md.x * q.z;
    a10 += md.y * q.x, a11 += md.y * q.y, a12 += md.y * q.z;
    a20 += md.z * q.x, a21 += md.z * q.y, a22 += md.z * q.z;
  }
  s[0] = sx, s[1] = sy, s[2] = sz;
  A[0] = a00, A[1] = a01, A[2] = a02, A[3] = a10, A[4] = a11, A[5] = a12;
  A[6] = a20, A[7] = a21, A[8] = a22;
  return mass;
}

/* Constraint i's goals, p_j += unit (cm + R q_j - p_j) for its free members;
 * with SSE2 two at a time, the scalar operations in the same order. */
static void unit_goals(tb_metaball *m, int i, tb_vec3 cm, tb_mat3 R) {
  const int *member = m->cmember;
  const double *wf = m->wf, unit = m->set.unit;
  const tb_vec3 *eq = m->eq;
  tb_vec3 *p = m->p;
  int k = m->cstart[i], k1 = m->cstart[i + 1];
#ifdef __SSE2__
  const __m128d u = _mm_set1_pd(unit), cx = _mm_set1_pd(cm.x), cy = _mm_set1_pd(cm.y),
                cz = _mm_set1_pd(cm.z);
  __m128d r[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) r[a][b] = _mm_set1_pd(R.m[a][b]);
  for (; k + 1 < k1; k += 2) {
    int j0 = member[k], j1 = member[k + 1];
    int f0 = wf[j0] != 0, f1 = wf[j1] != 0; /* fixed or removed: left */
    if (!f0 && !f1) continue;
    __m128d q[3] = {pair3(eq, k, k + 1, 0), pair3(eq, k, k + 1, 1), pair3(eq, k, k + 1, 2)};
    __m128d c[3] = {cx, cy, cz};
    for (int a = 0; a < 3; a++) {
      __m128d rq = _mm_add_pd(_mm_add_pd(_mm_mul_pd(r[a][0], q[0]), _mm_mul_pd(r[a][1], q[1])),
                              _mm_mul_pd(r[a][2], q[2]));
      __m128d pj = pair3(p, j0, j1, a), goal = _mm_add_pd(c[a], rq);
      pj = _mm_add_pd(pj, _mm_mul_pd(u, _mm_sub_pd(goal, pj)));
      if (f0) _mm_storel_pd(&p[j0].x + a, pj);
      if (f1) _mm_storeh_pd(&p[j1].x + a, pj);
    }
  }
#endif
  for (; k < k1; k++) {
    int j = member[k];
    if (wf[j] == 0) continue; /* fixed or removed */
    tb_vec3 goal = tb_add(cm, tb_m3_mulv(R, eq[k]));
    p[j] = tb_madd(p[j], unit, tb_sub(goal, p[j]));
  }
}

/* The unit constraints (see the head), in sphere order; each sphere's
 * rotation is its own constraint's. One pass over the members gives the
 * centre of mass and A = sum_j m_j (p_j - cm) q_j^T: with d_j = p_j - p_i
 * (the sphere's own, which keeps A free of the organ's distance from the
 * origin), cm = p_i + sum m_j d_j / M and A = sum m_j d_j q_j^T - (cm -
 * p_i) (sum m_j q_j)^T, the last sum 0 but for rounding (rest_centre). */
static void unit_constraints(tb_metaball *m) {
  for (int i = 0; i < m->n; i++) {
    if (!m->alive[i]) continue;
    double s[3], a[9], mass = unit_sums(m, i, s, a);
    tb_vec3 rel = tb_scale(tb_v3(s[0], s[1], s[2]), 1 / mass), cm = tb_add(m->p[i], rel),
            c = m->smq[i];
    tb_mat3 A = {{{a[0] - rel.x * c.x, a[1] - rel.x * c.y, a[2] - rel.x * c.z},
                  {a[3] - rel.y * c.x, a[4] - rel.y * c.y, a[5] - rel.y * c.z},
                  {a[6] - rel.z * c.x, a[7] - rel.z * c.y, a[8] - rel.z * c.z}}};
    int k0 = m->cstart[i], k1 = m->cstart[i + 1];
    tb_mat3 rot =
        k1 - k0 > 1 && !m->fixed[i] ? tb_metaball_turns(A, m->rot[i], 4, 1e-12) : m->rot[i];
    m->rot[i] = rot;
    unit_goals(m, i, cm, rot);
  }
}

/* One link's distance constraint (stiffness `stretch`, inverse masses wf). */
static void stretch_link(tb_vec3 *p, const double *wf, int a, int b, double len0, double stretch) {
  double wa = wf[a], wb = wf[b];
  if (wa + wb == 0) return;
  tb_vec3 d = tb_sub(p[b], p[a]);
  double l = tb_len(d);
  if (!(l > 0)) return;
  double s = stretch * (l - len0) / ((wa + wb) * l);
  p[a] = tb_madd(p[a], wa * s, d), p[b] = tb_madd(p[b], -wb * s, d);
}

/* Contacts across cracks: a pair (a, b) whose separation along the crack's
 * normal n (a's rotation turns it) is below its least one, while the two
 * face each other (their offset across n under r_a + r_b), is pushed apart
 * along n to it, by inverse masses (a one-sided constraint, as Müller et al.
 * 2007 §4.3's collision constraints; sliding along the crack is free). */
static void contacts(tb_metaball *m) {
  const double *wf = m->wf;
  tb_vec3 *p = m->p;
  for (int k = 0; k < m->ncontact; k++) {
    int a = m->contact[2 * k], b = m->contact[2 * k + 1];
    double wa = wf[a], wb = wf[b];
    if (wa + wb == 0) continue;
    tb_vec3 n = tb_m3_mulv(m->rot[a], m->cnormal[k]), d = tb_sub(p[b], p[a]);
    double g = tb_dot(d, n) - m->cdist[k];
    if (!(g < 0) || tb_len(tb_madd(d, -tb_dot(d, n), n)) > m->r[a] + m->r[b]) continue;
    double s = -g / (wa + wb);
    p[a] = tb_madd(p[a], -wa * s, n), p[b] = tb_madd(p[b], wb * s, n);
  }
}

/* The stretch sweeps: Gauss-Seidel in link order. Two consecutive links
 * sharing no sphere (the rule within a colour, colour_links) are projected
 * together, one in each lane of SSE2 registers: the scalar operations in
 * the same order, correctly rounded, so the same numbers. */
static void stretch_sweeps(tb_metaball *m) {
  const int *L = m->link;
  const double *len0 = m->len0, *wf = m->wf;
  tb_vec3 *p = m->p;
  double stretch = m->set.stretch;
  int nl = m->nl;
  for (int it = 0; it < m->set.iterations; it++) {
    int e = 0;
#ifdef __SSE2__
    const __m128d zero = _mm_setzero_pd(), k = _mm_set1_pd(stretch);
    for (; e + 1 < nl; e += 2) {
      int a0 = L[2 * e], b0 = L[2 * e + 1], a1 = L[2 * e + 2], b1 = L[2 * e + 3];
      __m128d wa = _mm_set_pd(wf[a1], wf[a0]), wb = _mm_set_pd(wf[b1], wf[b0]);
      /* (x, y) of each sphere in one load, then transposed to a lane per link */
      __m128d a0xy = _mm_loadu_pd(&p[a0].x), a1xy = _mm_loadu_pd(&p[a1].x);
      __m128d b0xy = _mm_loadu_pd(&p[b0].x), b1xy = _mm_loadu_pd(&p[b1].x);
      __m128d ax = _mm_unpacklo_pd(a0xy, a1xy), ay = _mm_unpackhi_pd(a0xy, a1xy);
      __m128d bx = _mm_unpacklo_pd(b0xy, b1xy), by = _mm_unpackhi_pd(b0xy, b1xy);
      __m128d az = _mm_loadh_pd(_mm_load_sd(&p[a0].z), &p[a1].z);
      __m128d bz = _mm_loadh_pd(_mm_load_sd(&p[b0].z), &p[b1].z);
      __m128d dx = _mm_sub_pd(bx, ax), dy = _mm_sub_pd(by, ay), dz = _mm_sub_pd(bz, az);
      __m128d q =
          _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz));
      __m128d w = _mm_add_pd(wa, wb);
      if (a0 == a1 || a0 == b1 || b0 == a1 || b0 == b1 ||
          _mm_movemask_pd(_mm_and_pd(_mm_cmpgt_pd(w, zero), _mm_cmpgt_pd(q, zero))) != 3) {
        stretch_link(p, wf, a0, b0, len0[e], stretch); /* shared sphere, or a link to skip */
        e--;
        continue;
      }
      __m128d l = _mm_sqrt_pd(q);
      __m128d s =
          _mm_div_pd(_mm_mul_pd(k, _mm_sub_pd(l, _mm_loadu_pd(len0 + e))), _mm_mul_pd(w, l));
      __m128d sa = _mm_mul_pd(wa, s), sb = _mm_mul_pd(_mm_sub_pd(zero, wb), s);
      ax = _mm_add_pd(ax, _mm_mul_pd(sa, dx)), ay = _mm_add_pd(ay, _mm_mul_pd(sa, dy));
      az = _mm_add_pd(az, _mm_mul_pd(sa, dz)), bx = _mm_add_pd(bx, _mm_mul_pd(sb, dx));
      by = _mm_add_pd(by, _mm_mul_pd(sb, dy)), bz = _mm_add_pd(bz, _mm_mul_pd(sb, dz));
      _mm_storeu_pd(&p[a0].x, _mm_unpacklo_pd(ax, ay));
      _mm_storeu_pd(&p[a1].x, _mm_unpackhi_pd(ax, ay));
      _mm_storeu_pd(&p[b0].x, _mm_unpacklo_pd(bx, by));
      _mm_storeu_pd(&p[b1].x, _mm_unpackhi_pd(bx, by));
      _mm_storel_pd(&p[a0].z, az), _mm_storeh_pd(&p[a1].z, az);
      _mm_storel_pd(&p[b0].z, bz), _mm_storeh_pd(&p[b1].z, bz);
    }
#endif
    for (; e < nl; e++) stretch_link(p, wf, L[2 * e], L[2 * e + 1], len0[e], stretch);
    contacts(m);
  }
}

void tb_metaball_step(tb_metaball *m, double dt, tb_vec3 gravity, const tb_vec3 *force) {
  int n = m->n;
  m->blend_left = fmax(0, m->blend_left - dt);
  for (int i = 0; i < n; i++) {
    if (!m->alive[i] || m->fixed[i]) {
      m->p[i] = m->c[i], m->wf[i] = 0;
      continue;
    }
    m->wf[i] = m->w[i];
    tb_vec3 a = gravity;
    if (force) a = tb_madd(a, m->w[i], force[i]);
    m->v[i] = tb_madd(m->v[i], dt, a);
    m->p[i] = tb_madd(m->c[i], dt, m->v[i]);
  }
  stretch_sweeps(m);
  unit_constraints(m);
  contacts(m);
  double keep = exp(-m->set.damping * dt);
  for (int i = 0; i < n; i++) {
    if (!m->alive[i] || m->fixed[i]) continue;
    m->v[i] = tb_scale(tb_sub(m->p[i], m->c[i]), keep / dt);
    m->c[i] = m->p[i];
  }
  tb_metaball_reskin(m);
  tb_metaball_zone_contact(m, dt);
}

int tb_metaball_count(const tb_metaball *m) { return m->n; }
const tb_vec3 *tb_metaball_centres(const tb_metaball *m) { return m->c; }
const tb_vec3 *tb_metaball_velocities(const tb_metaball *m) { return m->v; }
const double *tb_metaball_radii(const tb_metaball *m) { return m->r; }
const double *tb_metaball_masses(const tb_metaball *m) { return m->m; }
int tb_metaball_links(const tb_metaball *m, const int **pairs) {
  *pairs = m->link;
  return m->nl;
}
const tb_vec3 *tb_metaball_skin(const tb_metaball *m) { return m->x; }
int tb_metaball_fallbacks(const tb_metaball *m) { return m->nfallback; }
int tb_metaball_binding(const tb_metaball *m, int v, int sphere[3], double weight[3]) {
  int k = 0;
  for (int q = 0; q < 3; q++)
    if (m->bind[v][q] >= 0) sphere[k] = m->bind[v][q], weight[k++] = m->bw[v][q];
  return k;
}
