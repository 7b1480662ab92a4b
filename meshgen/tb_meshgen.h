/* Mesh generation: marching cubes on grey-value volumes (thesis §2.3.2),
 * surface clean-up, the synthetic liver, the instrument, geodesic spheres
 * (Bao 2006) and cantilever beams. Same settings, byte-identical meshes. */
#ifndef TB_MESHGEN_H
#define TB_MESHGEN_H

#include <stdint.h>

#include "core/tb_error.h"
#include "core/tb_mesh.h"

/* ---- grey-value volumes and marching cubes ---- */
/* Sample (i,j,k) sits at origin + (i*h.x, j*h.y, k*h.z); its value is
 * f[(k*ny + j)*nx + i]. "Inside" is f > iso. */
typedef struct tb_volume {
  int nx, ny, nz;
  tb_vec3 origin, h;
  double *f;
} tb_volume;

void tb_volume_free(tb_volume *v);
/* Marching cubes: a closed, consistently oriented (outward) triangle mesh
 * of the isosurface f = iso, vertices interpolated along cell edges (eq.
 * 2-3). The volume's border samples must be outside. normals (may be NULL)
 * receives malloc'ed per-vertex unit normals, interpolated from
 * central-difference gradients (eq. 2-2), pointing outward. */
int tb_marching_cubes(const tb_volume *v, double iso, tb_mesh *out, tb_vec3 **normals,
                      tb_error *err);

/* ---- surface clean-up (closed 2-manifold in, closed 2-manifold out) ---- */
/* Collapses edges shorter than min_len, shortest first, keeping the mesh a
 * closed 2-manifold (link condition) and never flipping a triangle. Returns
 * the number of collapses. Unused vertices are removed. */
int tb_remesh_collapse_short(tb_mesh *m, double min_len);
/* Flips edges between nearly coplanar triangles when that raises the
 * pair's smallest angle (keeps the mesh closed and manifold, valences >= 3,
 * no folds). Returns the number of flips, -1 on bad input or no memory. */
int tb_remesh_flip(tb_mesh *m);
/* Taubin lambda|mu smoothing (no shrinkage), iters passes. */
void tb_remesh_taubin(tb_mesh *m, int iters, double lambda, double mu);

/* ---- TetGen (meshgen/tetgen.cpp) ---- */
/* Tetrahedralises a closed surface with TetGen's switches (e.g. "pq1.4a0.5Y");
 * "Q" (quiet) and "z" (0-based) are added. out gets vertices, tets and
 * the boundary triangles. TetGen's failures come back as err. */
int tb_tetgen(const tb_mesh *surface, const char *switches, tb_mesh *out, tb_error *err);

/* ---- a user's surface to tets (meshgen/tetmesh.c) ---- */
/* TetGen's radius-edge bound when none is given: its own recommended q. */
#define TB_TETMESH_QUALITY 1.414
typedef struct tb_tetmesh_opts {
  double quality;    /* radius-edge ratio bound, >= 1 (TetGen's q) */
  double max_volume; /* largest tet volume (TetGen's a); 0: none */
  int tets;          /* target tet count (the volume bound searched); 0: none */
  int split_surface; /* 1: TetGen may add points on the surface; 0: the surface is kept (Y) */
} tb_tetmesh_opts;
tb_tetmesh_opts tb_tetmesh_default_opts(void);
/* Why the closed surface `name` cannot be tetrahedralised: open, not
 * manifold, misoriented, degenerate, or self-intersecting (the first pair
 * and the count, by our exact test). 0 when it can. */
int tb_tetmesh_check(const tb_mesh *surf, const char *name, tb_error *err);
/* The surface (unused vertices dropped) tetrahedralised by TetGen with the
 * options; with tets > 0 the volume bound is searched until the count is
 * within 1% (at most 40 meshes; the closest mesh met, an error beyond 10%).
 * Tets oriented positively, boundary triangles included; the surface's
 * vertices come first, in order. */
int tb_tetmesh(const tb_mesh *surf, const char *name, const tb_tetmesh_opts *o, tb_mesh *out,
               tb_error *err);
/* Shape of a tet mesh: dihedral angles (degrees) and the largest
 * radius-edge ratio (circumradius over shortest edge; 0.612 for a regular
 * tet). */
typedef struct tb_tet_shape {
  double min_dihedral, max_dihedral, max_radius_edge;
} tb_tet_shape;
tb_tet_shape tb_tet_mesh_shape(const tb_mesh *m);
/* Moves vertices near self-intersections of the closed surface m (umbrella
 * smoothing of the crossing triangles' vertices, the neighbourhood grown
 * each round) until no pair crosses, at most `rounds` rounds. Returns the
 * pairs left (0: untangled), or -1 with err; *moved gets the largest
 * displacement in mean edge lengths and *nmoved the vertices moved. */
int tb_surface_untangle(tb_mesh *m, int rounds, double *moved, int *nmoved, tb_error *err);
/* Caps every hole of an open, consistently oriented 2-manifold surface (a
 * fan around the loop's centroid, oriented like the surface); *loops gets
 * the holes capped. A closed surface is left as it is. An error when a cap
 * would cross the surface (m then unchanged but for spare capacity). */
int tb_mesh_close(tb_mesh *m, int *loops, tb_error *err);
/* Bisection on the log of TetGen's volume bound over [lo, hi], switches
 * `prefix` + "a<bound>", for a balance V/V* + T/T* - 2 = 0 (tv <= 0: T/T* -
 * 1), at most `iters` meshes, until the interval is narrower than `width`
 * or the closest mesh's |balance| is at most `stop`. The closest mesh met is
 * kept in *best (its balance in *best_b). */
int tb_tetgen_search(const tb_mesh *surf, const char *prefix, double lo, double hi, double tv,
                     double tt, int iters, double width, double stop, tb_mesh *best,
                     double *best_b, tb_error *err);

/* ---- the synthetic liver ---- */
typedef struct tb_liver_def {
  int surface_verts; /* target surface vertices (thesis: 725; 0: tb_liver_surface_for(tets)) */
  int tet_verts;     /* target tet-mesh vertices (thesis: 1206; 0: only the tet count) */
  int tets;          /* target tets (thesis: 4230; 0: tet_verts * 4230 / 1206; < 0: any) */
  double length;     /* extent along x (SOFA's liver is about 10) */
  double noise;      /* amplitude of the grey-value noise, relative */
  uint64_t seed;
} tb_liver_def;
tb_liver_def tb_liver_default_def(void);
/* Grey-value volume of the liver shape with spacing h (CT-like: smooth
 * blend of ellipsoids, intensity noise); the isovalue is returned. */
int tb_liver_volume(const tb_liver_def *def, double h, tb_volume *v, double *iso, tb_error *err);
/* Marching cubes + clean-up, with the grid spacing searched so the surface
 * has surface_verts vertices within 5% (surface_verts 0: the count
 * tb_liver_surface_for(tets) gives). */
int tb_liver_surface(const tb_liver_def *def, tb_mesh *surf, tb_error *err);
/* The surface vertices for a mesh of about `tets` tets: the thesis's 725
 * for 4230 tets, scaled by (tets / 4230)^0.8, so that TetGen's coarsest
 * quality mesh of that surface has about three quarters of the tets (a
 * surface of 151 vertices for 596 tets, 1762 for 12829). */
int tb_liver_surface_for(int tets);
/* The surface tetrahedralised by TetGen (boundary kept), the maximum tet
 * volume searched to balance the relative errors of the vertex and tet
 * counts against tet_verts and tets; fails unless both are within 10%.
 * With tet_verts 0 only the tet count is targeted (tets > 0), and it must
 * end within 2% (TB_LIVER_TET_TOL). */
#define TB_LIVER_TET_TOL 0.02
int tb_liver_tets(const tb_liver_def *def, const tb_mesh *surf, tb_mesh *tets, tb_error *err);
/* A TetGen liver of `tets` tets within 2% (TB_LIVER_TET_TOL), seeded: the
 * default liver's shape, a marching-cubes surface of
 * tb_liver_surface_for(tets) vertices, TetGen's maximum tet volume
 * searched (the pbd and scaling suites). */
int tb_liver_of_tets(int tets, uint64_t seed, tb_mesh *out, tb_error *err);

/* ---- instrument, spheres, beams ---- */
typedef struct tb_instrument_def {
  double length; /* shaft length */
  double radius; /* shaft radius */
  double jaw_length;
  double jaw_opening; /* angle between the jaws, radians */
  int segments;       /* around the shaft */
  int shaft_rings;    /* rings of the shaft + lower jaw tube */
  int jaw_rings;      /* rings of the upper jaw tube */
} tb_instrument_def;
tb_instrument_def tb_instrument_default_def(void);
int tb_instrument(const tb_instrument_def *def, tb_mesh *out, tb_error *err);

/* Geodesic sphere of nv = 10 f^2 + 2 vertices and 20 f^2 triangles (f = 5
 * and 10 give Bao 2006's 252/500 and 1002/2000); other nv is an error. */
int tb_geosphere(int nv, double radius, tb_mesh *out, tb_error *err);

/* Box cantilever [0,lx]x[0,ly]x[0,lz] split into nx*ny*nz cubes of 6 tets
 * each (conforming), boundary triangles included; tb_beam splits every cube
 * the same way (TB_SPLIT_KUHN). */
int tb_beam(double lx, double ly, double lz, int nx, int ny, int nz, tb_mesh *out, tb_error *err);

/* How tb_beam_with_split cuts the cubes: KUHN, every cube around its
 * (0,0,0)-(1,1,1) diagonal (tb_beam; a T4 beam under a vertical tip load
 * also bends sideways), or SYMMETRIC, cubes of the upper half of each axis
 * mirrored so the mesh is mirror-symmetric about y = ly/2 and z = lz/2
 * (needs even ny and nz; same vertex and tet counts). */
typedef enum tb_beam_split { TB_SPLIT_KUHN = 0, TB_SPLIT_SYMMETRIC = 1 } tb_beam_split;
int tb_beam_with_split(double lx, double ly, double lz, int nx, int ny, int nz, tb_beam_split split,
                       tb_mesh *out, tb_error *err);

/* ---- exact vertex count (meshgen/remesh_count.c) ---- */
/* Splits the longest edges (new vertex on the curve the end normals define)
 * or collapses the shortest (link condition, no flipped triangle) until the
 * closed, oriented 2-manifold m has exactly target vertices. Returns the
 * number of operations, or -1 with err ("remesh: reason"). */
int tb_remesh_to_count(tb_mesh *m, int target, tb_error *err);

/* ---- the metaball patent's organs (meshgen/organs.c) ---- */
/* The patent's table 1 per organ and our solid's nominal size (bounding box
 * extents x, y, z, within 10%; lengths in the liver's unit, SOFA's liver
 * being about 10 long). */
typedef struct tb_organ_info {
  const char *name;
  int verts;                /* the patent's surface vertices */
  int spheres;              /* the patent's spheres */
  double deform_ms, cut_ms; /* the patent's time per frame to deform and to cut */
  double size[3];
  const char *shape; /* how ours is made, one line */
} tb_organ_info;
#define TB_NORGANS 4
/* liver, spleen, gallbladder, steak (the patent's order) */
extern const tb_organ_info tb_organs[TB_NORGANS];
const tb_organ_info *tb_organ_find(const char *name);
/* The organ's closed surface with exactly verts vertices (0: the patent's
 * count; 200 ... 50000), seeded noise (same seed, same bytes): a synthetic
 * grey-value volume, marching cubes, the liver's clean-up, the grid spacing
 * searched to within 5%, then tb_remesh_to_count. The liver is
 * tb_liver_surface_exact of the default liver with these verts and seed. */
int tb_organ_surface(const char *name, int verts, uint64_t seed, tb_mesh *out, tb_error *err);
/* tb_liver_surface, then made exact by tb_remesh_to_count. */
int tb_liver_surface_exact(const tb_liver_def *def, tb_mesh *surf, tb_error *err);

#endif
