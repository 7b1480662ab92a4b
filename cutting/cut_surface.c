/* Cutting a closed surface with the folded plane: the metaball patent's step
 * 3 (5), surface splitting (表面分裂: "the triangles are split by the cases of
 * fig. 5 ... the polygons on both sides of the cut are each divided into
 * triangles") and crack generation (裂隙生成: "the points near the folded
 * plane, projected onto it, and the boundary points of the splitting are
 * triangulated with the boundary respected: all points triangulated, the
 * triangles outside the boundary removed", fig. 6). See tb_cut_surface.h for
 * what comes out; here is how.
 *
 * 1. Every triangle near the fold gets its cut polylines (tb_fold_triangle).
 *    A point becomes a vertex: an old vertex when it is one or lies within
 *    the snap distance of one; a point on an edge is keyed by (edge, piece,
 *    crease) so both triangles of the edge name the same new vertex (both
 *    must report it, or the attempt is inconsistent); an interior point is
 *    its triangle's own. Polylines give cut segments; points on no segment
 *    (a fold touching the surface) are dropped.
 * 2. A triangle with a cut vertex other than its corners is re-triangulated
 *    by CGAL's constrained Delaunay triangulation in its barycentric plane
 *    (corners (0,0), (1,0), (0,1); points on the long side placed exactly on
 *    it), the boundary pieces and the cut segments as constraints.
 * 3. The crack, per piece, in the rectangle (s |e_k|, t |D|): the corners,
 *    the cut vertices on the piece and on its sides, the sides split at them
 *    and the cut segments as constraints, Steiner points (a grid, extra
 *    points) away from the constraints. Each region between constraints is
 *    kept when a point of it is inside the organ (exact ray parity); a crease
 *    meeting the surface nowhere gets points of its own, shared by both pieces
 *    (see cut_crack.c), so + and - part along it when it lies inside. Its
 *    triangles go out twice: facing -n_k for the + side, +n_k for the - side.
 * 4. Un-welding. Around each vertex of the crack, the incident triangles are
 *    joined across their edges: an edge in two triangles joins them; a cut
 *    edge has four (two surface, one + crack, one - crack): the + crack joins
 *    the surface triangle that runs the edge the other way, the - crack the
 *    other one; an edge inside the crack has four crack triangles: + with +,
 *    - with -. Each set of joined triangles (a fan) gets its own copy of the
 *    vertex. So the + and - sides separate along the cut and inside the crack
 *    and stay joined at the tips and along the fold's edges inside the organ.
 * 5. The result is checked to be a closed, oriented 2-manifold. An attempt
 *    that is inconsistent (an edge point one triangle sees and its neighbour
 *    does not, crossing constraints, a piece in a triangle's plane) is
 *    repeated with the fold shifted by 1e-5, 2e-5, 4e-5 mean edge lengths
 *    along a fixed direction; then the cut fails with an error. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cut_priv.h"
#include "collision/tb_predicates.h"

tb_cut_def tb_cut_default_def(void) {
  tb_cut_def d;
  memset(&d, 0, sizeof d);
  d.snap = 1e-6;
  return d;
}

/* ---- step 1: cut points and segments ---- */

static void mark_cut(vrec *r, const tb_fold_tpoint *p) {
  if (r->cut) return;
  r->cut = 1, r->piece = p->piece, r->s = p->s, r->t = p->t, r->loc = p->fold_loc;
}

/* The triangle's cut points, with their place in its barycentric plane;
 * the long side (edge 0) exactly on u + v = 1. */
static int collect_triangle(cutter *c, int t, const tb_fold_cut *cut) {
  const int *T = c->tri + 3 * t;
  for (int i = 0; i < cut->n; i++) {
    const tb_fold_tpoint *p = &cut->pt[i];
    if (GROW(c->rp, c->nrp + 1, c->caprp)) return NOMEM;
    rawpt *r = &c->rp[c->nrp++];
    memset(r, 0, sizeof *r);
    r->tri = t, r->poly = p->polyline, r->p = *p, r->id = -1, r->edge = -1, r->where = -1;
    int corner = p->tri_loc == TB_FOLD_TRI_VERTEX ? p->tri_index : -1;
    for (int k = 0; k < 3 && corner < 0; k++)
      if (tb_dist(p->x, c->x[T[k]]) <= c->snapd) corner = k;
    if (corner >= 0) {
      r->where = 3 + corner, r->id = T[corner];
      r->u = corner == 1, r->v = corner == 2;
      continue;
    }
    if (p->tri_loc == TB_FOLD_TRI_INTERIOR) {
      if (p->bary[0] <= 0 || p->bary[1] <= 0 || p->bary[2] <= 0)
        return RETRY_BECAUSE(c, "a cut point inside a triangle lies on its boundary");
      r->u = p->bary[1], r->v = p->bary[2];
      continue;
    }
    int e = p->tri_index, he = 3 * t + (e + 1) % 3;
    r->where = e, r->edge = he < c->pair[he] ? he : c->pair[he];
    if (e == 1)
      r->u = 0, r->v = p->bary[2];
    else if (e == 2)
      r->u = p->bary[1], r->v = 0;
    else if (p->bary[1] >= 0.5)
      r->u = p->bary[1], r->v = 1.0 - p->bary[1];
    else
      r->v = p->bary[2], r->u = 1.0 - p->bary[2];
  }
  return OK;
}

/* Edge points are the same vertex when their (edge, piece, crease) agree. */
typedef struct ekey {
  int edge, piece, crease, tri, i;
} ekey;

static int ekey_same(const ekey *a, const ekey *b) {
  return a->edge == b->edge && a->piece == b->piece && a->crease == b->crease;
}
static int cmp_ekey(const void *pa, const void *pb) {
  const ekey *a = pa, *b = pb;
  const int ka[5] = {a->edge, a->piece, a->crease, a->tri, a->i};
  const int kb[5] = {b->edge, b->piece, b->crease, b->tri, b->i};
  for (int m = 0; m < 5; m++)
    if (ka[m] != kb[m]) return ka[m] < kb[m] ? -1 : 1;
  return 0;
}

/* Names every raw point's vertex; an edge point's key must be seen by
 * exactly the two triangles of its edge (unpaired[i] says it is not; that
 * matters when the point ends on a cut segment). */
static int name_points(cutter *c, int **unpaired_out) {
  int n = 0;
  ekey *key = malloc((size_t)(c->nrp + 1) * sizeof *key);
  int *unpaired = calloc((size_t)c->nrp + 1, sizeof *unpaired);
  if (!key || !unpaired) {
    free(key), free(unpaired);
    return NOMEM;
  }
  for (int i = 0; i < c->nrp; i++) {
    const rawpt *r = &c->rp[i];
    if (r->edge < 0) continue;
    key[n].edge = r->edge, key[n].piece = r->p.piece, key[n].tri = r->tri, key[n].i = i;
    key[n].crease = (r->p.fold_loc & TB_FOLD_CREASE) != 0;
    n++;
  }
  qsort(key, (size_t)n, sizeof *key, cmp_ekey);
  for (int i = 0; i < n;) {
    int j = i + 1, tris = 1;
    for (; j < n && ekey_same(&key[i], &key[j]); j++) tris += key[j].tri != key[j - 1].tri;
    int id = cut_new_vertex(c, c->rp[key[i].i].p.x);
    if (id < 0) {
      free(key), free(unpaired);
      return NOMEM;
    }
    for (int m = i; m < j; m++) c->rp[key[m].i].id = id, unpaired[key[m].i] = tris != 2;
    i = j;
  }
  free(key);
  for (int i = 0; i < c->nrp; i++) {
    rawpt *r = &c->rp[i];
    /* interior points of one triangle within the snap distance are one vertex (a crease
     * joint comes once from each piece, rounded differently) */
    for (int j = i - 1; r->id < 0 && r->where < 0 && j >= 0 && c->rp[j].tri == r->tri; j--)
      if (c->rp[j].where < 0 && tb_dist(c->rp[j].p.x, r->p.x) <= c->snapd) r->id = c->rp[j].id;
    if (r->id < 0 && (r->id = cut_new_vertex(c, r->p.x)) < 0) {
      free(unpaired);
      return NOMEM;
    }
    mark_cut(&c->v[r->id], &r->p);
  }
  *unpaired_out = unpaired;
  return OK;
}

/* Cut segments: consecutive points of a polyline with different vertices. */
static int make_segments(cutter *c) {
  for (int i = 0; i + 1 < c->nrp; i++) {
    const rawpt *a = &c->rp[i], *b = &c->rp[i + 1];
    if (a->tri != b->tri || a->poly != b->poly || a->id == b->id) continue;
    if (GROW(c->sg, c->nsg + 1, c->capsg)) return NOMEM;
    seg *s = &c->sg[c->nsg++];
    s->a = a->id, s->b = b->id, s->tri = a->tri;
    s->piece = a->p.piece > b->p.piece ? a->p.piece : b->p.piece;
    c->v[a->id].active = c->v[b->id].active = 1;
  }
  return OK;
}

/* ---- step 2: splitting a triangle ---- */

static int split_triangle(cutter *c, int t, int r0, int r1) {
  const int *T = c->tri + 3 * t;
  int cap = r1 - r0 + 3, np = 3, nseg = 0;
  int *id = malloc((size_t)cap * sizeof *id), *sg = malloc((size_t)4 * cap * sizeof *sg);
  double *xy = malloc((size_t)2 * cap * sizeof *xy), *par = malloc((size_t)cap * sizeof *par);
  int *edge_of = malloc((size_t)cap * sizeof *edge_of);
  int rc = NOMEM;
  if (!id || !sg || !xy || !par || !edge_of) goto done;
  for (int k = 0; k < 3; k++) id[k] = T[k], edge_of[k] = -1;
  xy[0] = 0, xy[1] = 0, xy[2] = 1, xy[3] = 0, xy[4] = 0, xy[5] = 1;
  for (int i = r0; i < r1; i++) {
    const rawpt *r = &c->rp[i];
    if (!c->v[r->id].active || r->where >= 3) continue;
    int dup = 0;
    for (int k = 3; k < np; k++) dup |= id[k] == r->id;
    if (dup) continue;
    id[np] = r->id, xy[2 * np] = r->u, xy[2 * np + 1] = r->v, edge_of[np] = r->where;
    /* along edge e from corner e+1 to corner e+2: the weight of corner e+2 */
    par[np] = r->where == 0 ? r->v : (r->where == 1 ? 1.0 - r->v : r->u);
    np++;
  }
  /* The sides, split at their points (insertion sort: a few points). */
  for (int e = 0; e < 3; e++) {
    int chain[TB_FOLD_CUT_MAX + 2], m = 0;
    chain[m++] = (e + 1) % 3;
    for (int k = 3; k < np; k++) {
      if (edge_of[k] != e) continue;
      int j = m;
      while (j > 1 && par[chain[j - 1]] > par[k]) chain[j] = chain[j - 1], j--;
      chain[j] = k, m++;
      if (m >= TB_FOLD_CUT_MAX) break;
    }
    chain[m++] = (e + 2) % 3;
    for (int j = 0; j + 1 < m; j++)
      sg[2 * nseg] = chain[j], sg[2 * nseg + 1] = chain[j + 1], nseg++;
  }
  for (int i = 0; i < c->nsg; i++) {
    if (c->sg[i].tri != t) continue;
    int a = -1, b = -1;
    for (int k = 0; k < np; k++) {
      if (id[k] == c->sg[i].a) a = k;
      if (id[k] == c->sg[i].b) b = k;
    }
    if (a < 0 || b < 0) continue;
    sg[2 * nseg] = a, sg[2 * nseg + 1] = b, nseg++;
  }
  tb_cdt2 cdt;
  if (tb_cdt2_build(xy, np, sg, nseg, &cdt)) {
    rc = RETRY_BECAUSE(c, "a split triangle's cut segments cross");
    goto done;
  }
  rc = OK;
  for (int i = 0; i < cdt.ntri && rc == OK; i++)
    if (cut_emit(c, id[cdt.tri[3 * i]], id[cdt.tri[3 * i + 1]], id[cdt.tri[3 * i + 2]], t, LAB_S))
      rc = NOMEM;
  tb_cdt2_free(&cdt);
done:
  free(id), free(sg), free(xy), free(par), free(edge_of);
  return rc;
}

/* ---- step 4: un-welding ---- */

typedef struct inc {
  int pos, dir, lab; /* corner's place in the vertex's list; +1 for v -> x, -1 for x -> v */
} inc;

/* Joins the corners around v across the edge {v, x} (see the head comment). */
static int join_edge(int *uf, const inc *e, int n) {
  if (n == 2) {
    if (e[0].dir == e[1].dir) return RETRY;
    cut_uf_join(uf, e[0].pos, e[1].pos);
    return OK;
  }
  if (n != 4) return RETRY;
  int ns = 0, np = 0, s[2] = {0, 0}, cp[2] = {0, 0}, cm[2] = {0, 0}, nm = 0;
  for (int i = 0; i < 4; i++) {
    if (e[i].lab == LAB_S) s[ns++ & 1] = i;
    if (e[i].lab == LAB_CP) cp[np++ & 1] = i;
    if (e[i].lab == LAB_CM) cm[nm++ & 1] = i;
  }
  if (ns == 2 && np == 1 && nm == 1) {
    if (e[s[0]].dir == e[s[1]].dir || e[cp[0]].dir == e[cm[0]].dir) return RETRY;
    int sp = e[s[0]].dir != e[cp[0]].dir ? s[0] : s[1];
    cut_uf_join(uf, e[sp].pos, e[cp[0]].pos);
    cut_uf_join(uf, e[sp == s[0] ? s[1] : s[0]].pos, e[cm[0]].pos);
    return OK;
  }
  if (np == 2 && nm == 2) {
    if (e[cp[0]].dir == e[cp[1]].dir || e[cm[0]].dir == e[cm[1]].dir) return RETRY;
    cut_uf_join(uf, e[cp[0]].pos, e[cp[1]].pos);
    cut_uf_join(uf, e[cm[0]].pos, e[cm[1]].pos);
    return OK;
  }
  return RETRY;
}

static int unweld(cutter *c) {
  int nvr = c->nvr, n3 = 3 * c->nout, rc = NOMEM;
  int *start = calloc((size_t)nvr + 2, sizeof *start), *list = malloc((size_t)n3 * sizeof *list);
  int *touch = calloc((size_t)nvr + 1, sizeof *touch), *fill = NULL, *uf = NULL, *root = NULL;
  inc *e = NULL;
  if (!start || !list || !touch) goto done;
  for (int i = 0; i < n3; i++) {
    start[c->otri[i] + 1]++;
    if (c->olab[i / 3] != LAB_S) touch[c->otri[i]] = 1;
  }
  int maxdeg = 0;
  for (int v = 0; v < nvr; v++) {
    if (start[v + 1] > maxdeg) maxdeg = start[v + 1];
    start[v + 1] += start[v];
  }
  fill = malloc((size_t)(nvr + 1) * sizeof *fill);
  uf = malloc((size_t)(maxdeg + 1) * sizeof *uf),
  root = malloc((size_t)(maxdeg + 1) * sizeof *root);
  e = malloc((size_t)(maxdeg + 1) * sizeof *e);
  if (!fill || !uf || !root || !e) goto done;
  memcpy(fill, start, (size_t)nvr * sizeof *fill);
  for (int i = 0; i < n3; i++) list[fill[c->otri[i]]++] = i;
  rc = OK;
  for (int v = 0; v < nvr && rc == OK; v++) {
    if (!touch[v]) continue;
    const int *L = list + start[v];
    int m = start[v + 1] - start[v];
    for (int a = 0; a < m; a++) uf[a] = a;
    for (int a = 0; a < m && rc == OK; a++)
      for (int d = 0; d < 2 && rc == OK; d++) {
        int ta = L[a] / 3, ka = L[a] % 3, x = c->otri[3 * ta + (ka + (d ? 2 : 1)) % 3], n = 0;
        int firstpos = -1;
        for (int b = 0; b < m; b++) {
          int tb = L[b] / 3, kb = L[b] % 3;
          int nx = c->otri[3 * tb + (kb + 1) % 3], px = c->otri[3 * tb + (kb + 2) % 3];
          if (nx != x && px != x) continue;
          if (firstpos < 0) firstpos = b;
          e[n].pos = b, e[n].dir = nx == x ? 1 : -1, e[n].lab = c->olab[tb], n++;
        }
        if (firstpos == a) rc = join_edge(uf, e, n); /* each edge once */
      }
    if (rc != OK) {
      c->why = "un-welding: a crack vertex's edge is not in 2 or 4 consistent triangles";
      break;
    }
    /* One copy per fan: sides from the crack triangles in it. */
    int nroot = 0;
    for (int a = 0; a < m; a++)
      if (cut_uf_find(uf, a) == a) root[nroot++] = a;
    if (nroot == 1) {
      int hp = 0, hm = 0;
      for (int a = 0; a < m; a++)
        hp |= c->olab[L[a] / 3] == LAB_CP, hm |= c->olab[L[a] / 3] == LAB_CM;
      c->v[v].side = hp && !hm ? 1 : (hm && !hp ? -1 : 0);
      continue;
    }
    int keep = -1, side[64];
    if (nroot > 64) {
      rc = RETRY_BECAUSE(c, "un-welding: more than 64 fans around a vertex");
      break;
    }
    for (int r = 0; r < nroot; r++) {
      int hp = 0, hm = 0;
      for (int a = 0; a < m; a++)
        if (cut_uf_find(uf, a) == root[r])
          hp |= c->olab[L[a] / 3] == LAB_CP, hm |= c->olab[L[a] / 3] == LAB_CM;
      side[r] = hp && !hm ? 1 : (hm && !hp ? -1 : 0);
      if (keep < 0 && side[r] == 1) keep = r;
    }
    if (keep < 0) keep = 0;
    for (int r = 0; r < nroot; r++) {
      int id = v;
      if (r == keep) {
        c->v[v].side = side[r];
      } else {
        vrec copy = c->v[v];
        if ((id = cut_new_vertex(c, copy.x)) < 0) {
          rc = NOMEM;
          break;
        }
        c->v[id] = copy;
        c->v[id].origin = v < c->nv ? v : -1, c->v[id].side = side[r];
      }
      for (int a = 0; a < m; a++)
        if (cut_uf_find(uf, a) == root[r]) c->otri[L[a]] = id;
    }
  }
done:
  free(start), free(list), free(touch), free(fill), free(uf), free(root), free(e);
  return rc;
}

/* ---- one attempt with one fold ---- */

static void reset(cutter *c) { c->nvr = c->nrp = c->nsg = c->nout = 0; }

static int tri_near_fold(const cutter *c, int t, tb_vec3 lo, tb_vec3 hi) {
  for (int a = 0; a < 3; a++) {
    double mn = INFINITY, mx = -INFINITY;
    for (int k = 0; k < 3; k++) {
      double v = tb_comp(c->x[c->tri[3 * t + k]], a);
      mn = v < mn ? v : mn, mx = v > mx ? v : mx;
    }
    if (mx < tb_comp(lo, a) || mn > tb_comp(hi, a)) return 0;
  }
  return 1;
}

/* Steps 1-4 and the final check, into c->otri / c->v. */
static int attempt(cutter *c, int *cut_any) {
  const tb_fold *f = c->f;
  reset(c);
  *cut_any = 0;
  for (int v = 0; v < c->nv; v++) {
    int id = cut_new_vertex(c, c->x[v]);
    if (id < 0) return NOMEM;
    c->v[id].origin = v;
  }
  tb_vec3 lo = f->p[0], hi = f->p[0];
  for (int i = 0; i < f->count; i++)
    lo = tb_vmin(lo, tb_vmin(f->p[i], f->q[i])), hi = tb_vmax(hi, tb_vmax(f->p[i], f->q[i]));
  lo = tb_sub(lo, tb_v3(c->snapd, c->snapd, c->snapd)),
  hi = tb_add(hi, tb_v3(c->snapd, c->snapd, c->snapd));
  tb_fold_cut cut;
  for (int t = 0; t < c->ntri; t++) {
    if (!tri_near_fold(c, t, lo, hi)) continue;
    const int *T = c->tri + 3 * t;
    const tb_vec3 tx[3] = {c->x[T[0]], c->x[T[1]], c->x[T[2]]};
    tb_fold_triangle(f, tx, &cut);
    if (cut.degenerate || cut.truncated)
      return RETRY_BECAUSE(c, cut.degenerate ? "a triangle of zero area on the cut"
                                             : "a triangle crossed by more than 64 cut points");
    if (cut.coplanar)
      for (int k = 0; k < 3; k++) {
        tb_fold_near nr;
        tb_fold_nearest(f, tx[k], &nr);
        if (nr.dist <= c->snapd) return RETRY_BECAUSE(c, "a fold piece lies in a triangle's plane");
      }
    int rc = collect_triangle(c, t, &cut);
    if (rc != OK) return rc;
  }
  int *unpaired = NULL, rc = name_points(c, &unpaired);
  if (rc == OK) rc = make_segments(c);
  for (int i = 0; rc == OK && i < c->nrp; i++)
    if (unpaired[i] && c->v[c->rp[i].id].active)
      rc = RETRY_BECAUSE(c, "an edge point one triangle sees and its neighbour does not");
  free(unpaired);
  if (rc != OK) return rc;
  if (c->nsg == 0) return OK; /* missed, or only touched */
  *cut_any = 1;
  /* Old triangles in their slots; a split one's first piece replaces it. */
  for (int t = 0; t < c->ntri; t++)
    if (cut_emit(c, c->tri[3 * t], c->tri[3 * t + 1], c->tri[3 * t + 2], t, LAB_S)) return NOMEM;
  c->nsplit = 0;
  memset(c->split, 0, (size_t)c->ntri * sizeof *c->split);
  for (int r0 = 0, r1; r0 < c->nrp; r0 = r1) {
    int t = c->rp[r0].tri, need = 0;
    for (r1 = r0; r1 < c->nrp && c->rp[r1].tri == t; r1++)
      need |= c->rp[r1].where < 3 && c->v[c->rp[r1].id].active;
    if (!need) continue;
    int first = c->nout;
    if ((rc = split_triangle(c, t, r0, r1)) != OK) return rc;
    if (c->nout == first) return RETRY_BECAUSE(c, "a split triangle gave no triangles");
    memcpy(c->otri + 3 * t, c->otri + 3 * first, 3 * sizeof *c->otri);
    c->ofrom[first] = -2; /* moved */
    c->split[t] = 1, c->nsplit++;
  }
  /* The crack, each piece's triangles counter-clockwise about +n_k. */
  int *crack = NULL, ncrack = 0, capcrack = 0;
  for (int i = 0; i < 2 * f->count; i++) c->corner_id[i] = -1;
  for (int i = 0; i < CREASE_MAX * f->count; i++) c->crease_id[i] = -1;
  for (int k = 0; k < f->npieces && rc == OK; k++)
    rc = cut_crack_piece(c, k, &crack, &ncrack, &capcrack);
  for (int side = 0; side < 2 && rc == OK; side++)
    for (int i = 0; i < ncrack && rc == OK; i++) {
      const int *q = crack + 3 * i;
      if (side == 0 ? cut_emit(c, q[0], q[2], q[1], -1, LAB_CP)
                    : cut_emit(c, q[0], q[1], q[2], -1, LAB_CM))
        rc = NOMEM;
    }
  free(crack);
  if (rc != OK) return rc;
  c->ncrack = 2 * ncrack;
  int m = 0; /* drop the moved slots */
  for (int i = 0; i < c->nout; i++) {
    if (c->ofrom[i] == -2) continue;
    memmove(c->otri + 3 * m, c->otri + 3 * i, 3 * sizeof *c->otri);
    c->ofrom[m] = c->ofrom[i], c->olab[m] = c->olab[i], m++;
  }
  c->nout = m;
  if ((rc = unweld(c)) != OK) return rc;
  return tb_cut_is_closed_manifold(c->nvr, c->nout, c->otri)
             ? OK
             : RETRY_BECAUSE(c, "the result is not a closed, oriented 2-manifold");
}

/* ---- the result ---- */

static int fill_result(cutter *c, int cut_any, tb_cut_result *out) {
  if (!cut_any) { /* unchanged: a copy */
    c->nout = 0, c->nvr = c->nv;
    for (int t = 0; t < c->ntri; t++)
      if (cut_emit(c, c->tri[3 * t], c->tri[3 * t + 1], c->tri[3 * t + 2], t, LAB_S)) return NOMEM;
    c->nsplit = c->ncrack = 0;
  }
  /* Keep the used new vertices, in order. */
  int *map = malloc((size_t)(c->nvr + 1) * sizeof *map),
      *mark = calloc((size_t)c->nvr + 1, sizeof *mark);
  if (!map || !mark) {
    free(map), free(mark);
    return NOMEM;
  }
  for (int i = 0; i < 3 * c->nout; i++) mark[c->otri[i]] = 1;
  int nv = 0;
  for (int v = 0; v < c->nvr; v++) map[v] = v < c->nv || mark[v] ? nv++ : -1;
  out->nv = nv, out->ntri = c->nout;
  out->x = malloc((size_t)nv * sizeof *out->x);
  out->origin = malloc((size_t)nv * sizeof *out->origin);
  out->side = malloc((size_t)nv * sizeof *out->side);
  out->tri = malloc((size_t)(3 * c->nout + 1) * sizeof *out->tri);
  out->tri_from = malloc((size_t)(c->nout + 1) * sizeof *out->tri_from);
  out->reskin = malloc((size_t)(nv + 1) * sizeof *out->reskin);
  if (!out->x || !out->origin || !out->side || !out->tri || !out->tri_from || !out->reskin) {
    free(map), free(mark);
    return NOMEM;
  }
  for (int v = 0; v < c->nvr; v++) {
    if (map[v] < 0) continue;
    out->x[map[v]] = v < c->nv ? c->x[v] : c->v[v].x;
    out->origin[map[v]] = c->v[v].origin, out->side[map[v]] = c->v[v].side;
  }
  /* Re-skin: the new vertices and the corners of every changed triangle. */
  memset(mark, 0, (size_t)(c->nvr + 1) * sizeof *mark);
  for (int t = 0; t < c->nout; t++) {
    const int *q = c->otri + 3 * t, from = c->ofrom[t];
    int changed = from < 0 || from >= c->ntri || c->split[from];
    for (int k = 0; k < 3 && !changed; k++) changed = q[k] != c->tri[3 * from + k];
    for (int k = 0; k < 3; k++) {
      out->tri[3 * t + k] = map[q[k]];
      if (changed) mark[map[q[k]]] = 1;
    }
    out->tri_from[t] = from;
  }
  out->nreskin = 0;
  for (int v = 0; v < nv; v++)
    if (v >= c->nv || mark[v]) out->reskin[out->nreskin++] = v;
  out->cut = cut_any, out->split_tris = c->nsplit, out->crack_tris = c->ncrack;
  out->components_after = tb_cut_components(nv, out->ntri, out->tri);
  free(map), free(mark);
  return OK;
}

void tb_cut_result_free(tb_cut_result *r) {
  free(r->x), free(r->origin), free(r->side), free(r->tri), free(r->tri_from), free(r->reskin);
  memset(r, 0, sizeof *r);
}

static void cutter_free(cutter *c) {
  free(c->pair), free(c->v), free(c->rp), free(c->sg), free(c->otri), free(c->ofrom), free(c->olab);
  free(c->split), free(c->corner_id), free(c->crease_id);
}

/* Half-edge pairs of a closed surface. */
static int make_pairs(cutter *c) {
  vstar vs = {NULL, NULL};
  c->pair = malloc((size_t)3 * c->ntri * sizeof *c->pair);
  if (!c->pair || cut_vstar_build(&vs, c->nv, c->ntri, c->tri)) {
    cut_vstar_free(&vs);
    return NOMEM;
  }
  for (int h = 0; h < 3 * c->ntri; h++)
    c->pair[h] = cut_find_edge(&vs, c->tri, c->tri[h - h % 3 + (h % 3 + 1) % 3], c->tri[h]);
  cut_vstar_free(&vs);
  return OK;
}

/* The fold moved by offset along a fixed direction (n_0 tilted towards e_0 and D). */
static int shifted_fold(const tb_fold *f, double offset, tb_fold *g) {
  tb_vec3 m =
      tb_normalize(tb_add(tb_add(f->piece[0].n, tb_scale(tb_normalize(f->piece[0].e), 0.31)),
                          tb_scale(tb_normalize(f->depth), 0.17)));
  tb_vec3 *p = malloc((size_t)f->count * sizeof *p);
  if (!p) return -1;
  for (int i = 0; i < f->count; i++) p[i] = tb_madd(f->p[i], offset, m);
  int rc = tb_fold_init(g, p, f->count, f->depth, NULL);
  free(p);
  return rc;
}

int tb_cut_surface(int nv, const tb_vec3 *x, int ntri, const int *tri, const tb_fold *fold,
                   const tb_cut_def *def, tb_cut_result *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  tb_cut_def d = def ? *def : tb_cut_default_def();
  if (nv < 4 || ntri < 4 || !x || !tri || !fold || fold->npieces < 1)
    return tb_error_set(err, NAME, 0, "no surface or no fold (%d vertices, %d triangles)", nv,
                        ntri);
  for (int v = 0; v < nv; v++)
    if (!tb_isfinite3(x[v])) return tb_error_set(err, NAME, 0, "vertex %d is not finite", v);
  if (!tb_cut_is_closed_manifold(nv, ntri, tri))
    return tb_error_set(err, NAME, 0, "the surface is not a closed, oriented 2-manifold");
  if (!(tb_cut_volume(x, ntri, tri) > 0))
    return tb_error_set(err, NAME, 0, "the surface encloses no positive volume (inward?)");
  if (!(d.snap >= 0) || !isfinite(d.spacing) || (d.nextra > 0 && !d.extra) || d.nextra < 0)
    return tb_error_set(err, NAME, 0, "bad settings (snap %g, spacing %g, %d extra points)", d.snap,
                        d.spacing, d.nextra);
  cutter c;
  memset(&c, 0, sizeof c);
  c.nv = nv, c.ntri = ntri, c.x = x, c.tri = tri, c.extra = d.extra, c.nextra = d.nextra;
  double sum = 0;
  for (int t = 0; t < ntri; t++)
    for (int k = 0; k < 3; k++) sum += tb_dist(x[tri[3 * t + k]], x[tri[3 * t + (k + 1) % 3]]);
  c.h = sum / (3.0 * ntri);
  c.snapd = (d.snap > 0 ? d.snap : 1e-6) * c.h;
  c.spacing = d.spacing == 0 ? c.h : (d.spacing < 0 ? 0 : d.spacing);
  c.split = calloc((size_t)ntri, sizeof *c.split);
  c.corner_id = malloc((size_t)2 * fold->count * sizeof *c.corner_id);
  c.crease_id = malloc((size_t)CREASE_MAX * fold->count * sizeof *c.crease_id);
  int rc = !c.split || !c.corner_id || !c.crease_id ? NOMEM : make_pairs(&c), cut_any = 0,
      used = -1;
  static const double shift[MAX_ATTEMPTS] = {0, 1e-5, -2e-5, 4e-5};
  for (int a = 0; a < MAX_ATTEMPTS && rc == OK; a++) {
    tb_fold g;
    memset(&g, 0, sizeof g);
    if (a > 0 && shifted_fold(fold, shift[a] * c.h, &g)) {
      rc = NOMEM;
      break;
    }
    c.f = a > 0 ? &g : fold;
    int r = attempt(&c, &cut_any);
    tb_fold_free(&g);
    if (r == OK) {
      used = a;
      break;
    }
    if (r == NOMEM) rc = NOMEM;
  }
  if (rc == OK && used < 0) {
    cutter_free(&c);
    return tb_error_set(err, NAME, 0, "the cut stays inconsistent after %d shifts of the fold (%s)",
                        MAX_ATTEMPTS - 1, c.why ? c.why : "?");
  }
  if (rc == OK) rc = fill_result(&c, cut_any, out);
  if (rc == OK) {
    out->perturbed = used;
    out->components_before = tb_cut_components(nv, ntri, tri);
  }
  cutter_free(&c);
  if (rc != OK) {
    tb_cut_result_free(out);
    return tb_error_set(err, NAME, 0, "out of memory");
  }
  return 0;
}
