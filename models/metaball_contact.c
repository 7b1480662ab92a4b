/* The skin's contact after cuts: the two faces of a crack do not pass
 * through each other or through the other side's surface near the crack,
 * and the pieces do not pass through each other (the metaball patent leaves
 * contact out; the spheres alone keep apart across a crack,
 * models/metaball.c, which does not stop the skin bound to them from
 * folding through the other face by a fraction of an edge).
 *
 * What meets what. (1) Twins: a crack point's copy on the + side and on the
 * - side (the cutter copies it bit for bit) keep their order along the
 * crack's normal (kept in the rest frame, turned by a sphere the - copy is
 * bound to) while they face each other (their offset across it under twice
 * the - copy's mean edge). (2) A cut's zone: every surface vertex on the
 * crack (side +1 or -1) or within ZONE_RINGS mean crack edges of the fold
 * (its side of the fold, tb_fold_side), labelled 2 k + (side > 0) for the
 * k-th cut, and the triangles whose three vertices share a label; a zone
 * vertex meets the triangles of the other side of its cut (a later cut's
 * splits drop the old triangles it split). (3) The pieces: the surface's
 * vertices and triangles by piece at the last cut's end; where the boxes of
 * two pieces overlap, the vertices in the overlap meet the other piece's
 * triangles there.
 *
 * The contact, after each step's skin (vertex against triangle, the
 * proximity half of Bridson, Fedkiw & Anderson 2002, "Robust treatment of
 * collisions, contact and friction for cloth animation", §6): a vertex
 * closer than the gap g in front of a triangle, or behind it by less than
 * DEEP mean edges, over it (its projection inside the triangle, off its
 * edges), its normal turned away from the triangle's (the faces face each
 * other: at a crack's mouth the other side's surface runs at a right angle
 * and is left alone) pushes their spheres apart along the triangle's
 * outward normal by g - d: half on the vertex's spheres, half on the
 * triangle's (all on one side when the other's are held), each sphere
 * taking the largest push of its vertices, as the ground does
 * (models/metaball_model.c); the push enters the spheres' velocities
 * (position-based: v += dx / dt); then the skin again, up to PASSES times
 * while anything is pushed. Candidates come from a hash grid, cells of
 * CELL mean triangle widths, each triangle in the cells its box (grown by
 * the depth) meets, a vertex looking in its own; a triangle over too many
 * cells (stretched far) is tried by every vertex. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metaball_priv.h"

#define ZONE_RINGS 3 /* a cut's zone reaches this many mean crack edges from the fold */
#define GAP 2e-4     /* the least separation, in mean edges */
#define PASSES 3     /* contact passes per step */
#define CELL 2.0     /* the grid's cell, in mean triangle widths */
#define ROOM 8       /* grid entries per triangle */
#define MAX_CELLS 64 /* a triangle over more cells goes on the list every vertex tries */
#define DEEP 0.5     /* a vertex behind a triangle by up to this many mean edges is pushed out */
#define FACING 0.2   /* ... when its normal and the triangle's are more than acos(-0.2) apart */
#define INSIDE 1e-3  /* ... and it lies over the triangle, this share of twice its area in */

typedef struct tb_metaball_zone {
  /* (2) the cuts' zones */
  int nv, vcap, *v;          /* (vertex, label) pairs */
  int nt, tcap, *t;          /* (3 vertices, label) quadruples */
  int ncut, ccap;            /* cuts, and room in: */
  double *deep, *gap, *cell; /* per cut: the deepest penetration pushed out, the gap, the cell */
  /* (3) the pieces: the surface at the last cut's end */
  int npiece, nsurf, scap, *surf; /* (3 vertices, piece) quadruples */
  int *vpiece;                    /* per skin vertex (nvert): its piece, -1 when unused */
  int nvert;
  double pdeep, pgap, pcell;
  /* (1) twins */
  int ntwin, twcap, *twin; /* (+ vertex, - vertex, sphere carrying the normal) triples */
  tb_vec3 *tn;             /* the crack's normal (to the + side) in the rest frame */
  double *treach;          /* beyond this tangential offset the two no longer face each other */
  int tncap, trcap;
  /* scratch of the step, sized at the cut's end */
  int H, *start, *bucketed, *key; /* the grid: H buckets; triangles by bucket (ecap) */
  int ecap, *big;                 /* room in bucketed; triangles every vertex tries */
  int *vl, *vlab, *tl, *label;    /* listed vertices, their labels; listed triangles; a
                                   * vertex's label while listed, else -1 (nvert) */
  tb_vec3 *normal;                /* per skin vertex (nvert) */
  tb_vec3 *blo, *bhi;             /* per piece: its box */
  tb_vec3 *push;                  /* per sphere (pcap): the largest push of a pass */
  int pcap;
} tb_metaball_zone;

void tb_metaball_zone_free(tb_metaball *m) {
  tb_metaball_zone *z = m->zone;
  if (!z) return;
  free(z->v), free(z->t), free(z->deep), free(z->gap), free(z->cell), free(z->surf);
  free(z->vpiece), free(z->twin), free(z->tn), free(z->treach), free(z->start), free(z->bucketed);
  free(z->big), free(z->key), free(z->vl), free(z->vlab), free(z->tl), free(z->label),
      free(z->normal);
  free(z->blo), free(z->bhi), free(z->push);
  free(z);
  m->zone = NULL;
}

static int grow(void **a, int *cap, int need, size_t size) {
  if (need <= *cap) return 0;
  int c = *cap ? *cap : 256;
  while (c < need) c *= 2;
  void *b = realloc(*a, (size_t)c * size);
  if (!b) return -1;
  *a = b, *cap = c;
  return 0;
}

static int resize(void **a, size_t n, size_t size) {
  void *b = realloc(*a, (n ? n : 1) * size);
  if (!b) return -1;
  *a = b;
  return 0;
}

/* ---- building: the old zones' triangles still in the surface ---- */

typedef struct tkey {
  int a, b, c;
} tkey;

static tkey sorted(const int *t) {
  int a = t[0], b = t[1], c = t[2], s;
  if (a > b) s = a, a = b, b = s;
  if (b > c) s = b, b = c, c = s;
  if (a > b) s = a, a = b, b = s;
  return (tkey){a, b, c};
}
static int by_tkey(const void *p, const void *q) {
  const tkey *x = p, *y = q;
  if (x->a != y->a) return x->a < y->a ? -1 : 1;
  if (x->b != y->b) return x->b < y->b ? -1 : 1;
  return (x->c > y->c) - (x->c < y->c);
}

static int keep_triangles(tb_metaball_zone *z, const tb_metaball_skin_def *d) {
  if (!z->nt) return 0;
  tkey *all = malloc(sizeof(tkey) * (size_t)d->ntri);
  if (!all) return -1;
  for (int t = 0; t < d->ntri; t++) all[t] = sorted(d->tri + 3 * t);
  qsort(all, (size_t)d->ntri, sizeof(tkey), by_tkey);
  int k = 0;
  for (int q = 0; q < z->nt; q++) {
    tkey key = sorted(z->t + 4 * q);
    if (bsearch(&key, all, (size_t)d->ntri, sizeof(tkey), by_tkey))
      memmove(z->t + 4 * k++, z->t + 4 * q, 4 * sizeof(int));
  }
  z->nt = k;
  free(all);
  return 0;
}

/* ---- building: twins ---- */

static const tb_vec3 *place_x; /* qsort's context: positions */
static int by_place(const void *pa, const void *pb) {
  int a = *(const int *)pa, b = *(const int *)pb;
  tb_vec3 p = place_x[a], q = place_x[b];
  for (int k = 0; k < 3; k++)
    if (tb_comp(p, k) != tb_comp(q, k)) return tb_comp(p, k) < tb_comp(q, k) ? -1 : 1;
  return a - b;
}

/* The old twins with a sphere to carry their normal, then the new cut's. */
static int twins(tb_metaball *m, const tb_metaball_skin_def *d, const tb_fold *f, const double *len,
                 const int *deg) {
  tb_metaball_zone *z = m->zone;
  int k = 0;
  for (int q = 0; q < z->ntwin; q++) {
    int *w = z->twin + 3 * q;
    if (!m->alive[w[2]] && (w[2] = m->bind[w[1]][0]) < 0) continue;
    memmove(z->twin + 3 * k, w, 3 * sizeof(int)), z->tn[k] = z->tn[q],
                                                  z->treach[k++] = z->treach[q];
  }
  z->ntwin = k;
  int n = 0, *on = malloc(sizeof(int) * (size_t)d->nv), rc = 0;
  if (!on) return -1;
  for (int v = 0; v < d->nv; v++)
    if (d->side[v] && deg[v]) on[n++] = v;
  place_x = d->x;
  qsort(on, (size_t)n, sizeof(int), by_place);
  for (int i = 0; i + 1 < n && rc == 0; i++) {
    int a = on[i], b = on[i + 1];
    if (memcmp(&d->x[a], &d->x[b], sizeof(tb_vec3)) || d->side[a] == d->side[b]) continue;
    if (d->side[a] < 0) a = on[i + 1], b = on[i];
    int s = m->bind[b][0];
    if (s < 0) continue;
    if (grow((void **)&z->twin, &z->twcap, 3 * (z->ntwin + 1), sizeof(int)) ||
        grow((void **)&z->tn, &z->tncap, z->ntwin + 1, sizeof(tb_vec3)) ||
        grow((void **)&z->treach, &z->trcap, z->ntwin + 1, sizeof(double))) {
      rc = -1;
      break;
    }
    tb_fold_near nr;
    tb_fold_nearest(f, d->x[b], &nr);
    int q = z->ntwin++;
    z->twin[3 * q] = a, z->twin[3 * q + 1] = b, z->twin[3 * q + 2] = s;
    z->tn[q] = tb_m3_mulv(tb_m3_transpose(m->rot[s]), f->piece[nr.piece].n);
    z->treach[q] = 2 * len[b] / deg[b];
    i++;
  }
  free(on);
  return rc;
}

/* ---- building: the cut's zone and the pieces ---- */

/* The widest side of a triangle's box. */
static double width(const tb_vec3 *x, const int *T) {
  tb_vec3 lo = tb_vmin(tb_vmin(x[T[0]], x[T[1]]), x[T[2]]);
  tb_vec3 e = tb_sub(tb_vmax(tb_vmax(x[T[0]], x[T[1]]), x[T[2]]), lo);
  return fmax(fmax(e.x, e.y), e.z);
}

/* Cut k's zone (see the head); h its mean crack edge. */
static int cut_zone(tb_metaball_zone *z, const tb_metaball_skin_def *d, const tb_fold *f,
                    const int *deg, int k, double h, int *nvert, int *ntri) {
  int *lab = malloc(sizeof(int) * (size_t)d->nv), rc = 0;
  if (!lab) return -1;
  for (int v = 0; v < d->nv && rc == 0; v++) {
    int side = deg[v] ? d->side[v] : 0;
    lab[v] = -1;
    if (deg[v] && !side) {
      tb_fold_near nr;
      tb_fold_nearest(f, d->x[v], &nr);
      if (nr.dist < ZONE_RINGS * h) side = tb_fold_side(f, d->x[v]);
    }
    if (!side) continue;
    lab[v] = 2 * k + (side > 0);
    if ((rc = grow((void **)&z->v, &z->vcap, 2 * (z->nv + 1), sizeof(int))) == 0)
      z->v[2 * z->nv] = v, z->v[2 * z->nv + 1] = lab[v], z->nv++, (*nvert)++;
  }
  double sum = 0; /* the cell: CELL times the zone's mean triangle width */
  for (int t = 0; t < d->ntri && rc == 0; t++) {
    const int *T = d->tri + 3 * t;
    if (lab[T[0]] < 0 || lab[T[0]] != lab[T[1]] || lab[T[0]] != lab[T[2]]) continue;
    if ((rc = grow((void **)&z->t, &z->tcap, 4 * (z->nt + 1), sizeof(int)))) break;
    memcpy(z->t + 4 * z->nt, T, 3 * sizeof(int)), z->t[4 * z->nt++ + 3] = lab[T[0]], (*ntri)++;
    sum += width(d->x, T);
  }
  free(lab);
  z->deep[k] = DEEP * h, z->gap[k] = GAP * h;
  z->cell[k] = fmax(CELL * (*ntri ? sum / *ntri : h), 2 * DEEP * h);
  return rc;
}

/* The surface by pieces (of_vertex from the caller's pieces, or -1). */
static int surface(tb_metaball_zone *z, const tb_metaball_skin_def *d, const int *of_vertex,
                   int npiece, double h) {
  if (grow((void **)&z->surf, &z->scap, 4 * d->ntri, sizeof(int)) ||
      resize((void **)&z->vpiece, (size_t)d->nv, sizeof(int)))
    return -1;
  double sum = 0;
  z->nsurf = d->ntri, z->npiece = of_vertex ? npiece : 0;
  for (int t = 0; t < d->ntri; t++) {
    const int *T = d->tri + 3 * t;
    memcpy(z->surf + 4 * t, T, 3 * sizeof(int));
    z->surf[4 * t + 3] = of_vertex ? of_vertex[T[0]] : 0;
    sum += width(d->x, T);
  }
  for (int v = 0; v < d->nv; v++) z->vpiece[v] = of_vertex ? of_vertex[v] : -1;
  z->pdeep = DEEP * h, z->pgap = GAP * h;
  z->pcell = fmax(CELL * (d->ntri ? sum / d->ntri : h), 2 * DEEP * h);
  return 0;
}

int tb_metaball_zone_add(tb_metaball *m, const tb_metaball_skin_def *d, const tb_fold *f,
                         const int *of_vertex, int npiece, int *nvert, int *ntri) {
  *nvert = *ntri = 0;
  if (!f || !d->side || d->ntri < 1) return 0;
  if (!m->zone && !(m->zone = calloc(1, sizeof *m->zone))) return -1;
  tb_metaball_zone *z = m->zone;
  int *deg = calloc((size_t)d->nv, sizeof(int));
  double *len = calloc((size_t)d->nv, sizeof(double)), sum = 0, all = 0;
  int ne = 0, rc = !deg || !len ? -1 : keep_triangles(z, d);
  for (int t = 0; t < d->ntri && rc == 0; t++) {
    const int *T = d->tri + 3 * t;
    int on = d->side[T[0]] || d->side[T[1]] || d->side[T[2]];
    for (int e = 0; e < 3; e++) {
      int a = T[e], b = T[(e + 1) % 3];
      double l = tb_dist(d->x[a], d->x[b]);
      len[a] += l, len[b] += l, deg[a]++, deg[b]++, all += l;
      if (on) sum += l, ne++;
    }
  }
  int k = z->ncut;
  if (rc == 0 && ne > 0 &&
      (grow((void **)&z->deep, &z->ccap, k + 1, sizeof(double)) ||
       resize((void **)&z->gap, (size_t)z->ccap, sizeof(double)) ||
       resize((void **)&z->cell, (size_t)z->ccap, sizeof(double))))
    rc = -1;
  if (rc == 0) rc = twins(m, d, f, len, deg);
  if (rc == 0 && ne > 0) rc = cut_zone(z, d, f, deg, k, sum / ne, nvert, ntri), z->ncut = k + 1;
  if (rc == 0) rc = surface(z, d, of_vertex, npiece, all / (3.0 * d->ntri));
  free(deg), free(len);
  if (rc) return -1;
  /* the step's scratch */
  int most = z->nt > z->nsurf ? z->nt : z->nsurf, H = 64;
  while (H < 8 * most) H *= 2;
  size_t V = (size_t)d->nv, P = (size_t)(z->npiece > 0 ? z->npiece : 1);
  if (resize((void **)&z->start, (size_t)H + 1, sizeof(int)) ||
      resize((void **)&z->bucketed, (size_t)ROOM * most, sizeof(int)) ||
      resize((void **)&z->big, (size_t)most, sizeof(int)) ||
      resize((void **)&z->key, (size_t)most, sizeof(int)) ||
      resize((void **)&z->tl, (size_t)most, sizeof(int)) ||
      resize((void **)&z->vl, V, sizeof(int)) || resize((void **)&z->vlab, V, sizeof(int)) ||
      resize((void **)&z->label, V, sizeof(int)) ||
      resize((void **)&z->normal, V, sizeof(tb_vec3)) ||
      resize((void **)&z->blo, P, sizeof(tb_vec3)) ||
      resize((void **)&z->bhi, P, sizeof(tb_vec3)) ||
      resize((void **)&z->push, (size_t)m->n, sizeof(tb_vec3)))
    return -1;
  z->H = H, z->ecap = ROOM * most, z->nvert = d->nv, z->pcap = m->n;
  for (int v = 0; v < d->nv; v++) z->label[v] = -1;
  memset(z->push, 0, sizeof(tb_vec3) * (size_t)m->n);
  return 0;
}

/* ---- the contact ---- */

static unsigned bucket(int i, int j, int k, int H) {
  unsigned h = (unsigned)i * 73856093u ^ (unsigned)j * 19349663u ^ (unsigned)k * 83492791u;
  return h & (unsigned)(H - 1);
}

static int cell_of(double v, double cell) { return (int)floor(v / cell); }

static int is_free(const tb_metaball *m, int v) {
  for (int q = 0; q < 3; q++) {
    int s = m->bind[v][q];
    if (s >= 0 && m->wf[s] > 0) return 1;
  }
  return 0;
}

/* Vertex v's free spheres take push, each the largest of its vertices'. */
static int take(tb_metaball *m, int v, tb_vec3 push) {
  tb_metaball_zone *z = m->zone;
  double l = tb_len(push);
  int any = 0;
  for (int q = 0; q < 3; q++) {
    int s = m->bind[v][q];
    if (s < 0 || s >= z->pcap || m->wf[s] == 0 || !(l > tb_len(z->push[s]))) continue;
    z->push[s] = push, any = 1;
  }
  return any;
}

/* Pushes vertex v and the corners of T apart along n by need. */
static int push_apart(tb_metaball *m, int v, const int *T, tb_vec3 n, double need) {
  int fv = is_free(m, v), ft = is_free(m, T[0]) || is_free(m, T[1]) || is_free(m, T[2]), any = 0;
  double share = ft ? (fv ? 0.5 : 0) : 1;
  if (share > 0) any |= take(m, v, tb_scale(n, share * need));
  if (share < 1)
    for (int q = 0; q < 3; q++) any |= take(m, T[q], tb_scale(n, -(1 - share) * need));
  return any;
}

/* Twin k short of its gap while still facing its copy: pushed apart. */
static int twin_push(tb_metaball *m, int k) {
  tb_metaball_zone *z = m->zone;
  int a = z->twin[3 * k], b = z->twin[3 * k + 1], s = z->twin[3 * k + 2];
  if (!m->alive[s]) /* the normal is in the rest frame: any sphere of b carries it */
    s = z->twin[3 * k + 2] = m->bind[b][0] >= 0 ? m->bind[b][0] : s;
  if (!m->alive[s]) return 0;
  tb_vec3 n = tb_m3_mulv(m->rot[s], z->tn[k]), d = tb_sub(m->x[a], m->x[b]);
  double g = tb_dot(d, n), gap = GAP * z->treach[k];
  if (!(g < gap) || tb_len(tb_madd(d, -g, n)) > z->treach[k]) return 0;
  int fa = is_free(m, a), fb = is_free(m, b), any = 0;
  double need = gap - g, share = fb ? (fa ? 0.5 : 0) : 1;
  if (share > 0) any |= take(m, a, tb_scale(n, share * need));
  if (share < 1) any |= take(m, b, tb_scale(n, -(1 - share) * need));
  return any;
}

/* Vertex v (normal nv) against triangle T: 1 with the push along T's
 * outward normal (*n) and its length (*need). */
static int meets(const tb_metaball *m, int v, tb_vec3 nv, const int *T, double gap, double deep,
                 double *need, tb_vec3 *n) {
  if (v == T[0] || v == T[1] || v == T[2]) return 0;
  tb_vec3 A = m->x[T[0]], B = m->x[T[1]], C = m->x[T[2]], p = m->x[v];
  tb_vec3 nn = tb_cross(tb_sub(B, A), tb_sub(C, A));
  double len = tb_len(nn);
  if (!(len > 0)) return 0;
  nn = tb_scale(nn, 1 / len);
  if (!(tb_dot(nv, nn) < -FACING)) return 0;
  double dist = tb_dot(tb_sub(p, A), nn);
  if (!(dist < gap) || !(dist > -deep)) return 0;
  tb_vec3 q = tb_madd(p, -dist, nn);
  double in = INSIDE * len;
  if (tb_dot(tb_cross(tb_sub(B, A), tb_sub(q, A)), nn) < in ||
      tb_dot(tb_cross(tb_sub(C, B), tb_sub(q, B)), nn) < in ||
      tb_dot(tb_cross(tb_sub(A, C), tb_sub(q, C)), nn) < in)
    return 0;
  *need = gap - dist, *n = nn;
  return 1;
}

/* The listed vertices (z->vl, labels z->vlab, nvl) against the listed
 * triangles (z->tl into T4, ntl): a vertex meets a triangle of the label
 * label ^ 1 (pieces == 0: a cut's two sides) or of any other label
 * (pieces == 1). Returns 1 when something was pushed. */
static int collide(tb_metaball *m, const int *T4, int ntl, int nvl, double cell, double gap,
                   double deep, int pieces) {
  tb_metaball_zone *z = m->zone;
  for (int k = 0; k < nvl; k++)
    z->label[z->vl[k]] = z->vlab[k], z->normal[z->vl[k]] = tb_v3(0, 0, 0);
  memset(z->start, 0, sizeof(int) * (size_t)(z->H + 1));
  /* each triangle in every cell its box, grown by the depth, meets (a
   * bucket once); past the room, or over MAX_CELLS cells, on a list every
   * vertex tries */
  int nbig = 0, entries = 0;
  for (int pass = 0; pass < 2; pass++) {
    for (int i = 0; i < ntl; i++) {
      const int *T = T4 + 4 * z->tl[i];
      tb_vec3 A = m->x[T[0]], B = m->x[T[1]], C = m->x[T[2]];
      if (pass == 0) {
        tb_vec3 n = tb_cross(tb_sub(B, A), tb_sub(C, A));
        for (int q = 0; q < 3; q++)
          if (z->label[T[q]] == T[3]) z->normal[T[q]] = tb_add(z->normal[T[q]], n);
      }
      tb_vec3 g = tb_v3(deep + gap, deep + gap, deep + gap);
      tb_vec3 lo = tb_sub(tb_vmin(tb_vmin(A, B), C), g), hi = tb_add(tb_vmax(tb_vmax(A, B), C), g);
      int i0 = cell_of(lo.x, cell), i1 = cell_of(hi.x, cell), j0 = cell_of(lo.y, cell);
      int j1 = cell_of(hi.y, cell), k0 = cell_of(lo.z, cell), k1 = cell_of(hi.z, cell);
      long cells = (long)(i1 - i0 + 1) * (j1 - j0 + 1) * (k1 - k0 + 1);
      if (pass == 0) {
        z->key[i] = cells > MAX_CELLS || entries + cells > z->ecap ? -1 : 1;
        if (z->key[i] < 0) {
          z->big[nbig++] = z->tl[i];
          continue;
        }
        entries += (int)cells;
      } else if (z->key[i] < 0) {
        continue;
      }
      for (int kk = k0; kk <= k1; kk++)
        for (int jj = j0; jj <= j1; jj++)
          for (int ii = i0; ii <= i1; ii++) {
            unsigned b = bucket(ii, jj, kk, z->H);
            if (pass == 0)
              z->start[b + 1]++;
            else
              z->bucketed[z->start[b]++] = z->tl[i];
          }
    }
    if (pass == 0)
      for (int b = 0; b < z->H; b++) z->start[b + 1] += z->start[b];
  }
  for (int b = z->H; b > 0; b--) z->start[b] = z->start[b - 1];
  z->start[0] = 0;
  int any = 0;
  for (int k = 0; k < nvl; k++) {
    int v = z->vl[k], lab = z->vlab[k];
    double l = tb_len(z->normal[v]);
    tb_vec3 nv = l > 0 ? tb_scale(z->normal[v], 1 / l) : tb_v3(0, 0, 0), p = m->x[v];
    unsigned b = bucket(cell_of(p.x, cell), cell_of(p.y, cell), cell_of(p.z, cell), z->H);
    for (int e = z->start[b]; e < z->start[b + 1] + nbig; e++) {
      const int *T = T4 + 4 * (e < z->start[b + 1] ? z->bucketed[e] : z->big[e - z->start[b + 1]]);
      double need;
      tb_vec3 n;
      if ((pieces ? T[3] == lab : T[3] != (lab ^ 1)) || !meets(m, v, nv, T, gap, deep, &need, &n))
        continue;
      any |= push_apart(m, v, T, n, need);
    }
  }
  for (int k = 0; k < nvl; k++) z->label[z->vl[k]] = -1;
  return any;
}

/* Cut c's zone, listed. */
static int cut_pass(tb_metaball *m, int c) {
  tb_metaball_zone *z = m->zone;
  int nvl = 0, ntl = 0;
  for (int k = 0; k < z->nv; k++)
    if (z->v[2 * k + 1] / 2 == c) z->vl[nvl] = z->v[2 * k], z->vlab[nvl++] = z->v[2 * k + 1];
  for (int t = 0; t < z->nt; t++)
    if (z->t[4 * t + 3] / 2 == c) z->tl[ntl++] = t;
  return collide(m, z->t, ntl, nvl, z->cell[c], z->gap[c], z->deep[c], 0);
}

static int inside(tb_vec3 p, tb_vec3 lo, tb_vec3 hi) {
  return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

/* Each pair of pieces whose boxes (grown by the deepest push) overlap:
 * their vertices and triangles (by centroid, the box grown by a cell) in
 * the overlap, listed. */
static int piece_pass(tb_metaball *m) {
  tb_metaball_zone *z = m->zone;
  if (z->npiece < 2) return 0;
  tb_vec3 big = tb_v3(INFINITY, INFINITY, INFINITY), r = tb_v3(z->pdeep, z->pdeep, z->pdeep);
  for (int p = 0; p < z->npiece; p++) z->blo[p] = big, z->bhi[p] = tb_scale(big, -1);
  for (int v = 0; v < z->nvert && v < m->nv; v++) {
    int p = z->vpiece[v];
    if (p >= 0) z->blo[p] = tb_vmin(z->blo[p], m->x[v]), z->bhi[p] = tb_vmax(z->bhi[p], m->x[v]);
  }
  int any = 0;
  for (int p = 0; p < z->npiece; p++)
    for (int q = p + 1; q < z->npiece; q++) {
      tb_vec3 lo = tb_vmax(tb_sub(z->blo[p], r), tb_sub(z->blo[q], r));
      tb_vec3 hi = tb_vmin(tb_add(z->bhi[p], r), tb_add(z->bhi[q], r));
      if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) continue;
      int nvl = 0, ntl = 0;
      for (int v = 0; v < z->nvert && v < m->nv; v++)
        if ((z->vpiece[v] == p || z->vpiece[v] == q) && inside(m->x[v], lo, hi))
          z->vl[nvl] = v, z->vlab[nvl++] = z->vpiece[v];
      tb_vec3 c = tb_v3(z->pcell, z->pcell, z->pcell), tlo = tb_sub(lo, c), thi = tb_add(hi, c);
      for (int t = 0; t < z->nsurf; t++) {
        const int *T = z->surf + 4 * t;
        if (T[3] != p && T[3] != q) continue;
        tb_vec3 g = tb_scale(tb_add(tb_add(m->x[T[0]], m->x[T[1]]), m->x[T[2]]), 1.0 / 3);
        if (inside(g, tlo, thi)) z->tl[ntl++] = t;
      }
      if (nvl && ntl) any |= collide(m, z->surf, ntl, nvl, z->pcell, z->pgap, z->pdeep, 1);
    }
  return any;
}

void tb_metaball_zone_contact(tb_metaball *m, double dt) {
  tb_metaball_zone *z = m->zone;
  if (!z || m->nv > z->nvert) return; /* a cut's end has not made it anew yet */
  for (int pass = 0; pass < PASSES; pass++) {
    int any = 0;
    for (int k = 0; k < z->ntwin; k++) any |= twin_push(m, k);
    for (int c = 0; c < z->ncut; c++) any |= cut_pass(m, c);
    any |= piece_pass(m);
    if (!any) return;
    for (int s = 0; s < z->pcap; s++) {
      if (z->push[s].x == 0 && z->push[s].y == 0 && z->push[s].z == 0) continue;
      m->c[s] = tb_add(m->c[s], z->push[s]), m->v[s] = tb_madd(m->v[s], 1 / dt, z->push[s]);
      z->push[s] = tb_v3(0, 0, 0);
    }
    tb_metaball_reskin(m);
  }
}
