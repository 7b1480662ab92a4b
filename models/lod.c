/* Levels of detail and the active surface (see tb_lod.h; Bao et al. 2006,
 * §3.3: faces of a node whose force passes a threshold are split, up to a
 * depth, with a 1-to-2 transition band; §3.4: a half-edge surface and a
 * forest of quadtrees). The levels come from core/butterfly.c; here only
 * the bookkeeping of which faces are on. */
#include "tb_lod.h"

#include <stdlib.h>
#include <string.h>

#include "core/tb_butterfly.h"
#include "core/tb_halfedge.h"

void tb_lod_free(tb_lod *lod) {
  if (lod->tri)
    for (int l = 0; l < lod->nlevels; l++)
      free(lod->tri[l]), free(lod->pair[l]), free(lod->out[l]), free(lod->mid[l]);
  free(lod->tri), free(lod->pair), free(lod->out), free(lod->mid), free(lod->rest),
      free(lod->level_nv), free(lod->level_nf), free(lod->first), free(lod->ends), free(lod->state),
      free(lod->out_tri), free(lod->out_leaf), free(lod->active);
  memset(lod, 0, sizeof *lod);
}

int tb_lod_create(tb_lod *lod, const tb_mesh *base, int nlevels, tb_error *err) {
  memset(lod, 0, sizeof *lod);
  if (nlevels < 1 || nlevels > 6)
    return tb_error_set(err, "lod", 0, "levels must be in [1, 6] (got %d)", nlevels);
  if (base->ntet || base->ntri < 1)
    return tb_error_set(err, "lod", 0, "needs a closed triangle surface (no tets)");
  int L = lod->nlevels = nlevels;
  lod->tri = calloc((size_t)L, sizeof(int *)), lod->pair = calloc((size_t)L, sizeof(int *));
  lod->mid = calloc((size_t)L, sizeof(int *)), lod->out = calloc((size_t)L, sizeof(int *));
  lod->level_nv = calloc((size_t)L, sizeof(int)), lod->level_nf = calloc((size_t)L, sizeof(int));
  lod->first = calloc((size_t)L + 1, sizeof(int));
  if (!lod->tri || !lod->pair || !lod->mid || !lod->out || !lod->level_nv || !lod->level_nf ||
      !lod->first)
    goto oom;
  tb_mesh cur = *base, next;
  int owned = 0; /* cur is ours to free (every level but the base) */
  for (int l = 0; l < L; l++) {
    tb_halfedge he;
    if (tb_halfedge_build(&he, cur.nv, cur.ntri, cur.tri, "lod", err)) {
      if (owned) tb_mesh_free(&cur);
      tb_lod_free(lod);
      return -1;
    }
    lod->level_nv[l] = cur.nv, lod->level_nf[l] = cur.ntri;
    lod->first[l + 1] = lod->first[l] + cur.ntri;
    lod->pair[l] = he.pair, lod->out[l] = he.out, he.pair = he.out = NULL;
    tb_halfedge_free(&he);
    lod->tri[l] = malloc(sizeof(int) * 3 * (size_t)cur.ntri);
    if (!lod->tri[l]) goto oom_cur;
    memcpy(lod->tri[l], cur.tri, sizeof(int) * 3 * (size_t)cur.ntri);
    if (l == L - 1) break;
    if (tb_butterfly(&cur, &next, &lod->mid[l], err)) {
      if (owned) tb_mesh_free(&cur);
      tb_lod_free(lod);
      return -1;
    }
    if (owned) tb_mesh_free(&cur);
    cur = next, owned = 1;
  }
  int nv = lod->nv = cur.nv, nall = lod->first[L];
  lod->rest = malloc(sizeof(tb_vec3) * (size_t)nv),
  lod->ends = malloc(sizeof(int) * 2 * (size_t)nv);
  lod->state = calloc((size_t)nall, 1), lod->active = calloc((size_t)nv, 1);
  int cap = lod->level_nf[L - 1]; /* a leaf of level l draws <= 2 <= 4^(L-1-l) triangles */
  lod->out_tri = malloc(sizeof(int) * 3 * (size_t)cap);
  lod->out_leaf = malloc(sizeof(int) * (size_t)cap);
  if (!lod->rest || !lod->ends || !lod->state || !lod->active || !lod->out_tri || !lod->out_leaf)
    goto oom_cur;
  memcpy(lod->rest, cur.x, sizeof(tb_vec3) * (size_t)nv);
  if (owned) tb_mesh_free(&cur);
  for (int i = 0; i < 2 * nv; i++) lod->ends[i] = -1;
  for (int l = 0; l + 1 < L; l++)
    for (int h = 0; h < 3 * lod->level_nf[l]; h++) {
      int v = lod->mid[l][h];
      lod->ends[2 * v] = lod->tri[l][h],
                    lod->ends[2 * v + 1] = lod->tri[l][h - h % 3 + (h + 1) % 3];
    }
  tb_lod_reset(lod);
  return 0;
oom_cur:
  if (owned) tb_mesh_free(&cur);
oom:
  tb_lod_free(lod);
  return tb_error_set(err, "lod", 0, "out of memory");
}

void tb_lod_reset(tb_lod *lod) {
  memset(lod->state, TB_LOD_OFF, (size_t)lod->first[lod->nlevels]);
  memset(lod->state, TB_LOD_LEAF, (size_t)lod->level_nf[0]);
  tb_lod_surface(lod);
}

int tb_lod_level(const tb_lod *lod, int id, int *f) {
  int l = 0;
  while (l + 1 < lod->nlevels && id >= lod->first[l + 1]) l++;
  *f = id - lod->first[l];
  return l;
}

static unsigned char *st(tb_lod *lod, int l, int f) { return &lod->state[lod->first[l] + f]; }

/* The face of level l across half-edge k of face f. */
static int across(const tb_lod *lod, int l, int f, int k) { return lod->pair[l][3 * f + k] / 3; }

/* Edges of leaf f (level l) whose neighbour is split: their midpoints hang. */
static int hanging(tb_lod *lod, int l, int f) {
  int n = 0;
  for (int k = 0; k < 3; k++) n += *st(lod, l, across(lod, l, f, k)) == TB_LOD_SPLIT;
  return n;
}

int tb_lod_refine(tb_lod *lod, int l, int f) {
  if (l + 1 >= lod->nlevels || *st(lod, l, f) != TB_LOD_LEAF) return 0;
  int n = 0;
  /* balance: every edge neighbour of f's level must be on before f splits */
  for (int k = 0; k < 3; k++) {
    int g = across(lod, l, f, k);
    if (*st(lod, l, g) == TB_LOD_OFF) n += tb_lod_refine(lod, l - 1, g / 4);
  }
  *st(lod, l, f) = TB_LOD_SPLIT;
  for (int c = 0; c < 4; c++) *st(lod, l + 1, 4 * f + c) = TB_LOD_LEAF;
  n++;
  /* closure: a neighbour leaf now hanging on two or three edges splits too */
  for (int k = 0; k < 3; k++) {
    int g = across(lod, l, f, k);
    if (*st(lod, l, g) == TB_LOD_LEAF && hanging(lod, l, g) >= 2) n += tb_lod_refine(lod, l, g);
  }
  return n;
}

int tb_lod_coarsen(tb_lod *lod, int l, int f) {
  if (l + 1 >= lod->nlevels || *st(lod, l, f) != TB_LOD_SPLIT) return 0;
  for (int c = 0; c < 4; c++)
    if (*st(lod, l + 1, 4 * f + c) != TB_LOD_LEAF) return 0;
  /* balance: no child may touch a split face of its level across f's
   * border (it would then touch faces two levels finer than f) */
  for (int c = 0; c < 3; c++) /* the corner children 0..2 hold f's border */
    for (int k = 0; k < 3; k++) {
      int g = across(lod, l + 1, 4 * f + c, k);
      if (g / 4 != f && *st(lod, l + 1, g) == TB_LOD_SPLIT) return 0;
    }
  /* closure: as a leaf, f may hang on one edge at most */
  if (hanging(lod, l, f) >= 2) return 0;
  *st(lod, l, f) = TB_LOD_LEAF;
  for (int c = 0; c < 4; c++) *st(lod, l + 1, 4 * f + c) = TB_LOD_OFF;
  return 1;
}

void tb_lod_apply(tb_lod *lod, const unsigned char *depth) {
  memset(lod->state, TB_LOD_OFF, (size_t)lod->first[lod->nlevels]);
  memset(lod->state, TB_LOD_LEAF, (size_t)lod->level_nf[0]);
  /* a split's balance can turn on faces around a vertex passed already (of
   * its level or, splitting a coarser neighbour, of a level done): the
   * levels are swept again until a sweep splits nothing, so the surface is
   * the least one holding every request, whatever the vertices' order */
  int split;
  do {
    split = 0;
    for (int l = 0; l + 1 < lod->nlevels; l++)
      for (int v = 0; v < lod->level_nv[l]; v++) {
        if (depth[v] <= l) continue;
        int h0 = lod->out[l][v], h = h0; /* the faces of level l around v */
        do {
          split += tb_lod_refine(lod, l, h / 3);
          h = lod->pair[l][h - h % 3 + (h + 2) % 3];
        } while (h != h0);
      }
  } while (split);
  tb_lod_surface(lod);
}

static void emit(tb_lod *lod, int a, int b, int c, int leaf) {
  int *t = lod->out_tri + 3 * lod->ntri;
  t[0] = a, t[1] = b, t[2] = c;
  lod->out_leaf[lod->ntri++] = leaf;
  lod->active[a] = lod->active[b] = lod->active[c] = 1;
}

void tb_lod_surface(tb_lod *lod) {
  lod->ntri = 0;
  memset(lod->active, 0, (size_t)lod->nv);
  for (int l = 0; l < lod->nlevels; l++)
    for (int f = 0; f < lod->level_nf[l]; f++) {
      if (*st(lod, l, f) != TB_LOD_LEAF) continue;
      const int *t = lod->tri[l] + 3 * f;
      int k = 0;
      while (k < 3 && *st(lod, l, across(lod, l, f, k)) != TB_LOD_SPLIT) k++;
      if (k == 3) {
        emit(lod, t[0], t[1], t[2], lod->first[l] + f);
        continue;
      }
      /* the transition band: split at the one hanging midpoint m of edge
       * (a, b), c opposite (closure leaves no leaf with two) */
      int a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3], m = lod->mid[l][3 * f + k];
      emit(lod, a, m, c, lod->first[l] + f);
      emit(lod, m, b, c, lod->first[l] + f);
    }
}
