/* The assembled system of the reference solver: a 3x3 node-block pattern
 * from the element connectivity (all nodes), the internal forces, energy
 * and tangent summed over the elements (ref_element.c), and the CHOLMOD
 * matrix over the free dofs only (upper triangle, symmetric), analysed once
 * and refactorised for every Newton iteration (supernodal L L^T, CHOLMOD's
 * default orderings, BLAS on one thread: set by tb_ref_solve).
 * A singular or indefinite matrix is reported, not factorised silently:
 * CHOLMOD flags pivots <= 0, and a pivot below TB_REF_PIVOT_TOL of its
 * diagonal entry (a singular matrix that rounding made slightly positive,
 * e.g. rigid-body motions left free) counts as singular too. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ref_priv.h"

#define TB_REF_PIVOT_TOL 1e-10

static void quiet_handler(int status, const char *file, int line, const char *msg) {
  (void)status, (void)file, (void)line, (void)msg;
}

static int cmp_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

static int find_block(const tb_ref_sys *s, int n, int m) {
  int lo = s->row[n], hi = s->row[n + 1] - 1;
  while (lo <= hi) {
    int mid = (lo + hi) / 2;
    if (s->col[mid] < m)
      lo = mid + 1;
    else if (s->col[mid] > m)
      hi = mid - 1;
    else
      return mid;
  }
  return -1;
}

/* Node rows: every pair of nodes sharing an element. */
static int build_blocks(tb_ref_sys *s, tb_error *err) {
  int nn = s->nn, npe = s->npe, ne = s->ntet * npe;
  int *inc_start = calloc((size_t)nn + 1, sizeof(int)), *inc = malloc(sizeof(int) * (size_t)ne);
  int *mark = malloc(sizeof(int) * (size_t)nn);
  s->row = calloc((size_t)nn + 1, sizeof(int));
  s->diag = malloc(sizeof(int) * (size_t)nn);
  if (!inc_start || !inc || !mark || !s->row || !s->diag) goto oom;
  for (int k = 0; k < ne; k++) inc_start[s->elem[k] + 1]++;
  for (int n = 0; n < nn; n++) inc_start[n + 1] += inc_start[n];
  for (int k = 0; k < ne; k++) inc[inc_start[s->elem[k]]++] = k / npe;
  for (int n = nn; n > 0; n--) inc_start[n] = inc_start[n - 1];
  inc_start[0] = 0;
  /* two passes: count the distinct neighbours, then list them */
  for (int pass = 0; pass < 2; pass++) {
    for (int n = 0; n < nn; n++) mark[n] = -1;
    for (int n = 0; n < nn; n++) {
      int c = 0;
      for (int k = inc_start[n]; k < inc_start[n + 1]; k++) {
        const int *e = s->elem + (size_t)inc[k] * npe;
        for (int a = 0; a < npe; a++)
          if (mark[e[a]] != n) {
            mark[e[a]] = n;
            if (pass) s->col[s->row[n] + c] = e[a];
            c++;
          }
      }
      if (!pass) {
        if (s->row[n] > INT_MAX / 9 - c) goto big;
        s->row[n + 1] = s->row[n] + c;
      }
    }
    if (!pass) {
      size_t nb = (size_t)s->row[nn];
      s->col = malloc(sizeof(int) * (nb ? nb : 1));
      s->kb = malloc(sizeof(double) * 9 * (nb ? nb : 1));
      if (!s->col || !s->kb) goto oom;
    }
  }
  for (int n = 0; n < nn; n++) {
    qsort(s->col + s->row[n], (size_t)(s->row[n + 1] - s->row[n]), sizeof(int), cmp_int);
    s->diag[n] = find_block(s, n, n);
  }
  s->elem_blk = malloc(sizeof(int) * (size_t)ne * npe);
  if (!s->elem_blk) goto oom;
  for (int t = 0; t < s->ntet; t++) {
    const int *e = s->elem + (size_t)t * npe;
    for (int a = 0; a < npe; a++)
      for (int b = 0; b < npe; b++)
        s->elem_blk[((size_t)t * npe + a) * npe + b] = find_block(s, e[a], e[b]);
  }
  free(inc_start), free(inc), free(mark);
  return 0;
big:
  free(inc_start), free(inc), free(mark);
  return tb_error_set(err, "reference", 0, "mesh too large for the int CHOLMOD interface");
oom:
  free(inc_start), free(inc), free(mark);
  return tb_error_set(err, "reference", 0, "out of memory");
}

/* Upper triangle over the free dofs; column J = dof 3n + c, rows 3m + r,
 * m <= n: K(3m+r, 3n+c) = K(3n+c, 3m+r) = block (n,m) entry (c,r). */
static int build_matrix(tb_ref_sys *s, tb_error *err) {
  const int *fr = s->free_of;
  size_t nnz = 0;
  for (int n = 0; n < s->nn; n++)
    for (int c = 0; c < 3; c++) {
      if (fr[3 * n + c] < 0) continue;
      for (int q = s->row[n]; q <= s->diag[n]; q++) {
        int m = s->col[q];
        for (int r = 0; r < 3 && !(m == n && r > c); r++) nnz += fr[3 * m + r] >= 0;
      }
    }
  if (nnz > (size_t)INT_MAX - 1)
    return tb_error_set(err, "reference", 0, "mesh too large for the int CHOLMOD interface");
  size_t nf = (size_t)s->nfree;
  s->A = cholmod_allocate_sparse(nf, nf, nnz ? nnz : 1, 1, 1, 1, CHOLMOD_REAL, &s->cc);
  s->a_src = malloc(sizeof(int) * (nnz ? nnz : 1));
  s->a_diag = malloc(sizeof(int) * (nf ? nf : 1));
  if (!s->A || !s->a_src || !s->a_diag) return tb_error_set(err, "reference", 0, "out of memory");
  int *Ap = s->A->p, *Ai = s->A->i, p = 0;
  for (int n = 0; n < s->nn; n++)
    for (int c = 0; c < 3; c++) {
      int j = fr[3 * n + c];
      if (j < 0) continue;
      Ap[j] = p;
      for (int q = s->row[n]; q <= s->diag[n]; q++) {
        int m = s->col[q];
        for (int r = 0; r < 3 && !(m == n && r > c); r++) {
          int i = fr[3 * m + r];
          if (i < 0) continue;
          Ai[p] = i;
          s->a_src[p] = 9 * q + 3 * c + r;
          if (i == j) s->a_diag[j] = p;
          p++;
        }
      }
    }
  Ap[nf] = p;
  return 0;
}

int tb_ref_sys_init(tb_ref_sys *s, tb_error *err) {
  cholmod_start(&s->cc);
  s->started = 1;
  s->cc.print = 0;
  s->cc.error_handler = quiet_handler;
  s->cc.supernodal = CHOLMOD_SUPERNODAL;
  s->cc.final_asis = 1;
  if (build_blocks(s, err)) return -1;
  if (s->nfree == 0) return 0; /* everything prescribed: nothing to solve */
  if (build_matrix(s, err)) return -1;
  s->L = cholmod_analyze(s->A, &s->cc);
  if (!s->L || s->cc.status < CHOLMOD_OK)
    return tb_error_set(err, "reference", 0, "CHOLMOD analysis failed (status %d)", s->cc.status);
  return 0;
}

void tb_ref_sys_free(tb_ref_sys *s) {
  if (s->started) {
    cholmod_free_factor(&s->L, &s->cc);
    cholmod_free_sparse(&s->A, &s->cc);
    cholmod_finish(&s->cc);
  }
  free(s->row), free(s->col), free(s->diag), free(s->kb), free(s->elem_blk);
  free(s->a_src), free(s->a_diag);
  memset(s, 0, sizeof *s);
}

int tb_ref_sys_eval(tb_ref_sys *s, const tb_vec3 *u, tb_vec3 *fint, double *energy, int want_k,
                    double *jmin, int *bad) {
  int npe = s->npe, nd = 3 * npe;
  memset(fint, 0, sizeof(tb_vec3) * (size_t)s->nn);
  if (want_k) memset(s->kb, 0, sizeof(double) * 9 * (size_t)s->row[s->nn]);
  *energy = 0, *jmin = INFINITY;
  double K[30 * 30];
  for (int t = 0; t < s->ntet; t++) {
    const int *e = s->elem + (size_t)t * npe;
    tb_vec3 ue[10], fe[10];
    for (int a = 0; a < npe; a++) ue[a] = u[e[a]], fe[a] = tb_v3(0, 0, 0);
    if (want_k) memset(K, 0, sizeof(double) * (size_t)(nd * nd));
    if (tb_ref_element(&s->mat, npe, s->gl + 4 * (size_t)t, s->vol[t], ue, energy, fe,
                       want_k ? K : NULL, jmin)) {
      *bad = t;
      return -1;
    }
    for (int a = 0; a < npe; a++) fint[e[a]] = tb_add(fint[e[a]], fe[a]);
    if (!want_k) continue;
    const int *blk = s->elem_blk + (size_t)t * npe * npe;
    for (int a = 0; a < npe; a++)
      for (int b = 0; b < npe; b++) {
        double *dst = s->kb + 9 * (size_t)blk[a * npe + b];
        for (int i = 0; i < 3; i++)
          for (int k = 0; k < 3; k++) dst[3 * i + k] += K[(3 * a + i) * nd + 3 * b + k];
      }
  }
  return 0;
}

void tb_ref_sys_mul(const tb_ref_sys *s, const tb_vec3 *v, tb_vec3 *y) {
  for (int n = 0; n < s->nn; n++) {
    double y0 = 0, y1 = 0, y2 = 0;
    for (int q = s->row[n]; q < s->row[n + 1]; q++) {
      const double *k = s->kb + 9 * (size_t)q;
      tb_vec3 w = v[s->col[q]];
      y0 += k[0] * w.x + k[1] * w.y + k[2] * w.z;
      y1 += k[3] * w.x + k[4] * w.y + k[5] * w.z;
      y2 += k[6] * w.x + k[7] * w.y + k[8] * w.z;
    }
    y[n] = tb_v3(y0, y1, y2);
  }
}

double tb_ref_sys_mean_diag(const tb_ref_sys *s) {
  double sum = 0;
  int cnt = 0;
  for (int n = 0; n < s->nn; n++)
    for (int c = 0; c < 3; c++)
      if (s->free_of[3 * n + c] >= 0) sum += s->kb[9 * (size_t)s->diag[n] + 4 * c], cnt++;
  return cnt ? sum / cnt : 0.0;
}

/* The pivot of permuted column k: L_kk^2 (L L^T) or D_kk (L D L^T). */
static double pivot(const cholmod_factor *L, int k, int *sup) {
  const double *Lx = L->x;
  if (L->is_super) {
    const int *super = L->super, *pi = L->pi, *px = L->px;
    while (super[*sup + 1] <= k) (*sup)++;
    int nsrow = pi[*sup + 1] - pi[*sup], jj = k - super[*sup];
    double d = Lx[px[*sup] + jj * nsrow + jj];
    return d * d;
  }
  double d = Lx[((const int *)L->p)[k]];
  return L->is_ll ? d * d : d;
}

int tb_ref_sys_factor(tb_ref_sys *s, double shift, int *node, tb_error *err) {
  const int *Ap = s->A->p;
  double *Ax = s->A->x;
  for (int p = 0; p < Ap[s->nfree]; p++) Ax[p] = s->kb[s->a_src[p]];
  for (int j = 0; j < s->nfree; j++) Ax[s->a_diag[j]] += shift;
  *node = -1;
  int ok = cholmod_factorize(s->A, s->L, &s->cc);
  s->factorisations++;
  const int *perm = s->L->Perm;
  int col = -1;
  if (s->cc.status == CHOLMOD_NOT_POSDEF || s->L->minor < s->L->n) {
    col = (int)s->L->minor;
  } else if (!ok || s->cc.status < CHOLMOD_OK) {
    return tb_error_set(err, "reference", 0, "CHOLMOD factorisation failed (status %d)",
                        s->cc.status);
  } else {
    int sup = 0;
    for (int k = 0; k < (int)s->L->n && col < 0; k++) {
      double d = pivot(s->L, k, &sup), a = Ax[s->a_diag[perm ? perm[k] : k]];
      if (!(d > TB_REF_PIVOT_TOL * fabs(a))) col = k;
    }
  }
  if (col < 0) return 0;
  int dof = col < (int)s->L->n && perm ? perm[col] : col;
  for (int d = 0; d < 3 * s->nn && dof >= 0; d++)
    if (s->free_of[d] == dof) {
      *node = d / 3;
      break;
    }
  return 1;
}

int tb_ref_sys_solve(tb_ref_sys *s, const double *b, double *x, tb_error *err) {
  cholmod_dense *B =
      cholmod_allocate_dense((size_t)s->nfree, 1, (size_t)s->nfree, CHOLMOD_REAL, &s->cc);
  if (!B) return tb_error_set(err, "reference", 0, "out of memory");
  memcpy(B->x, b, sizeof(double) * (size_t)s->nfree);
  cholmod_dense *X = cholmod_solve(CHOLMOD_A, s->L, B, &s->cc);
  cholmod_free_dense(&B, &s->cc);
  if (!X)
    return tb_error_set(err, "reference", 0, "CHOLMOD solve failed (status %d)", s->cc.status);
  memcpy(x, X->x, sizeof(double) * (size_t)s->nfree);
  cholmod_free_dense(&X, &s->cc);
  return 0;
}
