/* The table of triangle-triangle tests: adding a method is one file and one
 * entry here. */
#include <string.h>

#include "tb_tritri.h"

static const tb_tritri_method methods[] = {
    {"moller", "Moller 1997, interval overlap on the planes' line", tb_tritri_moller, 0},
    {"yuhe", "Yu & He 2013 projection test (V and H projections), as in thesis 4.4.2",
     tb_tritri_yuhe, 0},
    {"improved", "the thesis's improved projection test (4.4.2, fig. 4.14 a-f)", tb_tritri_improved,
     0},
    {"guigue", "Devillers & Guigue 2002, double-precision orientation predicates", tb_tritri_guigue,
     0},
    {"guigue-exact", "Devillers & Guigue 2002 with exact predicates (Shewchuk 1997)",
     tb_tritri_guigue_exact, 1},
    {"exact", "ours: filtered exact predicates, degenerate triangles as segments/points",
     tb_tritri_exact, 1},
    {"fcl", "FCL 0.7 Intersect<double>::intersect_Triangle", tb_tritri_fcl, 0},
    {"bullet", "Bullet 3.24 (double) btPrimitiveTriangle clip method, margin 0", tb_tritri_bullet,
     0},
    {"cgal", "CGAL do_intersect, exact predicates kernel: the oracle", tb_tritri_cgal, 1},
};

const tb_tritri_method *tb_tritri_methods(int *count) {
  *count = (int)(sizeof methods / sizeof methods[0]);
  return methods;
}

const tb_tritri_method *tb_tritri_find(const char *name) {
  int n;
  const tb_tritri_method *m = tb_tritri_methods(&n);
  for (int i = 0; i < n; i++)
    if (!strcmp(m[i].name, name)) return &m[i];
  return NULL;
}
