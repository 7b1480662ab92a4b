/* The reference libraries' triangle-triangle tests (reference/ref_fcl.cpp,
 * ref_bullet.cpp, ref_cgal.cpp), with the semantics of collision's
 * tb_tritri_fn, and their entries in collision's table of tests. CGAL's is
 * exact: the oracle every other test is judged against. */
#ifndef TB_ORACLES_H
#define TB_ORACLES_H

#include "collision/tb_tritri.h"

int tb_tritri_fcl(const tb_vec3 p[3],
                  const tb_vec3 q[3]); /* fcl::detail::Intersect::intersect_Triangle */
int tb_tritri_bullet(const tb_vec3 p[3],
                     const tb_vec3 q[3]); /* btPrimitiveTriangle clip method, margin 0 */
int tb_tritri_cgal(const tb_vec3 p[3],
                   const tb_vec3 q[3]); /* CGAL::do_intersect, exact predicates: the oracle */

/* Adds fcl, bullet and cgal to the table (tb_tritri_register), in that
 * order; a program calls it once at start-up (again: no change). */
void tb_oracles_register(void);

#endif
