/* The reference solution (tb_reference.h): static equilibrium of a
 * hyperelastic body by Newton's method (Bonet & Wood, Nonlinear Continuum
 * Mechanics for FEA, 2nd ed., ch. 9: Newton-Raphson with line search and
 * incremental loading).
 *
 * Discretisation: 10-node tets built from the linear mesh, one midside node
 * per unique edge (node nv + edge index of tb_mesh_edges), or the linear
 * tets themselves (def->quadratic = 0); elements and materials in
 * ref_element.c, assembly and CHOLMOD in ref_system.c.
 *
 * Loads, at load factor lambda in (0, 1]: lambda (consistent body force
 * rho g int N_a dV + the given nodal forces at the corner nodes), and the
 * prescribed displacements lambda (fixed_x - X) of the held components. A
 * midside node whose two ends both hold a component holds it too, at the
 * mean of the ends' prescribed values.
 *
 * Newton iteration at lambda: K du = -(f_int - f_ext) - K_fp g on the free
 * dofs, where g is what the prescribed dofs still lack of their target
 * (the step moves them by g), then a backtracking line search (alpha =
 * 1, 1/2, ... down to 1/1024): a trial with det F <= 0 anywhere is
 * rejected; a step that moves prescribed dofs is otherwise taken whole;
 * else a trial is accepted when the residual norm falls,
 * |r(alpha)| <= (1 - 1e-4 alpha) |r(0)|, or the energy (Armijo, 1e-4 of
 * the slope r . du) does.
 * Convergence: prescribed dofs at their targets, |r|_2 <= tol * s with
 * s = |(lambda f_ext on the free dofs, f_int on the prescribed dofs)|_2
 * (the applied loads and the support forces: the forces in balance), and
 * the last increment |alpha du|_inf <= sqrt(tol) |u|_inf (the linear
 * material needs no increment check: one Newton step solves it).
 * Failure of a load step (no convergence in max_iter iterations, the line
 * search failing, det F <= 0, an indefinite tangent even shifted) restores
 * the last equilibrium and halves the load increment, down to 1/1024 of
 * the initial 1/load_steps; the increment doubles again after two
 * successes. A tangent that is not positive definite is refactorised once
 * with 1e-2 of its mean diagonal added; at the rest state (the first
 * factorisation) it is an error instead: the supports leave rigid-body
 * motion free.
 * Statistics: iterations counts every Newton iteration (failed load steps
 * too), load_steps the accepted load increments. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ref_priv.h"
#include "report/tb_results.h"

void openblas_set_num_threads(int num_threads);

#define TB_REF_MAX_HALVINGS 10

tb_ref_def tb_ref_default_def(void) {
  tb_ref_def d;
  memset(&d, 0, sizeof d);
  d.material = TB_REF_NEOHOOKE;
  d.E = 3000, d.nu = 0.3;
  d.quadratic = 1;
  d.tol = 1e-9;
  d.max_iter = 30;
  d.load_steps = 0;
  return d;
}

typedef struct solver {
  const tb_ref_problem *p;
  tb_ref_def def;
  int nv, nn, ne, npe, ntet;
  int *edges;     /* 2 ne */
  tb_vec3 *X;     /* nn rest positions */
  int *elem;      /* npe per tet */
  tb_vec3 *gl;    /* 4 per tet */
  double *vol;    /* per tet */
  int *free_of;   /* 3 nn */
  double *target; /* 3 nn: prescribed displacement at lambda = 1 (held dofs) */
  tb_vec3 *fext;  /* nn, at lambda = 1 */
  tb_vec3 *u, *u_save, *u_trial, *fint, *f_trial, *dir, *gap, *kgap;
  double *rhs, *du;
  tb_ref_sys sys;
  int factored, iterations, steps;
  double rel, jmin;
} solver;

static void solver_free(solver *S) {
  tb_ref_sys_free(&S->sys);
  free(S->edges), free(S->X), free(S->elem), free(S->gl), free(S->vol), free(S->free_of);
  free(S->target), free(S->fext), free(S->u), free(S->u_save), free(S->u_trial), free(S->fint);
  free(S->f_trial), free(S->dir), free(S->gap), free(S->kgap), free(S->rhs), free(S->du);
}

static double comp(tb_vec3 v, int c) { return c == 0 ? v.x : (c == 1 ? v.y : v.z); }
static double *pcomp(tb_vec3 *v, int c) { return c == 0 ? &v->x : (c == 1 ? &v->y : &v->z); }

static int check_input(const tb_ref_problem *p, const tb_ref_def *d, tb_error *err) {
  if (!p || !p->mesh || !d) return tb_error_set(err, "reference", 0, "no problem or no settings");
  const tb_mesh *m = p->mesh;
  if (m->nv < 4 || m->ntet < 1 || !m->x || !m->tet)
    return tb_error_set(err, "reference", 0, "needs a tet mesh (nodes %d, tets %d)", m->nv,
                        m->ntet);
  if (m->nv > 20000000 || m->ntet > 20000000)
    return tb_error_set(err, "reference", 0, "mesh too large");
  if (d->material < TB_REF_NEOHOOKE || d->material > TB_REF_LINEAR)
    return tb_error_set(err, "reference", 0, "unknown material %d", d->material);
  if (!(d->E > 0) || !isfinite(d->E) || !(d->nu > -1) || !(d->nu < 0.5))
    return tb_error_set(err, "reference", 0, "needs E > 0 and -1 < nu < 0.5 (E %g, nu %g)", d->E,
                        d->nu);
  if (!(d->tol > 0) || !(d->tol < 1) || d->max_iter < 1 || d->load_steps < 0 ||
      d->load_steps > 1000000)
    return tb_error_set(err, "reference", 0,
                        "needs 0 < tol < 1, max_iter >= 1, 0 <= load_steps <= 1e6 (tol %g, "
                        "max_iter %d, load_steps %d)",
                        d->tol, d->max_iter, d->load_steps);
  if (!isfinite(p->density) || !tb_isfinite3(p->gravity))
    return tb_error_set(err, "reference", 0, "density and gravity must be finite");
  for (int i = 0; i < m->nv; i++) {
    if (!tb_isfinite3(m->x[i]))
      return tb_error_set(err, "reference", 0, "node %d has a non-finite position", i);
    if (p->force && !tb_isfinite3(p->force[i]))
      return tb_error_set(err, "reference", 0, "node %d has a non-finite force", i);
  }
  for (int t = 0; t < 4 * m->ntet; t++)
    if (m->tet[t] < 0 || m->tet[t] >= m->nv)
      return tb_error_set(err, "reference", 0, "tet %d has node index %d outside [0, %d)", t / 4,
                          m->tet[t], m->nv);
  if (p->nfixed <= 0)
    return tb_error_set(err, "reference", 0,
                        "no supports (%d prescribed nodes): the stiffness is singular, rigid-body "
                        "motion is free",
                        p->nfixed);
  if (p->nfixed > m->nv || !p->fixed || !p->fixed_x)
    return tb_error_set(err, "reference", 0, "bad prescribed nodes (%d of %d, lists %s)", p->nfixed,
                        m->nv, p->fixed && p->fixed_x ? "given" : "missing");
  for (int i = 0; i < p->nfixed; i++) {
    if (p->fixed[i] < 0 || p->fixed[i] >= m->nv || (i && p->fixed[i] <= p->fixed[i - 1]))
      return tb_error_set(err, "reference", 0,
                          "prescribed node %d (entry %d) out of range or not strictly ascending",
                          p->fixed[i], i);
    if (!tb_isfinite3(p->fixed_x[i]))
      return tb_error_set(err, "reference", 0, "prescribed node %d has a non-finite position",
                          p->fixed[i]);
    if (p->fixed_mask && (p->fixed_mask[i] < 0 || p->fixed_mask[i] > 7))
      return tb_error_set(err, "reference", 0, "prescribed node %d has mask %d (bits 1, 2, 4)",
                          p->fixed[i], p->fixed_mask[i]);
  }
  return 0;
}

static int find_edge(const int *edges, int ne, int a, int b) {
  if (a > b) {
    int t = a;
    a = b, b = t;
  }
  int lo = 0, hi = ne - 1;
  while (lo <= hi) {
    int mid = (lo + hi) / 2, ea = edges[2 * mid], eb = edges[2 * mid + 1];
    if (ea < a || (ea == a && eb < b))
      lo = mid + 1;
    else if (ea > a || eb > b)
      hi = mid - 1;
    else
      return mid;
  }
  return -1;
}

/* Nodes, elements, rest geometry, dofs and loads. */
static int setup(solver *S, tb_error *err) {
  const tb_ref_problem *p = S->p;
  const tb_mesh *m = p->mesh;
  S->nv = m->nv, S->ntet = m->ntet, S->npe = S->def.quadratic ? 10 : 4;
  if (S->def.quadratic) {
    S->ne = tb_mesh_edges(m, &S->edges);
    if (S->ne < 0) return tb_error_set(err, "reference", 0, "out of memory");
  }
  int nv = S->nv, nn = S->nn = nv + S->ne, npe = S->npe, nt = S->ntet;
  size_t n = (size_t)nn;
  S->X = malloc(sizeof(tb_vec3) * n);
  S->elem = malloc(sizeof(int) * (size_t)nt * npe);
  S->gl = malloc(sizeof(tb_vec3) * 4 * (size_t)nt);
  S->vol = malloc(sizeof(double) * (size_t)nt);
  S->free_of = malloc(sizeof(int) * 3 * n);
  S->target = calloc(3 * n, sizeof(double));
  S->fext = calloc(n, sizeof(tb_vec3));
  S->u = calloc(n, sizeof(tb_vec3));
  S->u_save = malloc(sizeof(tb_vec3) * n);
  S->u_trial = malloc(sizeof(tb_vec3) * n);
  S->fint = malloc(sizeof(tb_vec3) * n);
  S->f_trial = malloc(sizeof(tb_vec3) * n);
  S->dir = malloc(sizeof(tb_vec3) * n);
  S->gap = malloc(sizeof(tb_vec3) * n);
  S->kgap = malloc(sizeof(tb_vec3) * n);
  int *used = calloc((size_t)nv, sizeof(int)), *held = calloc(3 * n, sizeof(int));
  if (!S->X || !S->elem || !S->gl || !S->vol || !S->free_of || !S->target || !S->fext || !S->u ||
      !S->u_save || !S->u_trial || !S->fint || !S->f_trial || !S->dir || !S->gap || !S->kgap ||
      !used || !held) {
    free(used), free(held);
    return tb_error_set(err, "reference", 0, "out of memory");
  }
  memcpy(S->X, m->x, sizeof(tb_vec3) * (size_t)nv);
  for (int e = 0; e < S->ne; e++)
    S->X[nv + e] = tb_scale(tb_add(m->x[S->edges[2 * e]], m->x[S->edges[2 * e + 1]]), 0.5);
  for (int t = 0; t < nt; t++) {
    const int *c = m->tet + 4 * t;
    int *e = S->elem + (size_t)t * npe;
    for (int a = 0; a < 4; a++) e[a] = c[a], used[c[a]] = 1;
    for (int k = 0; npe == 10 && k < 6; k++)
      e[4 + k] =
          nv + find_edge(S->edges, S->ne, c[tb_ref_edge_ends[k][0]], c[tb_ref_edge_ends[k][1]]);
    S->vol[t] = tb_ref_tet_grads(m->x[c[0]], m->x[c[1]], m->x[c[2]], m->x[c[3]], S->gl + 4 * t);
    if (!(S->vol[t] > 0)) {
      free(used), free(held);
      return tb_error_set(err, "reference", 0,
                          "tet %d (nodes %d %d %d %d) is inverted or degenerate in the rest mesh "
                          "(volume %g)",
                          t, c[0], c[1], c[2], c[3], S->vol[t]);
    }
  }
  for (int i = 0; i < nv; i++)
    if (!used[i]) {
      free(used), free(held);
      return tb_error_set(err, "reference", 0, "node %d belongs to no tet", i);
    }
  free(used);
  /* prescribed dofs and their targets */
  for (int i = 0; i < p->nfixed; i++) {
    int k = p->fixed[i], mask = p->fixed_mask ? p->fixed_mask[i] : 7;
    for (int c = 0; c < 3; c++)
      if (mask & (1 << c))
        held[3 * k + c] = 1, S->target[3 * k + c] = comp(p->fixed_x[i], c) - comp(m->x[k], c);
  }
  for (int e = 0; e < S->ne; e++) {
    int a = S->edges[2 * e], b = S->edges[2 * e + 1], k = nv + e;
    for (int c = 0; c < 3; c++)
      if (held[3 * a + c] && held[3 * b + c])
        held[3 * k + c] = 1,
                     S->target[3 * k + c] = 0.5 * (S->target[3 * a + c] + S->target[3 * b + c]);
  }
  S->sys.nfree = 0;
  for (int d = 0; d < 3 * nn; d++) S->free_of[d] = held[d] ? -1 : S->sys.nfree++;
  free(held);
  /* loads: rho g int N_a dV by the element rule, plus the nodal forces */
  tb_ref_rule r = tb_ref_rule_for(npe);
  tb_vec3 body = tb_scale(p->gravity, p->density);
  for (int t = 0; t < nt && (body.x != 0 || body.y != 0 || body.z != 0); t++)
    for (int q = 0; q < r.n; q++) {
      double N[10];
      tb_ref_shape(npe, r.L[q], N);
      const int *e = S->elem + (size_t)t * npe;
      for (int a = 0; a < npe; a++)
        S->fext[e[a]] = tb_madd(S->fext[e[a]], r.w[q] * S->vol[t] * N[a], body);
    }
  if (p->force)
    for (int i = 0; i < nv; i++) S->fext[i] = tb_add(S->fext[i], p->force[i]);
  S->rhs = malloc(sizeof(double) * (S->sys.nfree ? (size_t)S->sys.nfree : 1));
  S->du = malloc(sizeof(double) * (S->sys.nfree ? (size_t)S->sys.nfree : 1));
  if (!S->rhs || !S->du) return tb_error_set(err, "reference", 0, "out of memory");
  return 0;
}

/* |r|_2 over the free dofs, the scale s of the header, max |gap| (gap set). */
static void residual(solver *S, const tb_vec3 *f, double lam, double *rnorm, double *scale,
                     double *gapmax) {
  double r2 = 0, s2 = 0, g = 0;
  for (int n = 0; n < S->nn; n++)
    for (int c = 0; c < 3; c++) {
      int d = 3 * n + c;
      double fi = comp(f[n], c), fe = lam * comp(S->fext[n], c);
      if (S->free_of[d] >= 0) {
        r2 += (fi - fe) * (fi - fe), s2 += fe * fe;
        *pcomp(&S->gap[n], c) = 0;
      } else {
        s2 += fi * fi;
        double gd = lam * S->target[d] - comp(S->u[n], c);
        *pcomp(&S->gap[n], c) = gd;
        g = fmax(g, fabs(gd));
      }
    }
  *rnorm = sqrt(r2), *scale = sqrt(s2), *gapmax = g;
}

static double potential(const solver *S, double w, const tb_vec3 *u, double lam) {
  double e = w;
  for (int n = 0; n < S->nn; n++) e -= lam * tb_dot(S->fext[n], u[n]);
  return e;
}

/* Newton at load factor lam from S->u. 0: converged, 1: failed (why), -1: error. */
static int newton(solver *S, double lam, char *why, size_t cap, tb_error *err) {
  tb_ref_sys *sys = &S->sys;
  int bad = -1, nn = S->nn, linear = S->def.material == TB_REF_LINEAR;
  double w, jmin, last_inc = INFINITY;
  if (tb_ref_sys_eval(sys, S->u, S->fint, &w, 0, &jmin, &bad)) {
    snprintf(why, cap, "tet %d inverted (det F %g)", bad, jmin);
    return 1;
  }
  for (int it = 0, steps = 0;; it++) {
    tb_progress_tick("reference solve: load %.2f, Newton iteration %d", lam, it + 1);
    double rnorm, scale, gapmax;
    residual(S, S->fint, lam, &rnorm, &scale, &gapmax);
    S->rel = scale > 0 ? rnorm / scale : (rnorm > 0 ? INFINITY : 0.0);
    S->jmin = jmin;
    double uinf = 0;
    for (int n = 0; n < nn; n++)
      uinf = fmax(uinf, fmax(fabs(S->u[n].x), fmax(fabs(S->u[n].y), fabs(S->u[n].z))));
    if (gapmax == 0 && S->rel <= S->def.tol &&
        (linear || steps == 0 || last_inc <= sqrt(S->def.tol) * uinf))
      return 0;
    if (it == S->def.max_iter) {
      snprintf(why, cap, "no convergence in %d Newton iterations (relative residual %.3g)", it,
               S->rel);
      return 1;
    }
    S->iterations++;
    double w0 = potential(S, w, S->u, lam);
    if (sys->nfree > 0) {
      if (tb_ref_sys_eval(sys, S->u, S->fint, &w, 1, &jmin, &bad)) {
        snprintf(why, cap, "tet %d inverted (det F %g)", bad, jmin);
        return 1;
      }
      int node, rc = tb_ref_sys_factor(sys, 0.0, &node, err);
      if (rc == 1 && !S->factored)
        return tb_error_set(err, "reference", 0,
                            "stiffness singular or not positive definite at the rest state (at "
                            "node %d): the supports leave rigid-body motion free",
                            node);
      if (rc == 1) {
        double shift = 1e-2 * tb_ref_sys_mean_diag(sys);
        rc = tb_ref_sys_factor(sys, shift, &node, err);
        if (rc == 1) {
          snprintf(why, cap,
                   "tangent not positive definite at node %d, even shifted by %.3g (buckling or "
                   "too large a load increment)",
                   node, shift);
          return 1;
        }
      }
      if (rc < 0) return -1;
      S->factored = 1;
      tb_ref_sys_mul(sys, S->gap, S->kgap);
      for (int n = 0; n < nn; n++)
        for (int c = 0; c < 3; c++) {
          int j = S->free_of[3 * n + c];
          if (j >= 0)
            S->rhs[j] = lam * comp(S->fext[n], c) - comp(S->fint[n], c) - comp(S->kgap[n], c);
        }
      if (tb_ref_sys_solve(sys, S->rhs, S->du, err)) return -1;
    }
    double slope = 0, dinf = 0;
    for (int n = 0; n < nn; n++)
      for (int c = 0; c < 3; c++) {
        int j = S->free_of[3 * n + c];
        double dv = j >= 0 ? S->du[j] : comp(S->gap[n], c);
        *pcomp(&S->dir[n], c) = dv;
        if (j >= 0) slope += (comp(S->fint[n], c) - lam * comp(S->fext[n], c)) * dv;
        dinf = fmax(dinf, fabs(dv));
      }
    /* backtracking line search */
    double alpha = 1, wt = 0;
    for (;;) {
      for (int n = 0; n < nn; n++) S->u_trial[n] = tb_madd(S->u[n], alpha, S->dir[n]);
      if (alpha == 1)
        for (int d = 0; d < 3 * nn; d++)
          if (S->free_of[d] < 0) *pcomp(&S->u_trial[d / 3], d % 3) = lam * S->target[d];
      int ok = tb_ref_sys_eval(sys, S->u_trial, S->f_trial, &wt, 0, &jmin, &bad) == 0;
      if (ok && gapmax > 0) break;
      if (ok) {
        double rt, st, gt;
        residual(S, S->f_trial, lam, &rt, &st, &gt);
        if (rt <= (1 - 1e-4 * alpha) * rnorm || rt <= 0.1 * S->def.tol * scale ||
            potential(S, wt, S->u_trial, lam) <= w0 + 1e-4 * alpha * slope)
          break;
      }
      alpha *= 0.5;
      if (alpha < 1.0 / 1024) {
        if (!ok)
          snprintf(why, cap, "tet %d inverts (det F %.3g) along every Newton step tried", bad,
                   jmin);
        else
          snprintf(why, cap, "line search found no decrease (relative residual %.3g)", S->rel);
        return 1;
      }
    }
    tb_vec3 *t = S->u;
    S->u = S->u_trial, S->u_trial = t;
    t = S->fint, S->fint = S->f_trial, S->f_trial = t;
    w = wt, steps++, last_inc = alpha * dinf;
  }
}

/* Reactions at the prescribed corners: f_int - f_ext on their held
 * components plus half of each held midside component between two of them. */
static int reactions(const solver *S, tb_vec3 *R) {
  const tb_ref_problem *p = S->p;
  int *slot = malloc(sizeof(int) * (size_t)S->nv);
  if (!slot) return -1;
  for (int i = 0; i < S->nv; i++) slot[i] = -1;
  for (int i = 0; i < p->nfixed; i++) R[i] = tb_v3(0, 0, 0), slot[p->fixed[i]] = i;
  for (int n = 0; n < S->nn; n++)
    for (int c = 0; c < 3; c++) {
      if (S->free_of[3 * n + c] >= 0) continue;
      double r = comp(S->fint[n], c) - comp(S->fext[n], c);
      if (n < S->nv) {
        *pcomp(&R[slot[n]], c) += r;
      } else {
        int e = n - S->nv;
        *pcomp(&R[slot[S->edges[2 * e]]], c) += 0.5 * r;
        *pcomp(&R[slot[S->edges[2 * e + 1]]], c) += 0.5 * r;
      }
    }
  free(slot);
  return 0;
}

static tb_ref_solution *make_solution(solver *S, tb_error *err) {
  tb_ref_solution *s = calloc(1, sizeof *s);
  if (!s) goto oom;
  s->nv = S->nv, s->nn = S->nn, s->ntet = S->ntet, s->npe = S->npe;
  s->nfixed = S->p->nfixed;
  s->iterations = S->iterations, s->load_steps = S->steps;
  s->residual = S->rel, s->jmin = S->jmin;
  s->X = malloc(sizeof(tb_vec3) * (size_t)S->nv);
  s->x = malloc(sizeof(tb_vec3) * (size_t)S->nv);
  s->reaction = malloc(sizeof(tb_vec3) * (size_t)s->nfixed);
  if (!s->X || !s->x || !s->reaction) goto oom;
  /* hand over the arrays the sampler needs */
  s->elem = S->elem, s->gl = S->gl, s->u = S->u;
  S->elem = NULL, S->gl = NULL, S->u = NULL;
  memcpy(s->X, S->X, sizeof(tb_vec3) * (size_t)S->nv);
  for (int i = 0; i < S->nv; i++) s->x[i] = tb_add(S->X[i], s->u[i]);
  for (int i = 0; i < s->nfixed; i++) { /* exactly where prescribed */
    int k = S->p->fixed[i], mask = S->p->fixed_mask ? S->p->fixed_mask[i] : 7;
    for (int c = 0; c < 3; c++)
      if (mask & (1 << c)) *pcomp(&s->x[k], c) = comp(S->p->fixed_x[i], c);
  }
  if (reactions(S, s->reaction)) goto oom;
  if (tb_ref_grid_build(s, err)) {
    tb_ref_free(s);
    return NULL;
  }
  return s;
oom:
  tb_ref_free(s);
  tb_error_set(err, "reference", 0, "out of memory");
  return NULL;
}

tb_ref_solution *tb_ref_solve(const tb_ref_problem *p, const tb_ref_def *def, tb_error *err) {
  if (check_input(p, def, err)) return NULL;
  openblas_set_num_threads(1); /* deterministic, and the reference runs alone */
  solver S;
  memset(&S, 0, sizeof S);
  S.p = p, S.def = *def;
  S.def.quadratic = def->quadratic != 0;
  tb_ref_solution *sol = NULL;
  if (setup(&S, err)) goto done;
  tb_ref_sys *sys = &S.sys;
  sys->mat.kind = def->material;
  tb_lame(def->E, def->nu, &sys->mat.lambda, &sys->mat.mu);
  sys->nn = S.nn, sys->ntet = S.ntet, sys->npe = S.npe;
  sys->elem = S.elem, sys->gl = S.gl, sys->vol = S.vol, sys->free_of = S.free_of;
  if (tb_ref_sys_init(sys, err)) goto done;
  double d0 = 1.0 / (def->load_steps > 0 ? def->load_steps : 1), d = d0, lam = 0;
  int good = 0;
  char why[256];
  while (lam < 1) {
    double lt = 1 - lam <= d * (1 + 1e-9) ? 1.0 : lam + d;
    memcpy(S.u_save, S.u, sizeof(tb_vec3) * (size_t)S.nn);
    int rc = newton(&S, lt, why, sizeof why, err);
    if (rc < 0) goto done;
    if (rc == 0) {
      lam = lt, S.steps++;
      if (++good >= 2 && d < d0) d = fmin(2 * d, d0), good = 0;
      continue;
    }
    memcpy(S.u, S.u_save, sizeof(tb_vec3) * (size_t)S.nn);
    d *= 0.5, good = 0;
    if (d < d0 / (1 << TB_REF_MAX_HALVINGS)) {
      tb_error_set(err, "reference", 0,
                   "Newton failed at load factor %.6g of 1 after halving the load increment %d "
                   "times: %s",
                   lt, TB_REF_MAX_HALVINGS, why);
      goto done;
    }
  }
  /* the final forces at the accepted state (S.fint is current) */
  sol = make_solution(&S, err);
done:
  solver_free(&S);
  return sol;
}

void tb_ref_free(tb_ref_solution *s) {
  if (!s) return;
  free(s->X), free(s->elem), free(s->gl), free(s->u), free(s->x), free(s->reaction);
  free(s->cell_start), free(s->cell_tet);
  free(s);
}

const tb_vec3 *tb_ref_positions(const tb_ref_solution *s) { return s->x; }
const tb_vec3 *tb_ref_reactions(const tb_ref_solution *s) { return s->reaction; }
double tb_ref_min_jacobian(const tb_ref_solution *s) { return s->jmin; }

void tb_ref_stats(const tb_ref_solution *s, int *iterations, int *load_steps, double *residual) {
  if (iterations) *iterations = s->iterations;
  if (load_steps) *load_steps = s->load_steps;
  if (residual) *residual = s->residual;
}
