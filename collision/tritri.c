/* The table of triangle-triangle tests: ours (adding one is one file and one
 * entry here), then the ones registered at start-up (the reference
 * libraries' adapters, reference/tb_oracles.h). */
#include <string.h>

#include "tb_tritri.h"

#define MAX_METHODS 32

static tb_tritri_method methods[MAX_METHODS] = {
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
};
static int nmethods = 6; /* ours above */

const tb_tritri_method *tb_tritri_methods(int *count) {
  *count = nmethods;
  return methods;
}

int tb_tritri_register(const tb_tritri_method *m) {
  const tb_tritri_method *old = tb_tritri_find(m->name);
  if (old) return old->test == m->test ? 0 : -1;
  if (nmethods == MAX_METHODS || !m->test) return -1;
  methods[nmethods++] = *m;
  return 0;
}

const tb_tritri_method *tb_tritri_find(const char *name) {
  int n;
  const tb_tritri_method *m = tb_tritri_methods(&n);
  for (int i = 0; i < n; i++)
    if (!strcmp(m[i].name, name)) return &m[i];
  return NULL;
}
