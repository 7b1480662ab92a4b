/* The reference libraries' triangle tests as entries of collision's table
 * (reference/tb_oracles.h). */
#include "tb_oracles.h"

static const tb_tritri_method oracles[] = {
    {"fcl", "FCL 0.7 Intersect<double>::intersect_Triangle", tb_tritri_fcl, 0},
    {"bullet", "Bullet 3.24 (double) btPrimitiveTriangle clip method, margin 0", tb_tritri_bullet,
     0},
    {"cgal", "CGAL do_intersect, exact predicates kernel: the oracle", tb_tritri_cgal, 1},
};

void tb_oracles_register(void) {
  for (int i = 0; i < (int)(sizeof oracles / sizeof oracles[0]); i++)
    (void)tb_tritri_register(&oracles[i]);
}
