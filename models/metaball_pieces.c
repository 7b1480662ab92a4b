/* The skin and the spheres after a cut (tb_metaball_set_skin; the metaball
 * patent's step 3 (5), re-binding, 重新绑定). The cut surface is the truth of
 * what the blade parted: the spheres follow its pieces, and the skin of a
 * piece is bound to spheres of that piece only.
 *
 * 1. Pieces: the components of the surface's triangles; a sphere's piece is
 *    the one holding its current centre (exact ray parity,
 *    tb_cut_locate). A new sphere (from the point set) in no piece lies
 *    outside the organ and is removed; an old one in none (a packing may put
 *    a centre just outside) goes with the piece most vertices bound to it
 *    are on, else with its nearest vertex's.
 * 2. A piece with fewer than four spheres (a severed sliver, a wedge
 *    between two cracks) gets more, up to four: each at the inward-pushed
 *    triangle centroid farthest from the piece's spheres (from its vertices
 *    for the first: its inscribed ball, roughly), reaching its nearest
 *    vertex, moving with the piece's mean velocity, at rest where the
 *    piece's rigid fit of its vertices to their rest positions puts it.
 *    Links between two pieces go. A piece whose spheres fall into several
 *    groups (components through the links) has them joined, one link at a
 *    time, between the two nearest spheres of different groups (gap
 *    |c_i - c_j| - r_i - r_j), not across the last fold where another pair
 *    will do. A sphere with fewer than five links is linked to its nearest
 *    spheres of its piece (not across the fold) until it has five, or all
 *    of its piece: with fewer a group of spheres turns about them as on a
 *    hinge, its skin folding over its neighbours'.
 * 3. Contact: pairs of spheres on either side of the last fold (their centre
 *    segment crosses it, or they are in two pieces) within 1.5 (r_i + r_j)
 *    keep at least their present separation along the fold's normal (carried
 *    by the first one's rotation) while they face each other, by the step
 *    (models/metaball.c): the two faces of the crack touch now, may slide
 *    along each other, and do not pass through each other.
 * 4. The skin: a vertex is bound anew when it is new, asked for, bound to a
 *    removed sphere or one of another piece, or (off the fold) to one whose
 *    centre lies across the fold; then to the spheres with the smallest
 *    k = d / r in [1, 2] among those of its piece on its side (its crack
 *    side, or not across the fold), else the smallest k among them, else in
 *    its piece, else anywhere. Its rest position is the one the caller gives
 *    (the cut surface's, consistent with the old surface: models/
 *    metaball_model_cut.c), the skin blended in from x over
 *    TB_METABALL_BLEND; without one, it solves the skin formula at the
 *    current configuration, so the skin reproduces x. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metaball_priv.h"
#include "tb_model.h"
#include "cutting/tb_cut_surface.h"

#define REACH 1.5 /* contact pairs: centres within REACH (r_i + r_j) */

typedef struct pieces {
  int n;
  int *of_tri, *of_vertex; /* a vertex no triangle uses: -1 */
  int *of_sphere;          /* -1: removed, or no pieces */
} pieces;

static void pieces_free(pieces *P) { free(P->of_tri), free(P->of_vertex), free(P->of_sphere); }

static int uf_find(int *p, int i) {
  while (p[i] != i) i = p[i] = p[p[i]];
  return i;
}

/* ---- 1. pieces of the surface and of the spheres ---- */

static int surface_pieces(const tb_metaball_skin_def *d, pieces *P) {
  P->of_tri = malloc(sizeof(int) * (size_t)d->ntri);
  P->of_vertex = malloc(sizeof(int) * (size_t)d->nv);
  if (!P->of_tri || !P->of_vertex) return -1;
  if ((P->n = tb_cut_piece_of(d->nv, d->ntri, d->tri, P->of_tri)) < 0) return -1;
  for (int v = 0; v < d->nv; v++) P->of_vertex[v] = -1;
  for (int t = 0; t < d->ntri; t++)
    for (int k = 0; k < 3; k++) P->of_vertex[d->tri[3 * t + k]] = P->of_tri[t];
  return 0;
}

/* An old sphere in no piece: the piece most of its (old) vertices are on,
 * else its nearest vertex's. */
static int piece_by_vertices(const tb_metaball *m, const tb_metaball_skin_def *d, const pieces *P,
                             int s, int *votes) {
  memset(votes, 0, sizeof(int) * (size_t)P->n);
  int best = -1;
  for (int v = 0; v < m->nv; v++)
    for (int q = 0; q < 3; q++)
      if (m->bind[v][q] == s && P->of_vertex[v] >= 0) votes[P->of_vertex[v]]++;
  for (int p = 0; p < P->n; p++)
    if (votes[p] > 0 && (best < 0 || votes[p] > votes[best])) best = p;
  double dmin = INFINITY;
  for (int v = 0; v < d->nv && best < 0; v++)
    if (P->of_vertex[v] >= 0 && tb_dist(d->x[v], m->c[s]) < dmin) dmin = tb_dist(d->x[v], m->c[s]);
  for (int v = 0; v < d->nv && best < 0; v++)
    if (P->of_vertex[v] >= 0 && tb_dist(d->x[v], m->c[s]) == dmin) best = P->of_vertex[v];
  return best;
}

static int sphere_pieces(tb_metaball *m, const tb_metaball_skin_def *d, pieces *P,
                         tb_metaball_skin_report *rep) {
  int n = m->n, *loc = malloc(sizeof(int) * (size_t)n), *gone = malloc(sizeof(int) * (size_t)n);
  int *votes = malloc(sizeof(int) * (size_t)(P->n + 1)), ngone = 0;
  P->of_sphere = malloc(sizeof(int) * (size_t)n);
  if (!loc || !gone || !votes || !P->of_sphere ||
      tb_cut_locate(d->x, d->ntri, d->tri, P->of_tri, P->n, n, m->c, loc)) {
    free(loc), free(gone), free(votes);
    return -1;
  }
  for (int s = 0; s < n; s++) {
    P->of_sphere[s] = -1;
    if (!m->alive[s]) continue;
    if (loc[s] >= 0)
      P->of_sphere[s] = loc[s];
    else if (s >= d->first_new)
      gone[ngone++] = s;
    else
      P->of_sphere[s] = piece_by_vertices(m, d, P, s, votes);
  }
  tb_metaball_remove_set(m, ngone, gone);
  rep->outside = ngone;
  free(loc), free(gone), free(votes);
  return 0;
}

/* ---- 2. links: none between pieces, one group of spheres per piece ---- */

static int crosses(const tb_metaball *m, tb_vec3 a, tb_vec3 b) {
  return m->cut && m->cut->has_fold && tb_metaball_cut_crosses(m->cut, a, b);
}

typedef struct linkset {
  int n, cap, *pairs, *deg;
} linkset;

static int link_add(linkset *L, int a, int b) {
  if (2 * L->n + 2 > L->cap) {
    int *grown = realloc(L->pairs, sizeof(int) * (size_t)(L->cap *= 2));
    if (!grown) return -1;
    L->pairs = grown;
  }
  L->pairs[2 * L->n] = a, L->pairs[2 * L->n + 1] = b, L->n++, L->deg[a]++, L->deg[b]++;
  return 0;
}

static int linked(const linkset *L, int a, int b) {
  for (int e = 0; e < L->n; e++)
    if ((L->pairs[2 * e] == a && L->pairs[2 * e + 1] == b) ||
        (L->pairs[2 * e] == b && L->pairs[2 * e + 1] == a))
      return 1;
  return 0;
}

/* Sphere s, linked to fewer than MIN_LINKS others of its piece, linked to
 * the nearest ones (gap) not across the fold: a sphere with one or two links
 * swings about them (its unit constraint has no rotation to hold), and the
 * skin bound to it folds over its neighbours'. With three, a small group of
 * spheres held to the rest by a few links still turned about them as on a
 * hinge (the steak's cut-off thin end, falling freely: five of its 24
 * spheres 0.19 rad off the piece's rotation a second after the cut, its
 * skin folded at the crack's rim); with five, 0.002 rad. */
#define MIN_LINKS 5
static int anchor(tb_metaball *m, const pieces *P, linkset *L, int s,
                  tb_metaball_skin_report *rep) {
  while (L->deg[s] < MIN_LINKS) {
    int best = -1;
    double bg = INFINITY;
    for (int j = 0; j < m->n; j++) {
      if (j == s || !m->alive[j] || P->of_sphere[j] != P->of_sphere[s]) continue;
      double g = tb_dist(m->c[s], m->c[j]) - m->r[s] - m->r[j];
      if (!(g < bg) || linked(L, s, j) || crosses(m, m->c[s], m->c[j])) continue;
      bg = g, best = j;
    }
    if (best < 0) return 0;
    if (link_add(L, s, best)) return -1;
    rep->anchored++;
  }
  return 0;
}

/* The links kept and added, into m (tb_metaball_set_links). */
static int relink(tb_metaball *m, const pieces *P, tb_metaball_skin_report *rep) {
  int n = m->n;
  linkset L = {0, 2 * m->nl + 16, NULL, NULL};
  L.pairs = malloc(sizeof(int) * (size_t)L.cap), L.deg = calloc((size_t)n, sizeof(int));
  int *uf = malloc(sizeof(int) * (size_t)n), rc = 0;
  if (!L.pairs || !L.deg || !uf) rc = -1;
  for (int s = 0; s < n && rc == 0; s++) {
    uf[s] = s;
  }
  for (int e = 0; e < m->nl && rc == 0; e++) {
    int a = m->link[2 * e], b = m->link[2 * e + 1];
    if (P->of_sphere[a] != P->of_sphere[b]) {
      rep->links_cut++;
      continue;
    }
    rc = link_add(&L, a, b);
    int ra = uf_find(uf, a), rb = uf_find(uf, b);
    if (ra != rb) uf[ra > rb ? ra : rb] = ra < rb ? ra : rb;
  }
  for (int p = 0; p < P->n && rc == 0; p++)
    for (;;) { /* the nearest pair of two groups of piece p, until one group */
      int bi = -1, bj = -1, ai = -1, aj = -1;
      double bg = INFINITY, ag = INFINITY; /* best not across the fold; best of all */
      for (int i = 0; i < n; i++) {
        if (!m->alive[i] || P->of_sphere[i] != p) continue;
        for (int j = i + 1; j < n; j++) {
          if (!m->alive[j] || P->of_sphere[j] != p || uf_find(uf, i) == uf_find(uf, j)) continue;
          double g = tb_dist(m->c[i], m->c[j]) - m->r[i] - m->r[j];
          if (g < ag) ag = g, ai = i, aj = j;
          if (g < bg && !crosses(m, m->c[i], m->c[j])) bg = g, bi = i, bj = j;
        }
      }
      if (ai < 0) break;
      if (bi < 0) bi = ai, bj = aj;
      if ((rc = link_add(&L, bi, bj))) break;
      rep->joined++;
      int ra = uf_find(uf, bi), rb = uf_find(uf, bj);
      uf[ra > rb ? ra : rb] = ra < rb ? ra : rb;
    }
  int before = L.n;
  for (int s = 0; s < n && rc == 0; s++)
    if (m->alive[s]) rc = anchor(m, P, &L, s, rep);
  if (rc == 0 && (rep->links_cut || rep->joined || L.n != before))
    rc = tb_metaball_set_links(m, L.n, L.pairs);
  free(L.pairs), free(L.deg), free(uf);
  return rc;
}

/* Spheres for a piece with fewer than MIN_SPHERES (see the head): with two
 * a piece turns freely about their axis, with three about their plane's
 * hinges, and its skin crumples (a wedge between two cracks of the liver,
 * 539 vertices on two spheres: 487 crossing pairs a second later). Each
 * goes where the piece is thickest away from its spheres: among points a
 * little inside its triangles (inside the piece, tb_cut_locate), the one
 * farthest from the piece's sphere centres (from its vertices for the
 * first), reaching its nearest vertex. Its rest centre and rotation: the
 * rigid motion that best maps the piece's vertices now onto their rest
 * positions (when d->x0 gives them; else the current frame). */
#define MIN_SPHERES 4
#define SEED_CANDIDATES 70
static void piece_frame(const tb_metaball_skin_def *d, const pieces *P, int p, tb_vec3 *xm,
                        tb_vec3 *Xm, tb_mat3 *R) {
  int n = 0;
  tb_vec3 a = tb_v3(0, 0, 0), b = tb_v3(0, 0, 0);
  for (int v = 0; v < d->nv; v++)
    if (P->of_vertex[v] == p)
      a = tb_add(a, d->x[v]), b = tb_add(b, d->x0 ? d->x0[v] : d->x[v]), n++;
  *xm = tb_scale(a, 1.0 / (n ? n : 1)), *Xm = tb_scale(b, 1.0 / (n ? n : 1));
  *R = tb_m3_identity();
  if (!d->x0 || n < 3) return;
  tb_mat3 A = {{{0}}};
  for (int v = 0; v < d->nv; v++) {
    if (P->of_vertex[v] != p) continue;
    tb_vec3 q = tb_sub(d->x[v], *xm), Q = tb_sub(d->x0[v], *Xm);
    double qv[3] = {q.x, q.y, q.z}, Qv[3] = {Q.x, Q.y, Q.z};
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) A.m[r][c] += qv[r] * Qv[c];
  }
  *R = tb_m3_polar(A);
}

static int seed(tb_metaball *m, const tb_metaball_skin_def *d, pieces *P,
                tb_metaball_skin_report *rep) {
  int *count = calloc((size_t)P->n, sizeof(int)), *at = malloc(sizeof(int) * SEED_CANDIDATES);
  tb_vec3 *cand = malloc(sizeof(tb_vec3) * SEED_CANDIDATES);
  int rc = !count || !at || !cand ? -1 : 0;
  for (int s = 0; s < m->n && rc == 0; s++)
    if (m->alive[s] && P->of_sphere[s] >= 0) count[P->of_sphere[s]]++;
  for (int p = 0; p < P->n && rc == 0; p++) {
    if (count[p] >= MIN_SPHERES) continue;
    int nt = 0, nc = 0, nvp = 0;
    for (int t = 0; t < d->ntri; t++) nt += P->of_tri[t] == p;
    int stride = nt > SEED_CANDIDATES - 6 ? nt / (SEED_CANDIDATES - 6) : 1;
    for (int t = 0, k = 0; t < d->ntri && nc < SEED_CANDIDATES; t++) {
      if (P->of_tri[t] != p || k++ % stride) continue;
      tb_vec3 A = d->x[d->tri[3 * t]], B = d->x[d->tri[3 * t + 1]], C = d->x[d->tri[3 * t + 2]];
      tb_vec3 n = tb_cross(tb_sub(B, A), tb_sub(C, A));
      double area2 = tb_len(n);
      if (!(area2 > 0)) continue;
      tb_vec3 g = tb_scale(tb_add(tb_add(A, B), C), 1.0 / 3);
      cand[nc++] = tb_madd(g, -0.3 * sqrt(area2) / area2, n); /* 0.3 sqrt(2 area) inwards */
    }
    tb_vec3 vel = tb_v3(0, 0, 0), sum = tb_v3(0, 0, 0);
    for (int v = 0; v < d->nv; v++)
      if (P->of_vertex[v] == p) {
        sum = tb_add(sum, d->x[v]), nvp++;
        if (d->v) vel = tb_add(vel, d->v[v]);
      }
    if (nvp) vel = tb_scale(vel, 1.0 / nvp);
    if (nc && tb_cut_locate(d->x, d->ntri, d->tri, P->of_tri, P->n, nc, cand, at)) rc = -1;
    tb_vec3 xm, Xm;
    tb_mat3 R;
    piece_frame(d, P, p, &xm, &Xm, &R);
    while (rc == 0 && count[p] < MIN_SPHERES) {
      tb_vec3 best = nvp ? tb_scale(sum, 1.0 / nvp) : tb_v3(0, 0, 0);
      double far = -1;
      for (int k = 0; k < nc; k++) {
        if (at[k] != p) continue;
        double near = INFINITY;
        if (count[p] == 0)
          for (int v = 0; v < d->nv; v++)
            if (P->of_vertex[v] == p) near = fmin(near, tb_dist(cand[k], d->x[v]));
        for (int s = 0; s < m->n; s++)
          if (m->alive[s] && P->of_sphere[s] == p) near = fmin(near, tb_dist(cand[k], m->c[s]));
        if (near > far) far = near, best = cand[k];
      }
      if (count[p] > 0 && !(far > 0)) break; /* no place apart from its spheres */
      double r = INFINITY;
      for (int v = 0; v < d->nv; v++)
        if (P->of_vertex[v] == p) r = fmin(r, tb_dist(best, d->x[v]));
      if (!(r > 0) || !isfinite(r)) r = 1e-6;
      tb_vec3 c0 = tb_add(Xm, tb_m3_mulv(tb_m3_transpose(R), tb_sub(best, xm)));
      int s = m->n;
      int *grown = NULL;
      if (tb_metaball_add(m, 1, &c0, &best, &R, &r, &vel) ||
          !(grown = realloc(P->of_sphere, sizeof(int) * (size_t)m->n))) {
        rc = -1;
        break;
      }
      P->of_sphere = grown, P->of_sphere[s] = p, count[p]++, rep->seeded++;
    }
  }
  free(count), free(at), free(cand);
  return rc;
}

/* ---- 3. contact across the crack ---- */

/* Pair (a, b) across the fold: the fold's normal at their midpoint, turned
 * from a to b, in a's rest frame, and their separation along it now. */
static int add_contact(tb_metaball *m, int a, int b) {
  if (m->ncontact == m->contact_cap) {
    int cap = m->contact_cap ? 2 * m->contact_cap : 256;
    int *c = realloc(m->contact, sizeof(int) * 2 * (size_t)cap);
    if (c) m->contact = c;
    double *dd = realloc(m->cdist, sizeof(double) * (size_t)cap);
    if (dd) m->cdist = dd;
    tb_vec3 *nn = realloc(m->cnormal, sizeof(tb_vec3) * (size_t)cap);
    if (nn) m->cnormal = nn;
    if (!c || !dd || !nn) return -1;
    m->contact_cap = cap;
  }
  tb_fold_near nr;
  tb_vec3 d = tb_sub(m->c[b], m->c[a]);
  tb_fold_nearest(&m->cut->fold, tb_madd(m->c[a], 0.5, d), &nr);
  tb_vec3 n = m->cut->fold.piece[nr.piece].n;
  if (tb_dot(d, n) < 0) n = tb_scale(n, -1);
  int k = m->ncontact++;
  m->contact[2 * k] = a, m->contact[2 * k + 1] = b;
  m->cnormal[k] = tb_m3_mulv(tb_m3_transpose(m->rot[a]), n), m->cdist[k] = tb_dot(d, n);
  return 0;
}

static int contacts(tb_metaball *m, const pieces *P, tb_metaball_skin_report *rep) {
  int k = 0; /* the old pairs of spheres still alive */
  for (int q = 0; q < m->ncontact; q++) {
    int a = m->contact[2 * q], b = m->contact[2 * q + 1];
    if (!m->alive[a] || !m->alive[b]) continue;
    m->contact[2 * k] = a, m->contact[2 * k + 1] = b, m->cnormal[k] = m->cnormal[q];
    m->cdist[k++] = m->cdist[q];
  }
  m->ncontact = k;
  if (!m->cut || !m->cut->has_fold) return 0;
  double rmax = 0;
  for (int s = 0; s < m->n; s++)
    if (m->alive[s]) rmax = fmax(rmax, m->r[s]);
  tb_vec3 grow = tb_v3(2 * REACH * rmax, 2 * REACH * rmax, 2 * REACH * rmax);
  tb_vec3 lo = tb_sub(m->cut->flo, grow), hi = tb_add(m->cut->fhi, grow);
  int n = m->n, near = 0, *list = malloc(sizeof(int) * (size_t)n);
  if (!list) return -1;
  for (int s = 0; s < n; s++) {
    tb_vec3 c = m->c[s];
    if (m->alive[s] && c.x >= lo.x && c.y >= lo.y && c.z >= lo.z && c.x <= hi.x && c.y <= hi.y &&
        c.z <= hi.z)
      list[near++] = s;
  }
  for (int i = 0; i < near; i++)
    for (int j = i + 1; j < near; j++) {
      int a = list[i], b = list[j];
      double l = tb_dist(m->c[a], m->c[b]);
      if (!(l < REACH * (m->r[a] + m->r[b]))) continue;
      int apart = P && P->of_sphere && P->of_sphere[a] != P->of_sphere[b];
      if (!apart && !crosses(m, m->c[a], m->c[b])) continue;
      if (add_contact(m, a, b)) return free(list), -1;
      rep->contacts++;
    }
  free(list);
  return 0;
}

/* ---- 4. the skin ---- */

typedef struct binder {
  const signed char *sside; /* per sphere: its side of the fold (0: no fold) */
  const int *spiece;        /* per sphere: its piece (NULL: no pieces) */
  int fold;                 /* 1: the last cut's fold is there for the crossing test */
} binder;

/* 1 when vertex v (at x, on crack side `side`, in piece `piece`, off the
 * fold when `off`) may be bound to sphere s at this level: 0 everything,
 * 1 its piece only, 2 any alive sphere; a vertex no triangle uses has piece -1
 * and takes any. */
static int admits(const tb_metaball *m, const binder *b, int s, tb_vec3 x, int side, int piece,
                  int off, int level) {
  if (!m->alive[s]) return 0;
  if (level < 2 && b->spiece && piece >= 0 && b->spiece[s] != piece) return 0;
  if (level > 0) return 1;
  if (side) return b->sside[s] == side;
  return !(off && b->fold && crosses(m, x, m->c[s]));
}

/* Vertex v at x bound at the current configuration (see the head). */
static void bind_current(tb_metaball *m, const binder *b, int v, tb_vec3 x, int side, int piece,
                         int off, int keep_rest) {
  int best[3] = {-1, -1, -1};
  double kb[3] = {INFINITY, INFINITY, INFINITY};
  for (int pass = 0; pass < 4 && best[0] < 0; pass++)
    for (int s = 0; s < m->n; s++) {
      double k = tb_dist(x, m->c[s]) / m->r[s];
      if ((pass == 0 && (k < 1 || k > 2)) || !(k < kb[pass == 0 ? 2 : 0])) continue;
      if (!admits(m, b, s, x, side, piece, off, pass == 0 ? 0 : pass - 1)) continue;
      int at = pass == 0 ? 2 : 0;
      while (at > 0 && k < kb[at - 1]) kb[at] = kb[at - 1], best[at] = best[at - 1], at--;
      kb[at] = k, best[at] = s;
    }
  double sum = 0, sg = m->set.sigma;
  for (int q = 0; q < 3; q++) {
    m->bind[v][q] = best[q];
    m->bw[v][q] = best[q] < 0 ? 0 : exp(-kb[q] * kb[q] / (2 * sg * sg));
    sum += m->bw[v][q];
  }
  for (int q = 0; q < 3; q++) m->bw[v][q] = sum > 0 ? m->bw[v][q] / sum : (q == 0);
  if (keep_rest) {
    tb_metaball_bind_offsets(m, v);
    return;
  }
  tb_mat3 M = {{{0}}};
  tb_vec3 rhs = x;
  for (int q = 0; q < 3; q++) {
    int s = m->bind[v][q];
    if (s < 0) continue;
    double wq = m->bw[v][q];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) M.m[i][j] += wq * m->rot[s].m[i][j];
    rhs = tb_madd(rhs, -wq, tb_sub(m->c[s], tb_m3_mulv(m->rot[s], m->c0[s])));
  }
  double det = tb_m3_det(M);
  if (!(fabs(det) > 1e-6)) { /* rotations too far apart to average: the nearest alone */
    int s = m->bind[v][0];
    m->bind[v][1] = m->bind[v][2] = -1, m->bw[v][0] = 1, m->bw[v][1] = m->bw[v][2] = 0;
    M = m->rot[s], det = tb_m3_det(M);
    rhs = tb_sub(x, tb_sub(m->c[s], tb_m3_mulv(m->rot[s], m->c0[s])));
  }
  m->x0[v] = tb_scale(tb_m3_mulv(tb_m3_transpose(tb_m3_cofactor(M)), rhs), 1 / det);
  m->x[v] = x;
  tb_metaball_bind_offsets(m, v);
}

/* 1 when vertex v's binding breaks a rule of the head's step 4. */
static int bound_wrong(const tb_metaball *m, const binder *b, int v, tb_vec3 x, int side, int piece,
                       int off) {
  for (int q = 0; q < 3; q++) {
    int s = m->bind[v][q];
    if (s >= 0 && !admits(m, b, s, x, side, piece, off, 0)) return 1;
  }
  return 0;
}

static int grow_skin(tb_metaball *m, int nv) {
  size_t V = (size_t)(nv > 0 ? nv : 1);
  tb_vec3 *x0 = realloc(m->x0, sizeof(tb_vec3) * V);
  if (x0) m->x0 = x0;
  tb_vec3 *xs = realloc(m->x, sizeof(tb_vec3) * V);
  if (xs) m->x = xs;
  int(*bind)[3] = realloc(m->bind, sizeof *m->bind * V);
  if (bind) m->bind = bind;
  double(*bw)[3] = realloc(m->bw, sizeof *m->bw * V);
  if (bw) m->bw = bw;
  tb_vec3(*xo)[3] = realloc(m->xo, sizeof *m->xo * V);
  if (xo) m->xo = xo;
  return x0 && xs && bind && bw && xo ? 0 : -1;
}

static int rebind_skin(tb_metaball *m, const tb_metaball_skin_def *d, const pieces *P,
                       tb_metaball_skin_report *rep) {
  const tb_fold *f = m->cut && m->cut->has_fold ? &m->cut->fold : NULL;
  signed char *sside = malloc((size_t)m->n);
  if (!sside) return -1;
  for (int s = 0; s < m->n; s++)
    sside[s] = f && m->alive[s] ? (signed char)tb_fold_side(f, m->c[s]) : 0;
  binder b = {sside, P ? P->of_sphere : NULL, f != NULL};
  double rmax = 0, scale = 0;
  for (int s = 0; s < m->n; s++)
    if (m->alive[s]) rmax = fmax(rmax, m->r[s]), scale = fmax(scale, tb_len(m->c[s]));
  tb_vec3 grow = tb_v3(2 * rmax, 2 * rmax, 2 * rmax);
  tb_vec3 lo = f ? tb_sub(m->cut->flo, grow) : tb_v3(0, 0, 0);
  tb_vec3 hi = f ? tb_add(m->cut->fhi, grow) : tb_v3(0, 0, 0);
  int old = m->nv;
  m->nv = d->nv;
  if (!d->x0) m->blend_left = 0; /* a blend is for the vertices it was made for */
  for (int v = 0; v < d->nv; v++) {
    tb_vec3 x = d->x[v];
    int side = d->side ? d->side[v] : 0, piece = P ? P->of_vertex[v] : -1, off = 0;
    if (f && x.x >= lo.x && x.y >= lo.y && x.z >= lo.z && x.x <= hi.x && x.y <= hi.y &&
        x.z <= hi.z) {
      tb_fold_near nr;
      tb_fold_nearest(f, x, &nr);
      off = nr.dist > 1e-12 * (scale + rmax);
    }
    int again =
        v >= old || (d->rebind && d->rebind[v]) || bound_wrong(m, &b, v, x, side, piece, off);
    if (!again) continue;
    if (d->x0) m->x0[v] = d->x0[v];
    bind_current(m, &b, v, x, side, piece, off, d->x0 != NULL);
    rep->rebound++;
  }
  free(sside);
  if (!d->x0) return 0;
  /* the skin at the given rest positions, blended in from the positions */
  tb_vec3 *blend = realloc(m->blend, sizeof(tb_vec3) * (size_t)(d->nv > 0 ? d->nv : 1));
  if (!blend) return -1;
  m->blend = blend, m->blend_left = 0;
  tb_metaball_reskin(m);
  for (int v = 0; v < d->nv; v++) blend[v] = tb_sub(d->x[v], m->x[v]), m->x[v] = d->x[v];
  m->blend_left = TB_METABALL_BLEND;
  return 0;
}

int tb_metaball_set_skin(tb_metaball *m, const tb_metaball_skin_def *d,
                         tb_metaball_skin_report *rep, tb_error *err) {
  tb_metaball_skin_report r;
  memset(&r, 0, sizeof r);
  if (!d || d->nv < m->nv || !d->x || d->ntri < 0 || (d->ntri > 0 && !d->tri))
    return tb_error_set(err, "metaball skin", 0, "%d vertices, fewer than %d, or no triangles",
                        d ? d->nv : 0, m->nv);
  int alive = 0;
  for (int s = 0; s < m->n; s++) alive += m->alive[s];
  if (!alive && d->ntri == 0) return tb_error_set(err, "metaball skin", 0, "no sphere left");
  const tb_fold *f = m->cut && m->cut->has_fold ? &m->cut->fold : NULL;
  for (int v = 0; v < d->nv; v++) {
    if (!tb_isfinite3(d->x[v]))
      return tb_error_set(err, "metaball skin", 0, "vertex %d not finite", v);
    if (d->side && d->side[v] && (!f || (d->side[v] != 1 && d->side[v] != -1)))
      return tb_error_set(err, "metaball skin", 0, "vertex %d: side %d without a cut", v,
                          d->side[v]);
  }
  for (int i = 0; i < 3 * d->ntri; i++)
    if (d->tri[i] < 0 || d->tri[i] >= d->nv)
      return tb_error_set(err, "metaball skin", 0, "triangle %d: vertex %d out of range", i / 3,
                          d->tri[i]);
  pieces P = {0, NULL, NULL, NULL};
  int rc = grow_skin(m, d->nv);
  if (rc == 0 && d->ntri > 0) {
    rc = surface_pieces(d, &P);
    if (rc == 0) rc = sphere_pieces(m, d, &P, &r);
    if (rc == 0) rc = seed(m, d, &P, &r);
    if (rc == 0) rc = relink(m, &P, &r);
    if (rc == 0) {
      int *grown = realloc(m->piece, sizeof(int) * (size_t)m->n);
      if (grown) memcpy(m->piece = grown, P.of_sphere, sizeof(int) * (size_t)m->n);
      rc = grown ? 0 : -1;
    }
    r.pieces = P.n;
  }
  if (rc == 0) rc = contacts(m, d->ntri > 0 ? &P : NULL, &r);
  if (rc == 0) rc = rebind_skin(m, d, d->ntri > 0 ? &P : NULL, &r);
  if (rc == 0)
    rc = tb_metaball_zone_add(m, d, m->cut && m->cut->has_fold ? &m->cut->fold : NULL,
                              d->ntri > 0 ? P.of_vertex : NULL, P.n, &r.zone_vertices,
                              &r.zone_triangles);
  pieces_free(&P);
  if (rc) return tb_error_set(err, "metaball skin", 0, "out of memory (%d vertices)", d->nv);
  if (rep) *rep = r;
  return 0;
}
