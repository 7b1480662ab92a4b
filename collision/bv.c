/* Bounding volumes and their overlap tests (thesis §4.3.3 part 2): sphere-
 * sphere by centre distance against the radius sum, AABB-AABB by interval
 * overlap on the three axes, sphere-AABB by the squared distance from the
 * centre to its closest point on the box (Ericson 2005, §5.1.3, the code the
 * thesis quotes). All volumes are closed: touching counts as overlapping.
 * The sphere of a box (§4.3.3 part 1) is centred at the box centre with
 * radius half the diagonal, rounded outward so that it truly contains the
 * box and the two tests above never reject touching volumes by rounding. */
#include <float.h>

#include "tb_bvh.h"

int tb_sphere_sphere(tb_sphere a, tb_sphere b) {
  double dx = a.c.x - b.c.x, dy = a.c.y - b.c.y, dz = a.c.z - b.c.z, r = a.r + b.r;
  return dx * dx + dy * dy + dz * dz <= r * r;
}

int tb_sphere_aabb(tb_sphere s, tb_aabb b) {
  double d = 0.0, v;
  /* excess of each coordinate outside the box's slab */
  v = s.c.x < b.lo.x ? b.lo.x - s.c.x : (s.c.x > b.hi.x ? s.c.x - b.hi.x : 0.0);
  d += v * v;
  v = s.c.y < b.lo.y ? b.lo.y - s.c.y : (s.c.y > b.hi.y ? s.c.y - b.hi.y : 0.0);
  d += v * v;
  v = s.c.z < b.lo.z ? b.lo.z - s.c.z : (s.c.z > b.hi.z ? s.c.z - b.hi.z : 0.0);
  d += v * v;
  return d <= s.r * s.r;
}

int tb_aabb_aabb(tb_aabb a, tb_aabb b) {
  return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y &&
         a.lo.z <= b.hi.z && b.lo.z <= a.hi.z;
}

/* Rounding: the centre (lo + hi) / 2 is off by at most eps/2 |c_i| per axis
 * (plus half the smallest subnormal when it underflows), so the corner
 * distance from it is at most the true half diagonal plus eps |c|_1; the
 * half diagonal itself and the tests' own arithmetic carry a few eps of
 * relative error, covered by the relative 1e-12. Extents outside
 * [2^-450, 2^450] are first scaled by an exact power of two so that their
 * squares neither underflow nor overflow (a box 1e-200 wide gets a sphere
 * 1e-200 wide, not 0); boxes within TB_COORD_MAX (core/tb_mesh.h) of
 * ordinary size never take that branch. The radius is at least
 * TB_SPHERE_MIN_R (2^-500): then r^2 and every radius sum squared in the
 * tests are normal numbers (never a subnormal or zero), and squared
 * distances that underflow only err towards "overlap". Within TB_COORD_MAX
 * no square or sum of squares of the tests overflows. */
tb_sphere tb_aabb_sphere(tb_aabb b) {
  tb_sphere s;
  s.c = tb_v3(0.5 * (b.lo.x + b.hi.x), 0.5 * (b.lo.y + b.hi.y), 0.5 * (b.lo.z + b.hi.z));
  double dx = b.hi.x - b.lo.x, dy = b.hi.y - b.lo.y, dz = b.hi.z - b.lo.z;
  double m = dx > dy ? dx : dy;
  m = m > dz ? m : dz;
  double h;
  if (m > 0x1p-450 && m < 0x1p450) {
    h = 0.5 * sqrt(dx * dx + dy * dy + dz * dz);
  } else { /* exact scaling: 2^600 brings 2^-1074 to 2^-474, 2^-600 2^1024 to 2^424 */
    double up = m < 1 ? 0x1p600 : 0x1p-600;
    dx *= up, dy *= up, dz *= up;
    h = 0.5 * sqrt(dx * dx + dy * dy + dz * dz) / up;
  }
  double slack = DBL_EPSILON * (fabs(s.c.x) + fabs(s.c.y) + fabs(s.c.z));
  s.r = (h + slack) * (1.0 + 1e-12);
  if (s.r < TB_SPHERE_MIN_R) s.r = TB_SPHERE_MIN_R;
  return s;
}
