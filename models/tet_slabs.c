/* A schedule for parallel Gauss-Seidel sweeps over a tet mesh in four
 * phases instead of one per colour (tet_colour.c needs 20 to 50 colours on
 * a TetGen mesh, each a barrier).
 *
 * The nodes are cut into B slabs of equal node counts along the mesh's
 * longest extent. A tet whose nodes all lie in slab b is interior to b; one
 * whose nodes lie in slabs b and b + 1 belongs to the interface b; any other
 * (it spans three slabs or more: slabs thinner than a tet) is "wide". A
 * sweep runs four phases, each a set of tasks that share no node, a task's
 * tets in a fixed order on one thread:
 *   0. the B slabs' interiors;
 *   1. the even interfaces 0, 2, 4, ... (interface b touches only slabs b
 *      and b + 1, so b and b + 2 share no node);
 *   2. the odd interfaces;
 *   3. the wide tets, one task.
 * The order in which every node sees its tets is fixed by the mesh alone,
 * so a sweep gives the same bits on any thread count. Each task also lists
 * its conflicts, the tasks of other phases sharing a node with it: a
 * thread may start a task once those have run (pbd_solve.c), without a
 * barrier between phases. B is the largest
 * power of two up to max_slabs with at least TETS_PER_SLAB tets a slab and
 * at most 1 in WIDE_SHARE tets wide: B = 1 (one task, no threads) for small
 * meshes.
 *
 * The nodes are numbered again, slab by slab, in the spatial order
 * (tb_spatial_order) within a slab: a task reads and writes one compact
 * range of memory, and two threads rarely share a cache line. */
#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "tb_model.h"

#define TETS_PER_SLAB 600 /* below this, a task costs little beside its synchronisation */
#define WIDE_SHARE 200

typedef struct keyed {
  double key;
  int id;
} keyed;

static int by_key(const void *pa, const void *pb) {
  const keyed *a = pa, *b = pb;
  if (a->key != b->key) return a->key < b->key ? -1 : 1;
  return (a->id > b->id) - (a->id < b->id);
}

static int by_u64(const void *pa, const void *pb) {
  uint64_t a = *(const uint64_t *)pa, b = *(const uint64_t *)pb;
  return (a > b) - (a < b);
}

/* The task of tet e (mesh node ids) given each node's slab, in 0 .. 2B - 1:
 * interiors 0 .. B-1, then interfaces by phase (even, odd), then wide. */
static int task_of(const int *e, const int *slab, int B) {
  int lo = slab[e[0]], hi = lo;
  for (int k = 1; k < 4; k++) {
    int b = slab[e[k]];
    lo = b < lo ? b : lo, hi = b > hi ? b : hi;
  }
  if (hi == lo) return lo;
  if (hi > lo + 1) return 2 * B - 1;
  int neven = B / 2; /* interfaces 0, 2, .. B - 2 */
  return B + (lo % 2 == 0 ? lo / 2 : neven + lo / 2);
}

/* Within each task, the tets by a greedy colouring local to the task (first
 * fit in the order above, at most 64 colours; a tet that finds none takes
 * the last, sharing nodes), then as before. One thread runs a task, so the
 * colours need no barrier: they only keep consecutive tets from sharing a
 * node, so that the processor overlaps one tet's projection with the next
 * instead of waiting for the positions the last one wrote. key: nt scratch. */
static int colour_tasks(const tb_mesh *mesh, tb_tet_slabs *s, uint64_t *key) {
  uint64_t *used = calloc((size_t)(mesh->nv ? mesh->nv : 1), sizeof *used);
  int *was = malloc(sizeof(int) * (size_t)(mesh->ntet ? mesh->ntet : 1));
  if (!used || !was) return free(used), free(was), -1;
  memcpy(was, s->order, sizeof(int) * (size_t)mesh->ntet);
  for (int q = 0; q < s->ntasks; q++) {
    int a = s->task[q], b = s->task[q + 1];
    for (int k = a; k < b; k++) {
      const int *e = mesh->tet + 4 * was[k];
      uint64_t busy = used[e[0]] | used[e[1]] | used[e[2]] | used[e[3]];
      int c = 0;
      while (c < 63 && (busy >> c & 1)) c++;
      for (int j = 0; j < 4; j++) used[e[j]] |= (uint64_t)1 << c;
      key[k] = (uint64_t)c << 32 | (uint64_t)(k - a);
    }
    for (int k = a; k < b; k++) /* the next task starts with no colour used */
      for (int j = 0; j < 4; j++) used[mesh->tet[4 * was[k] + j]] = 0;
    qsort(key + a, (size_t)(b - a), sizeof *key, by_u64);
    for (int k = a; k < b; k++) s->order[k] = was[a + (int)(key[k] & 0xffffffffu)];
  }
  free(used), free(was);
  return 0;
}

/* The conflicts: for each task, the tasks of the other phases that share
 * a node with it (tasks of one phase share none), by ascending task. */
static int conflicts(const tb_mesh *mesh, tb_tet_slabs *s) {
  const int nv = mesh->nv, nq = s->ntasks;
  int *owner = malloc(sizeof(int) * 4 * (size_t)(nv ? nv : 1));
  int *stamp = malloc(sizeof(int) * (size_t)nq);
  s->conf_start = calloc((size_t)nq + 1, sizeof(int));
  if (!owner || !stamp || !s->conf_start) return free(owner), free(stamp), -1;
  for (int i = 0; i < 4 * nv; i++) owner[i] = -1;
  for (int ph = 0; ph < 4; ph++)
    for (int q = s->phase[ph]; q < s->phase[ph + 1]; q++)
      for (int k = s->task[q]; k < s->task[q + 1]; k++)
        for (int j = 0; j < 4; j++) owner[4 * mesh->tet[4 * s->order[k] + j] + ph] = q;
  for (int pass = 0; pass < 2; pass++) {
    for (int q = 0; q < nq; q++) stamp[q] = -1;
    for (int q = 0; q < nq; q++) {
      int n = 0, ph = tb_tet_slabs_phase(s, q);
      for (int k = s->task[q]; k < s->task[q + 1]; k++)
        for (int j = 0; j < 4; j++)
          for (int p = 0; p < 4; p++) {
            int c = owner[4 * mesh->tet[4 * s->order[k] + j] + p];
            if (p == ph || c < 0 || stamp[c] == q) continue;
            stamp[c] = q;
            if (pass) s->conf[s->conf_start[q] + n] = c;
            n++;
          }
      if (!pass) s->conf_start[q + 1] = s->conf_start[q] + n;
    }
    if (!pass) {
      s->conf = malloc(sizeof(int) * (size_t)(s->conf_start[nq] ? s->conf_start[nq] : 1));
      if (!s->conf) return free(owner), free(stamp), -1;
    }
  }
  for (int q = 0; q < nq; q++) /* ascending (insertion: a few each) */
    for (int a = s->conf_start[q] + 1; a < s->conf_start[q + 1]; a++)
      for (int b = a; b > s->conf_start[q] && s->conf[b - 1] > s->conf[b]; b--) {
        int t = s->conf[b];
        s->conf[b] = s->conf[b - 1], s->conf[b - 1] = t;
      }
  free(owner), free(stamp);
  return 0;
}

int tb_tet_slabs_phase(const tb_tet_slabs *s, int q) {
  int ph = 0;
  while (ph < 3 && q >= s->phase[ph + 1]) ph++;
  return ph;
}

int tb_tet_slabs_build(const tb_mesh *mesh, int max_slabs, tb_tet_slabs *s, tb_error *err) {
  memset(s, 0, sizeof *s);
  const int nv = mesh->nv, nt = mesh->ntet;
  if (nv >= 1 << 28 || nt >= 1 << 28) /* the tets' sort keys hold 28 bits of each */
    return tb_error_set(err, "slabs", 0, "%d nodes and %d tets: at most 2^28 - 1 each", nv, nt);
  size_t V = (size_t)(nv ? nv : 1), T = (size_t)(nt ? nt : 1);
  keyed *k = malloc(sizeof *k * V);
  int *slab = malloc(sizeof(int) * V), *rank = malloc(sizeof(int) * V);
  int *count = NULL;
  uint64_t *key = malloc(sizeof *key * T);
  s->old = malloc(sizeof(int) * V), s->nw = malloc(sizeof(int) * V);
  s->order = malloc(sizeof(int) * T);
  if (!k || !slab || !rank || !key || !s->old || !s->nw || !s->order) goto oom;
  /* the longest extent */
  double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
  for (int i = 0; i < nv; i++)
    for (int a = 0; a < 3; a++) {
      double c = tb_comp(mesh->x[i], a);
      lo[a] = c < lo[a] ? c : lo[a], hi[a] = c > hi[a] ? c : hi[a];
    }
  int axis = 0;
  for (int a = 1; a < 3; a++)
    if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  for (int i = 0; i < nv; i++) k[i].key = tb_comp(mesh->x[i], axis), k[i].id = i;
  qsort(k, (size_t)nv, sizeof *k, by_key);
  for (int r = 0; r < nv; r++) rank[k[r].id] = r;
  /* B: the largest power of two that keeps slabs full and wide tets rare */
  int B = 1;
  while (2 * B <= max_slabs && (long)nt >= (long)TETS_PER_SLAB * 2 * B) B *= 2;
  for (; B > 1; B /= 2) {
    for (int i = 0; i < nv; i++) slab[i] = (int)((long)rank[i] * B / nv);
    long wide = 0;
    for (int t = 0; t < nt; t++) wide += task_of(mesh->tet + 4 * t, slab, B) == 2 * B - 1;
    if (wide * WIDE_SHARE <= nt) break;
  }
  if (B == 1)
    for (int i = 0; i < nv; i++) slab[i] = 0;
  s->nslabs = B;
  s->ntasks = B == 1 ? 1 : 2 * B;
  s->task = calloc((size_t)s->ntasks + 1, sizeof(int));
  count = calloc((size_t)s->ntasks + 1, sizeof(int));
  if (!s->task || !count) goto oom;
  /* nodes: slab by slab, the spatial order within (counted by slab, B <=
   * ntasks, then placed in the spatial order) */
  if (tb_spatial_order(mesh->x, nv, rank)) goto oom;
  for (int i = 0; i < nv; i++) count[slab[i] + 1]++;
  for (int b = 0; b < B; b++) count[b + 1] += count[b];
  for (int r = 0; r < nv; r++) {
    int i = rank[r], n = count[slab[i]]++;
    s->old[n] = i, s->nw[i] = n;
  }
  memset(count, 0, sizeof(int) * ((size_t)s->ntasks + 1));
  /* tets: by task, then by smallest (new) node, then by id */
  for (int t = 0; t < nt; t++) {
    const int *e = mesh->tet + 4 * t;
    int task = B == 1 ? 0 : task_of(e, slab, B), m = s->nw[e[0]];
    for (int j = 1; j < 4; j++) m = s->nw[e[j]] < m ? s->nw[e[j]] : m;
    key[t] = (uint64_t)task << 56 | (uint64_t)m << 28 | (uint64_t)t;
    count[task + 1]++;
  }
  qsort(key, (size_t)nt, sizeof *key, by_u64);
  for (int t = 0; t < nt; t++) s->order[t] = (int)(key[t] & ((1u << 28) - 1));
  for (int q = 0; q < s->ntasks; q++) s->task[q + 1] = s->task[q] + count[q + 1];
  if (colour_tasks(mesh, s, key)) goto oom;
  /* phases over the tasks */
  if (B == 1) {
    s->phase[1] = s->phase[2] = s->phase[3] = s->phase[4] = 1;
  } else {
    s->phase[1] = B, s->phase[2] = B + B / 2, s->phase[3] = 2 * B - 1, s->phase[4] = 2 * B;
  }
  if (conflicts(mesh, s)) goto oom;
  free(k), free(slab), free(rank), free(key), free(count);
  return 0;
oom:
  free(k), free(slab), free(rank), free(key), free(count);
  tb_tet_slabs_free(s);
  return tb_error_set(err, "slabs", 0, "out of memory (%d nodes, %d tets)", nv, nt);
}

void tb_tet_slabs_free(tb_tet_slabs *s) {
  free(s->old), free(s->nw), free(s->order), free(s->task), free(s->conf_start), free(s->conf);
  memset(s, 0, sizeof *s);
}
