/* The crack (the metaball patent's 裂隙生成, fig. 6; step 3 of
 * cutting/cut_surface.c): per piece of the folded plane, the part inside the
 * organ triangulated in the piece's (s, t) rectangle by CGAL's constrained
 * Delaunay triangulation, the cut's vertices and the piece's sides as
 * constraints, Steiner points away from them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cut_priv.h"

/* ---- step 3: the crack ---- */

static double seg_dist(tb_vec3 p, tb_vec3 a, tb_vec3 b) {
  tb_vec3 ab = tb_sub(b, a);
  double l = tb_dot(ab, ab), u = l > 0 ? tb_dot(tb_sub(p, a), ab) / l : 0.0;
  u = u < 0 ? 0 : (u > 1 ? 1 : u);
  return tb_dist(p, tb_madd(a, u, ab));
}

typedef struct cpt { /* a crack point of one piece */
  int id;            /* vertex, or -1 for a Steiner point (created when used) */
  double s, t;       /* in the piece */
  int side;          /* SIDE_* it lies on, or -1 */
  int crease;        /* a crease point: its index into c->crease_id, else -1 */
} cpt;

static tb_vec3 piece_point(const tb_fold *f, int k, double s, double t) {
  return tb_madd(tb_madd(f->p[k], s, f->piece[k].e), t, f->depth);
}

/* Which side of piece k a cut vertex lies on (-1: inside the piece), with its (s, t) there. */
static int place_on_piece(const tb_fold *f, const vrec *r, int k, double *s, double *t) {
  *t = r->t;
  if (r->piece == k) {
    *s = r->s;
    if ((r->loc & TB_FOLD_CREASE) || (r->loc & TB_FOLD_END)) return SIDE_R;
    if (r->loc & TB_FOLD_START) return SIDE_L;
  } else if (r->piece == k - 1 && (r->loc & TB_FOLD_CREASE)) {
    *s = 0.0;
    return SIDE_L;
  } else {
    return -2; /* not on this piece */
  }
  (void)f;
  if (r->loc & TB_FOLD_PATH) return SIDE_B;
  if (r->loc & TB_FOLD_DEPTH) return SIDE_T;
  return -1;
}

static int corner_vertex(cutter *c, int which) { /* which = 2 i (+1 for q_i) */
  if (c->corner_id[which] < 0)
    c->corner_id[which] = cut_new_vertex(c, which & 1 ? c->f->q[which / 2] : c->f->p[which / 2]);
  return c->corner_id[which];
}

/* A crease inside the organ would be one edge from p_i to q_i (or from where it meets the
 * surface) in all four crack sheets (+ and - of both pieces): a crease meeting the surface
 * nowhere would end, on the path and the depth edge inside, in one vertex joining + and -
 * (not a manifold), and any long crease gives triangles the skin cannot bend. So a crease
 * gets points t = j / m about the spacing apart, away from the cut points on it, shared by
 * both pieces (c->crease_id), which un-welding gives a + and a - copy each; those outside
 * the organ lie in regions dropped as outside and are never made. */
static void crease_points(cutter *c, int k, int side, cpt *pt, int *np) {
  const tb_fold *f = c->f;
  int i = side == SIDE_R ? k + 1 : k; /* the crease at path point i */
  int m = c->spacing > 0 ? (int)ceil(tb_len(f->depth) / c->spacing) : 2, n0 = *np;
  m = m < 2 ? 2 : (m > CREASE_MAX ? CREASE_MAX : m);
  for (int j = 1; j < m; j++) {
    int ok = 1;
    for (int q = 4; q < n0 && ok; q++)
      ok = !(pt[q].side == side && fabs(pt[q].t - (double)j / m) * m < 0.5);
    if (!ok) continue;
    pt[*np].id = -1, pt[*np].s = side == SIDE_R ? 1.0 : 0.0, pt[*np].t = (double)j / m;
    pt[*np].side = side, pt[*np].crease = CREASE_MAX * i + j, (*np)++;
  }
}

/* The path and depth edges of piece k (t = 0, t = 1) where they run inside the organ (the
 * depth edge of a blade that stops inside is the crack's floor, which both sides share)
 * would be single edges between the corners and the cut points on them: triangles as long
 * as the blade, which the skin cannot bend, so they cross the surface when the organ bends.
 * So each gets points m = ns per unit of s (about the spacing apart) away from the cut points
 * on it; those in regions outside the organ are never made. */
static void edge_points(const tb_fold *f, int k, int side, int m, cpt *pt, int *np) {
  double el = tb_len(f->piece[k].e);
  int n0 = *np;
  for (int j = 1; j < m; j++) {
    double s = (double)j / m;
    int ok = 1;
    for (int i = 4; i < n0 && ok; i++)
      ok = !(pt[i].side == side && fabs(pt[i].s - s) * el * m < 0.5 * el);
    if (ok)
      pt[*np].id = -1, pt[*np].s = s, pt[*np].t = side == SIDE_T ? 1.0 : 0.0, pt[*np].side = side,
      pt[*np].crease = -1, (*np)++;
  }
}

static int crease_vertex(cutter *c, const cpt *p) {
  int *id = &c->crease_id[p->crease];
  if (*id < 0) *id = cut_new_vertex(c, tb_madd(c->f->p[p->crease / CREASE_MAX], p->t, c->f->depth));
  return *id;
}

/* The grid (i / ns, j / nt) of piece k: points inside the organ's box, farther than minsep
 * from every constraint (only the grid points in each constraint's reach are measured:
 * lines of constant s lie |e| sin(angle(e, D)) apart per unit of s) and from the points
 * after nfixed (the caller's). */
static int grid_points(cutter *c, int k, int ns, int nt, double minsep, cpt *pt, int *np,
                       int nfixed, const int *sg, int nseg) {
  const tb_fold *f = c->f;
  double el = tb_len(f->piece[k].e), dl = tb_len(f->depth);
  double sine = tb_len(tb_cross(f->piece[k].e, f->depth)) / (el * dl);
  int ms = (int)ceil(minsep / (el * sine) * ns) + 1, mt = (int)ceil(minsep / (dl * sine) * nt) + 1;
  int nextra = *np;
  unsigned char *bad = calloc((size_t)(ns + 1) * (nt + 1), 1);
  if (!bad) return NOMEM;
  for (int j = 0; j < nseg; j++) {
    const cpt *a = &pt[sg[2 * j]], *b = &pt[sg[2 * j + 1]];
    tb_vec3 A = piece_point(f, k, a->s, a->t), B = piece_point(f, k, b->s, b->t);
    int i0 = (int)floor(fmin(a->s, b->s) * ns) - ms, i1 = (int)ceil(fmax(a->s, b->s) * ns) + ms;
    int j0 = (int)floor(fmin(a->t, b->t) * nt) - mt, j1 = (int)ceil(fmax(a->t, b->t) * nt) + mt;
    i0 = i0 < 1 ? 1 : i0, j0 = j0 < 1 ? 1 : j0, i1 = i1 > ns - 1 ? ns - 1 : i1;
    j1 = j1 > nt - 1 ? nt - 1 : j1;
    for (int jj = j0; jj <= j1; jj++)
      for (int ii = i0; ii <= i1; ii++)
        if (!bad[ii + (ns + 1) * jj] &&
            seg_dist(piece_point(f, k, (double)ii / ns, (double)jj / nt), A, B) < minsep)
          bad[ii + (ns + 1) * jj] = 1;
  }
  tb_vec3 lo = c->x[0], hi = c->x[0];
  for (int v = 1; v < c->nv; v++) lo = tb_vmin(lo, c->x[v]), hi = tb_vmax(hi, c->x[v]);
  for (int jj = 1; jj < nt; jj++)
    for (int ii = 1; ii < ns; ii++) {
      if (bad[ii + (ns + 1) * jj]) continue;
      double s = (double)ii / ns, t = (double)jj / nt;
      tb_vec3 X = piece_point(f, k, s, t);
      int ok =
          X.x >= lo.x && X.y >= lo.y && X.z >= lo.z && X.x <= hi.x && X.y <= hi.y && X.z <= hi.z;
      for (int m = nfixed; m < nextra && ok; m++)
        ok = tb_dist(X, piece_point(f, k, pt[m].s, pt[m].t)) >= minsep;
      if (ok)
        pt[*np].id = -1, pt[*np].s = s, pt[*np].t = t, pt[*np].side = -1, pt[*np].crease = -1,
        (*np)++;
    }
  free(bad);
  return OK;
}

int cut_crack_piece(cutter *c, int k, int **crack, int *ncrack, int *capcrack) {
  const tb_fold *f = c->f;
  double el = tb_len(f->piece[k].e), dl = tb_len(f->depth);
  int ns = 0, nt = 0;
  if (c->spacing > 0) {
    ns = (int)ceil(el / c->spacing), nt = (int)ceil(dl / c->spacing);
    if ((double)ns * nt > 1e6) ns = nt = 0; /* a blade far larger than the organ's grain */
  }
  int cap = c->nvr + 4 + 2 * CREASE_MAX + 2 * ns + (ns + 1) * (nt + 1) + c->nextra;
  cpt *pt = malloc((size_t)cap * sizeof *pt);
  int *sg = NULL, np = 0, nseg = 0, capseg = 0, rc = NOMEM;
  double *xy = NULL;
  int *keep = NULL;
  tb_cdt2 cdt = {0, NULL, NULL, 0};
  if (!pt) goto done;
  /* Corners p_k, p_{k+1}, q_{k+1}, q_k (as points 0..3); a cut vertex on a corner takes its place.
   */
  static const double cs[4] = {0, 1, 1, 0}, ct[4] = {0, 0, 1, 1};
  const int cw[4] = {2 * k, 2 * (k + 1), 2 * (k + 1) + 1, 2 * k + 1};
  for (int i = 0; i < 4; i++)
    pt[np].id = c->corner_id[cw[i]], pt[np].s = cs[i], pt[np].t = ct[i], pt[np].side = -1,
    pt[np].crease = -1, np++;
  for (int v = 0; v < c->nvr; v++) {
    const vrec *r = &c->v[v];
    if (!r->cut || !r->active) continue;
    double s, t;
    int side = place_on_piece(f, r, k, &s, &t);
    if (side == -2) continue;
    int at = -1;
    for (int i = 0; i < 4; i++)
      if (s == cs[i] && t == ct[i]) at = i;
    if (at >= 0) {
      pt[at].id = v, c->corner_id[cw[at]] = v;
      continue;
    }
    pt[np].id = v, pt[np].s = s, pt[np].t = t, pt[np].side = side, pt[np].crease = -1, np++;
  }
  if (k > 0) crease_points(c, k, SIDE_L, pt, &np);
  if (k + 1 < f->npieces) crease_points(c, k, SIDE_R, pt, &np);
  edge_points(f, k, SIDE_B, ns, pt, &np);
  edge_points(f, k, SIDE_T, ns, pt, &np);
  for (int i = 0; i < 4; i++)
    if (pt[i].id < 0) pt[i].id = -10 - cw[i]; /* created only when a kept triangle uses it */
  int nfixed = np;
  /* Constraints: the four sides split at their points, then the cut segments of the piece. */
  for (int side = 0; side < 4; side++) {
    static const int from[4] = {0, 1, 0, 3}, to[4] = {3, 2, 1, 2};
    int m = 0;
    int *chain = malloc((size_t)(np + 2) * sizeof *chain);
    if (!chain) goto done;
    chain[m++] = from[side];
    for (int i = 4; i < np; i++) {
      if (pt[i].side != side) continue;
      double key = side <= SIDE_R ? pt[i].t : pt[i].s;
      int j = m;
      while (j > 1 && (side <= SIDE_R ? pt[chain[j - 1]].t : pt[chain[j - 1]].s) > key)
        chain[j] = chain[j - 1], j--;
      chain[j] = i, m++;
    }
    chain[m++] = to[side];
    if (GROW(sg, 2 * (nseg + m), capseg)) {
      free(chain);
      goto done;
    }
    for (int j = 0; j + 1 < m; j++)
      sg[2 * nseg] = chain[j], sg[2 * nseg + 1] = chain[j + 1], nseg++;
    free(chain);
  }
  for (int i = 0; i < c->nsg; i++) {
    if (c->sg[i].piece != k) continue;
    int a = -1, b = -1;
    for (int j = 0; j < nfixed; j++) {
      if (pt[j].id == c->sg[i].a) a = j;
      if (pt[j].id == c->sg[i].b) b = j;
    }
    if (a < 0 || b < 0) {
      rc = RETRY_BECAUSE(c, "a cut segment's end is not among its crack piece's points");
      goto done;
    }
    if (GROW(sg, 2 * (nseg + 1), capseg)) goto done;
    sg[2 * nseg] = a, sg[2 * nseg + 1] = b, nseg++;
  }
  /* Steiner points: the caller's, then the grid; away from the constraints and each other. */
  double minsep = 0.5 * (c->spacing > 0 ? c->spacing : c->h);
  for (int i = 0; i < c->nextra; i++) {
    tb_fold_near nr;
    tb_fold_nearest(f, c->extra[i], &nr);
    if (nr.piece != k || !(nr.s > 0 && nr.s < 1 && nr.t > 0 && nr.t < 1)) continue;
    tb_vec3 X = piece_point(f, k, nr.s, nr.t);
    int ok = 1;
    for (int j = 0; j < nseg && ok; j++) {
      const cpt *a = &pt[sg[2 * j]], *b = &pt[sg[2 * j + 1]];
      ok = seg_dist(X, piece_point(f, k, a->s, a->t), piece_point(f, k, b->s, b->t)) >= minsep;
    }
    for (int j = nfixed; j < np && ok; j++)
      ok = tb_dist(X, piece_point(f, k, pt[j].s, pt[j].t)) >= minsep;
    if (ok)
      pt[np].id = -1, pt[np].s = nr.s, pt[np].t = nr.t, pt[np].side = -1, pt[np].crease = -1, np++;
  }
  if (ns > 1 && nt > 1 && (rc = grid_points(c, k, ns, nt, minsep, pt, &np, nfixed, sg, nseg)) != OK)
    goto done;
  rc = NOMEM;
  xy = malloc((size_t)2 * np * sizeof *xy);
  if (!xy) goto done;
  for (int i = 0; i < np; i++) xy[2 * i] = pt[i].s * el, xy[2 * i + 1] = pt[i].t * dl;
  if (tb_cdt2_build(xy, np, sg, nseg, &cdt)) {
    rc = RETRY_BECAUSE(c, "the crack's constraints cross or its points coincide");
    goto done;
  }
  /* Each region: inside the organ or not, from its largest triangles' centroids. */
  keep = malloc((size_t)(cdt.nregion + 1) * sizeof *keep);
  if (!keep) goto done;
  rc = OK;
  for (int g = 0; g < cdt.nregion && rc == OK; g++) {
    keep[g] = -1;
    double tried = INFINITY;
    for (int attempt = 0; attempt < 4 && keep[g] < 0; attempt++) {
      int best = -1;
      double ba = -1;
      for (int i = 0; i < cdt.ntri; i++) {
        if (cdt.region[i] != g) continue;
        const double *A = xy + 2 * cdt.tri[3 * i], *B = xy + 2 * cdt.tri[3 * i + 1],
                     *C = xy + 2 * cdt.tri[3 * i + 2];
        double area = (B[0] - A[0]) * (C[1] - A[1]) - (B[1] - A[1]) * (C[0] - A[0]);
        if (area > ba && area < tried) ba = area, best = i;
      }
      if (best < 0) break;
      tried = ba;
      double s = 0, t = 0;
      for (int m = 0; m < 3; m++)
        s += pt[cdt.tri[3 * best + m]].s / 3, t += pt[cdt.tri[3 * best + m]].t / 3;
      keep[g] = cut_inside_organ(c->x, c->ntri, c->tri, piece_point(f, k, s, t));
    }
    if (keep[g] < 0)
      rc = RETRY_BECAUSE(c, "inside or outside the organ undecided for a crack region");
  }
  for (int i = 0; i < cdt.ntri && rc == OK; i++) {
    if (!keep[cdt.region[i]]) continue;
    int v[3];
    for (int m = 0; m < 3; m++) {
      cpt *p = &pt[cdt.tri[3 * i + m]];
      if (p->id <= -10) p->id = corner_vertex(c, -10 - p->id);
      if (p->id == -1)
        p->id =
            p->crease >= 0 ? crease_vertex(c, p) : cut_new_vertex(c, piece_point(f, k, p->s, p->t));
      if (p->id < 0) rc = NOMEM;
      v[m] = p->id;
    }
    if (rc == OK && cut_grow((void **)crack, capcrack, 3 * (*ncrack + 1), sizeof **crack))
      rc = NOMEM;
    if (rc != OK) break;
    memcpy(*crack + 3 * *ncrack, v, sizeof v);
    (*ncrack)++;
  }
done:
  tb_cdt2_free(&cdt);
  free(pt), free(sg), free(xy), free(keep);
  return rc;
}
