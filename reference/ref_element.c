/* The element kernel of the reference solver: shape functions of the
 * 4-node and 10-node (quadratic, straight-sided) tets, quadrature, and the
 * hyperelastic stresses with their consistent tangents.
 *
 * Shapes (Zienkiewicz & Taylor, The FEM vol. 1, §8.8, barycentric L_i):
 * corner N_a = L_a (2 L_a - 1), midside of edge (i,j) N = 4 L_i L_j; the
 * linear tet N_a = L_a. The rest midside nodes sit at the edge midpoints, so
 * the isoparametric map is the affine map of the linear tet: dL_i/dX is
 * constant per tet and dN/dX follows from the chain rule.
 *
 * Quadrature (10-node tets): the fully symmetric 14-point rule of degree 5
 * with positive weights (two 4-point orbits, one 6-point orbit; e.g.
 * Walkington 2000, Jaskowiec & Sukumar 2020); its parameters were solved
 * from the moment equations to 40 digits and tests/test_reference.c checks
 * every monomial of degree <= 5. Degree 5 integrates the linear and StVK
 * element forces and tangents exactly (their integrands have degree <= 4 on
 * a quadratic tet), positive weights keep the tangent of a stable material
 * positive semi-definite. Linear tets: one centroid point (exact).
 *
 * Materials (Bonet & Wood, Nonlinear Continuum Mechanics for FEA, 2nd ed.,
 * §6.4-6.5), F = I + du/dX, J = det F, C = F^T F:
 *  - compressible Neo-Hookean psi = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2,
 *    P = mu (F - F^-T) + lambda ln J F^-T,
 *    dP_iJ/dF_kL = mu d_ik d_JL + (mu - lambda ln J) Fi_Jk Fi_Li + lambda Fi_Ji Fi_Lk
 *    (Fi = F^-1; from dF^-T = -F^-T dF^T F^-T and d ln J = F^-T : dF);
 *  - St Venant-Kirchhoff E = (C - I)/2, S = lambda tr E I + 2 mu E, P = F S,
 *    psi = mu E:E + lambda/2 (tr E)^2,
 *    dP_iJ/dF_kL = d_ik S_LJ + lambda F_iJ F_kL + mu (F_iL F_kJ + (F F^T)_ik d_JL);
 *  - linear (small strain) eps = sym(F - I), P = sigma = lambda tr eps I + 2 mu eps,
 *    dP_iJ/dF_kL = lambda d_iJ d_kL + mu (d_ik d_JL + d_iL d_Jk).
 * Element forces f_ai = sum_q w_q P_iJ dN_a/dX_J, tangent
 * K_(ai)(bk) = sum_q w_q dN_a/dX_J A_iJkL dN_b/dX_L. */
#include <math.h>
#include <string.h>

#include "ref_priv.h"

const int tb_ref_edge_ends[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};

/* 14-point degree-5 rule: orbits (a,a,a,1-3a) x2 and (b,b,1/2-b,1/2-b). */
#define TB_Q_A1 0.092735250310891226402
#define TB_Q_W1 0.073493043116361949544
#define TB_Q_A2 0.31088591926330060980
#define TB_Q_W2 0.11268792571801585080
#define TB_Q_B 0.045503704125649649492
#define TB_Q_C (0.5 - TB_Q_B)
#define TB_Q_W3 0.042546020777081466438

static const double q14_L[14][4] = {{1 - 3 * TB_Q_A1, TB_Q_A1, TB_Q_A1, TB_Q_A1},
                                    {TB_Q_A1, 1 - 3 * TB_Q_A1, TB_Q_A1, TB_Q_A1},
                                    {TB_Q_A1, TB_Q_A1, 1 - 3 * TB_Q_A1, TB_Q_A1},
                                    {TB_Q_A1, TB_Q_A1, TB_Q_A1, 1 - 3 * TB_Q_A1},
                                    {1 - 3 * TB_Q_A2, TB_Q_A2, TB_Q_A2, TB_Q_A2},
                                    {TB_Q_A2, 1 - 3 * TB_Q_A2, TB_Q_A2, TB_Q_A2},
                                    {TB_Q_A2, TB_Q_A2, 1 - 3 * TB_Q_A2, TB_Q_A2},
                                    {TB_Q_A2, TB_Q_A2, TB_Q_A2, 1 - 3 * TB_Q_A2},
                                    {TB_Q_B, TB_Q_B, TB_Q_C, TB_Q_C},
                                    {TB_Q_B, TB_Q_C, TB_Q_B, TB_Q_C},
                                    {TB_Q_B, TB_Q_C, TB_Q_C, TB_Q_B},
                                    {TB_Q_C, TB_Q_B, TB_Q_B, TB_Q_C},
                                    {TB_Q_C, TB_Q_B, TB_Q_C, TB_Q_B},
                                    {TB_Q_C, TB_Q_C, TB_Q_B, TB_Q_B}};
static const double q14_w[14] = {TB_Q_W1, TB_Q_W1, TB_Q_W1, TB_Q_W1, TB_Q_W2, TB_Q_W2, TB_Q_W2,
                                 TB_Q_W2, TB_Q_W3, TB_Q_W3, TB_Q_W3, TB_Q_W3, TB_Q_W3, TB_Q_W3};
static const double q1_L[1][4] = {{0.25, 0.25, 0.25, 0.25}};
static const double q1_w[1] = {1.0};

tb_ref_rule tb_ref_rule_for(int npe) {
  tb_ref_rule r;
  if (npe == 10)
    r.n = 14, r.L = q14_L, r.w = q14_w;
  else
    r.n = 1, r.L = q1_L, r.w = q1_w;
  return r;
}

void tb_ref_shape(int npe, const double L[4], double *N) {
  if (npe == 4) {
    for (int a = 0; a < 4; a++) N[a] = L[a];
    return;
  }
  for (int a = 0; a < 4; a++) N[a] = L[a] * (2 * L[a] - 1);
  for (int e = 0; e < 6; e++) N[4 + e] = 4 * L[tb_ref_edge_ends[e][0]] * L[tb_ref_edge_ends[e][1]];
}

void tb_ref_shape_grad(int npe, const double L[4], const tb_vec3 gl[4], tb_vec3 *G) {
  if (npe == 4) {
    for (int a = 0; a < 4; a++) G[a] = gl[a];
    return;
  }
  for (int a = 0; a < 4; a++) G[a] = tb_scale(gl[a], 4 * L[a] - 1);
  for (int e = 0; e < 6; e++) {
    int i = tb_ref_edge_ends[e][0], j = tb_ref_edge_ends[e][1];
    G[4 + e] = tb_scale(tb_add(tb_scale(gl[j], L[i]), tb_scale(gl[i], L[j])), 4.0);
  }
}

double tb_ref_tet_grads(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d, tb_vec3 gl[4]) {
  tb_vec3 e1 = tb_sub(b, a), e2 = tb_sub(c, a), e3 = tb_sub(d, a);
  double det = tb_dot(e1, tb_cross(e2, e3));
  if (!(det > 0)) return det / 6.0;
  /* rows of [e1 e2 e3]^-1 are the gradients of L1, L2, L3 */
  gl[1] = tb_scale(tb_cross(e2, e3), 1.0 / det);
  gl[2] = tb_scale(tb_cross(e3, e1), 1.0 / det);
  gl[3] = tb_scale(tb_cross(e1, e2), 1.0 / det);
  gl[0] = tb_scale(tb_add(tb_add(gl[1], gl[2]), gl[3]), -1.0);
  return det / 6.0;
}

static double det3(const double F[9]) {
  return F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
         F[2] * (F[3] * F[7] - F[4] * F[6]);
}

static void neo_hooke(const tb_ref_material *m, const double F[9], double J, double *psi,
                      double P[9], double *A) {
  double Fi[9]; /* F^-1 by cofactors */
  Fi[0] = (F[4] * F[8] - F[5] * F[7]) / J, Fi[1] = (F[2] * F[7] - F[1] * F[8]) / J;
  Fi[2] = (F[1] * F[5] - F[2] * F[4]) / J, Fi[3] = (F[5] * F[6] - F[3] * F[8]) / J;
  Fi[4] = (F[0] * F[8] - F[2] * F[6]) / J, Fi[5] = (F[2] * F[3] - F[0] * F[5]) / J;
  Fi[6] = (F[3] * F[7] - F[4] * F[6]) / J, Fi[7] = (F[1] * F[6] - F[0] * F[7]) / J;
  Fi[8] = (F[0] * F[4] - F[1] * F[3]) / J;
  double lnj = log(J), mu = m->mu, lam = m->lambda, i1 = 0;
  for (int k = 0; k < 9; k++) i1 += F[k] * F[k];
  *psi = 0.5 * mu * (i1 - 3) - mu * lnj + 0.5 * lam * lnj * lnj;
  for (int i = 0; i < 3; i++)
    for (int J_ = 0; J_ < 3; J_++)
      P[3 * i + J_] = mu * F[3 * i + J_] + (lam * lnj - mu) * Fi[3 * J_ + i];
  if (!A) return;
  double c = mu - lam * lnj;
  for (int i = 0; i < 3; i++)
    for (int J_ = 0; J_ < 3; J_++)
      for (int k = 0; k < 3; k++)
        for (int L = 0; L < 3; L++)
          A[9 * (3 * i + J_) + 3 * k + L] = (i == k && J_ == L ? mu : 0.0) +
                                            c * Fi[3 * J_ + k] * Fi[3 * L + i] +
                                            lam * Fi[3 * J_ + i] * Fi[3 * L + k];
}

static void stvk(const tb_ref_material *m, const double F[9], double *psi, double P[9], double *A) {
  double E[9], S[9], mu = m->mu, lam = m->lambda;
  for (int I = 0; I < 3; I++)
    for (int J_ = 0; J_ < 3; J_++) {
      double c = 0;
      for (int k = 0; k < 3; k++) c += F[3 * k + I] * F[3 * k + J_];
      E[3 * I + J_] = 0.5 * (c - (I == J_));
    }
  double tr = E[0] + E[4] + E[8], ee = 0;
  for (int k = 0; k < 9; k++) ee += E[k] * E[k];
  *psi = mu * ee + 0.5 * lam * tr * tr;
  for (int k = 0; k < 9; k++) S[k] = 2 * mu * E[k] + (k % 4 == 0 ? lam * tr : 0.0);
  for (int i = 0; i < 3; i++)
    for (int J_ = 0; J_ < 3; J_++)
      P[3 * i + J_] = F[3 * i] * S[J_] + F[3 * i + 1] * S[3 + J_] + F[3 * i + 2] * S[6 + J_];
  if (!A) return;
  double B[9]; /* F F^T */
  for (int i = 0; i < 3; i++)
    for (int k = 0; k < 3; k++)
      B[3 * i + k] =
          F[3 * i] * F[3 * k] + F[3 * i + 1] * F[3 * k + 1] + F[3 * i + 2] * F[3 * k + 2];
  for (int i = 0; i < 3; i++)
    for (int J_ = 0; J_ < 3; J_++)
      for (int k = 0; k < 3; k++)
        for (int L = 0; L < 3; L++)
          A[9 * (3 * i + J_) + 3 * k + L] =
              (i == k ? S[3 * L + J_] : 0.0) + lam * F[3 * i + J_] * F[3 * k + L] +
              mu * F[3 * i + L] * F[3 * k + J_] + (J_ == L ? mu * B[3 * i + k] : 0.0);
}

static void linear(const tb_ref_material *m, const double F[9], double *psi, double P[9],
                   double *A) {
  double e[9], mu = m->mu, lam = m->lambda;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) e[3 * i + j] = 0.5 * (F[3 * i + j] + F[3 * j + i]) - (i == j);
  double tr = e[0] + e[4] + e[8], ee = 0;
  for (int k = 0; k < 9; k++) ee += e[k] * e[k];
  *psi = mu * ee + 0.5 * lam * tr * tr;
  for (int k = 0; k < 9; k++) P[k] = 2 * mu * e[k] + (k % 4 == 0 ? lam * tr : 0.0);
  if (!A) return;
  for (int i = 0; i < 3; i++)
    for (int J_ = 0; J_ < 3; J_++)
      for (int k = 0; k < 3; k++)
        for (int L = 0; L < 3; L++)
          A[9 * (3 * i + J_) + 3 * k + L] = (i == J_ && k == L ? lam : 0.0) +
                                            (i == k && J_ == L ? mu : 0.0) +
                                            (i == L && J_ == k ? mu : 0.0);
}

int tb_ref_stress(const tb_ref_material *m, const double F[9], double *psi, double P[9], double *A,
                  double *J) {
  *J = det3(F);
  if (m->kind == TB_REF_LINEAR) {
    linear(m, F, psi, P, A);
    return 0;
  }
  if (!(*J > 0)) return -1;
  if (m->kind == TB_REF_STVK)
    stvk(m, F, psi, P, A);
  else
    neo_hooke(m, F, *J, psi, P, A);
  return 0;
}

int tb_ref_element(const tb_ref_material *m, int npe, const tb_vec3 gl[4], double vol,
                   const tb_vec3 *u, double *energy, tb_vec3 *f, double *K, double *jmin) {
  tb_ref_rule r = tb_ref_rule_for(npe);
  int nd = 3 * npe;
  for (int q = 0; q < r.n; q++) {
    tb_vec3 G[10];
    tb_ref_shape_grad(npe, r.L[q], gl, G);
    double F[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int a = 0; a < npe; a++) {
      double ua[3] = {u[a].x, u[a].y, u[a].z}, ga[3] = {G[a].x, G[a].y, G[a].z};
      for (int i = 0; i < 3; i++)
        for (int J_ = 0; J_ < 3; J_++) F[3 * i + J_] += ua[i] * ga[J_];
    }
    double psi, P[9], A[81], J;
    int rc = tb_ref_stress(m, F, &psi, P, K ? A : NULL, &J);
    if (J < *jmin) *jmin = J;
    if (rc) return -1;
    double w = r.w[q] * vol;
    *energy += w * psi;
    for (int a = 0; a < npe; a++) {
      double ga[3] = {G[a].x, G[a].y, G[a].z}, fa[3];
      for (int i = 0; i < 3; i++)
        fa[i] = w * (P[3 * i] * ga[0] + P[3 * i + 1] * ga[1] + P[3 * i + 2] * ga[2]);
      f[a] = tb_add(f[a], tb_v3(fa[0], fa[1], fa[2]));
    }
    if (!K) continue;
    /* T[b][3i+J][k] = sum_L A_iJkL G_bL, then K_(ai)(bk) += w G_aJ T */
    double T[10][27];
    for (int b = 0; b < npe; b++) {
      double gb[3] = {G[b].x, G[b].y, G[b].z};
      for (int iJ = 0; iJ < 9; iJ++)
        for (int k = 0; k < 3; k++) {
          const double *a9 = A + 9 * iJ + 3 * k;
          T[b][3 * iJ + k] = a9[0] * gb[0] + a9[1] * gb[1] + a9[2] * gb[2];
        }
    }
    for (int a = 0; a < npe; a++) {
      double ga[3] = {w * G[a].x, w * G[a].y, w * G[a].z};
      for (int b = 0; b < npe; b++) {
        const double *t = T[b];
        for (int i = 0; i < 3; i++) {
          double *row = K + (size_t)(3 * a + i) * nd + 3 * b;
          for (int k = 0; k < 3; k++)
            row[k] += ga[0] * t[9 * i + k] + ga[1] * t[9 * i + 3 + k] + ga[2] * t[9 * i + 6 + k];
        }
      }
    }
  }
  return 0;
}
