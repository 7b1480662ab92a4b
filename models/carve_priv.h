/* Private to the tet models that cut by removing elements (pbd.c,
 * fem_corot.c): SOFA's carving. While the blade moves, every tet its
 * newest sweep touches is removed; the surface is the boundary of the tets
 * left, and the node masses are lumped again from them. The model removes
 * the tets from its own arrays; carve.c finds them, rebuilds the surface
 * and the masses. */
#ifndef TB_CARVE_PRIV_H
#define TB_CARVE_PRIV_H

#include "tb_model.h"

typedef struct tb_carve {
  int nv;
  tb_vec3 *X;     /* rest positions: the boundary's orientation and the masses */
  int ntri, *tri; /* the boundary of the tets left, oriented outward */
  unsigned long version;
  int have_last; /* the blade's position at the last MOVE is last */
  tb_vec3 last;
  int last_n;           /* that MOVE's path length */
  int removed;          /* tets removed since BEGIN */
  unsigned char *alive; /* per tet of the rest mesh, in its order: 0 once removed */
  int *scratch;         /* 4 ntet ints: the tets left, packed */
  double *mass;         /* nv: masses lumped from the tets left */
} tb_carve;

/* From the model's rest mesh (copied); err names the model on failure. */
int tb_carve_init(tb_carve *c, const tb_mesh *mesh, const char *model, tb_error *err);
void tb_carve_free(tb_carve *c);

/* One cut event: BEGIN and END mark the cut; at MOVE, hit[t] = 1 for each of
 * the nt tets (4 node indices each, in the model's order; alive[t] == 0
 * skips t, alive NULL: all alive) that the sheet the blade swept since the
 * last MOVE touches (the folded plane from the blade's last position through
 * the path's new points to its position now, cutting/tb_fold.h) at the
 * positions x. Returns the number hit (0 at BEGIN and END), or -1 with err
 * on a bad event. */
int tb_carve_event(tb_carve *c, const tb_cut_event *ev, const tb_vec3 *x, const int *tet, int nt,
                   const unsigned char *alive, unsigned char *hit, tb_error *err);

/* After the model removed tets: the boundary of the nt tets left (alive as
 * above) and their lumped masses into c->mass (density * volume / 4 per
 * node, or node_mass > 0 for all; a node left without tets keeps the mass
 * it had); removed: how many went. Returns 0, or -1 out of memory. */
int tb_carve_update(tb_carve *c, const int *tet, int nt, const unsigned char *alive, int removed,
                    double density, double node_mass, tb_error *err);

/* The surface over the positions x (all nv nodes; those of no tet unused). */
tb_surface tb_carve_surface(const tb_carve *c, const tb_vec3 *x);
/* END's stats: tets removed by the cut, the surface's pieces. */
void tb_carve_stats(const tb_carve *c, tb_cut_stats *st);

#endif
