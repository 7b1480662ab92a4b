/* Coulomb friction of a body resting on a rigid ground, in position form
 * (Macklin et al. 2014, "Unified particle physics for real-time
 * applications", §6.1), shared by the scene driver's contact response
 * (scenes/contact.c) and the position-based models, which project the
 * ground inside their solve (models/pbd_solve.c).
 *
 * A contact node's normal correction d over the step stands for the normal
 * impulse m d / dt, its tangential displacement dx_t for the impulse friction
 * must remove to hold it. Static friction is decided for the contact as a
 * whole, |sum m dx_t| <= mu_s sum m d, so an elastic body whose contact
 * nodes carry unequal loads sticks or slips as a rigid block does: on a
 * slope of angle a under gravity the sums are M g sin a dt^2 and
 * M g cos a dt^2 from rest, and the body sticks exactly when tan a <= mu_s.
 * When it slips, each node's dx_t is shortened by mu_k d (kinetic). */
#include <math.h>

#include "tb_model.h"

int tb_ground_friction(const tb_ground *g, int n, const int *ids, const double *depth,
                       const tb_vec3 *x0, const double *mass, tb_vec3 *p, double *keep) {
  tb_vec3 T = tb_v3(0, 0, 0);
  double N = 0;
  for (int k = 0; k < n; k++) {
    int i = ids[k];
    tb_vec3 dx = tb_sub(p[k], x0[i]);
    T = tb_madd(T, mass[i], tb_madd(dx, -tb_dot(dx, g->n), g->n));
    N += mass[i] * depth[k];
  }
  int stick = tb_len(T) <= g->mu_s * N;
  for (int k = 0; k < n; k++) {
    tb_vec3 dx = tb_sub(p[k], x0[ids[k]]);
    tb_vec3 dxt = tb_madd(dx, -tb_dot(dx, g->n), g->n);
    double lt = tb_len(dxt), kp = 0;
    if (!stick && lt > 0) kp = fmax(0, 1 - g->mu_k * depth[k] / lt);
    p[k] = tb_madd(p[k], kp - 1, dxt);
    keep[k] = kp;
  }
  return stick;
}
