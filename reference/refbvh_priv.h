// Private to reference/ref_bvh_*.cpp (C++ only): the object behind the
// opaque tb_ref_bvh of tb_refbvh.h. Each library derives from it; the public
// C functions (in ref_bvh_fcl.cpp) check the input, build the right kind and
// turn every exception into a tb_error.
#ifndef TB_REFBVH_PRIV_H
#define TB_REFBVH_PRIV_H

extern "C" {
#include "tb_refbvh.h"
}

struct tb_ref_bvh {
  tb_ref_kind kind;
  int nv, ntri;
  tb_ref_bvh(tb_ref_kind k, int n_vertices, int n_triangles)
      : kind(k), nv(n_vertices), ntri(n_triangles) {}
  virtual ~tb_ref_bvh() {}
  // New positions for all nv vertices (already checked finite).
  virtual int update(const tb_vec3 *x, tb_error *err) = 0;
  // Pairs (i of this, j of b) appended to out; b has the same kind.
  virtual int collide(tb_ref_bvh &b, tb_pairlist *out, tb_error *err) = 0;
};

// The library's name for a kind ("fcl-aabb", ...), used in error messages.
const char *tb_refbvh_name(tb_ref_kind kind);
// Appends the pair (i, j): grows out->ij with realloc; 0, or -1 out of memory.
int tb_refbvh_push(tb_pairlist *out, int i, int j);
// Bullet GImpact (ref_bvh_bullet.cpp): builds the kind's model, NULL with err
// set on failure (the mesh is already checked).
tb_ref_bvh *tb_refbvh_bullet_new(tb_ref_kind kind, const tb_vec3 *x, int nv, const int *tri,
                                 int ntri, tb_error *err);

#endif
