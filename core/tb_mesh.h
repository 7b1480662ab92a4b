/* Triangle and tetrahedral meshes: one struct for both, flat arrays.
 * A surface mesh has ntet == 0; a tet mesh may also carry triangles (its
 * boundary, or the triangles a file listed). Indices are 0-based. */
#ifndef TB_MESH_H
#define TB_MESH_H

#include "tb_error.h"
#include "tb_math.h"

typedef struct tb_mesh {
  int nv;
  tb_vec3 *x; /* nv positions */
  int ntri;
  int *tri; /* 3*ntri vertex indices */
  int ntet;
  int *tet;     /* 4*ntet vertex indices */
  int nskipped; /* elements of other kinds a reader skipped (lines, quads, ...) */
} tb_mesh;

/* Topology of the triangles of a mesh, from tb_mesh_topology(). */
typedef struct tb_mesh_topo {
  int nedges;            /* distinct undirected edges */
  int boundary_edges;    /* edges used by one triangle */
  int nonmanifold_edges; /* edges used by more than two triangles */
  int misoriented_edges; /* edges two triangles traverse in the same direction */
  int nonmanifold_verts; /* vertices whose triangle fan is not one disc/cycle */
  int unused_verts;      /* vertices no triangle uses */
  int degenerate_tris;   /* triangles with a repeated vertex index */
  int components;        /* connected components of triangles */
  int euler;             /* V - E + F over used vertices */
  int closed;            /* no boundary edges */
  int manifold;          /* closed-or-not, no non-manifold edge or vertex */
} tb_mesh_topo;

void tb_mesh_free(tb_mesh *m);
/* Deep copy; returns 0 or -1 when out of memory. */
int tb_mesh_copy(tb_mesh *dst, const tb_mesh *src);

/* Byte-identical positions and indices. */
int tb_mesh_equal(const tb_mesh *a, const tb_mesh *b);

/* The largest coordinate magnitude a mesh may have: sums of products of
 * three coordinates (volumes, the triangle tests' determinants) then stay
 * finite for any mesh size. Readers and generators refuse beyond it. */
#define TB_COORD_MAX 1e90
/* 1 when x is finite and within +-TB_COORD_MAX in every coordinate. */
int tb_coord_ok(tb_vec3 x);
/* 0 when every vertex is tb_coord_ok, else -1 with err naming `what` and
 * the first vertex that is not (0-based). */
int tb_mesh_check_coords(const tb_mesh *m, const char *what, tb_error *err);

/* 0 when every triangle and tet index is in [0, nv); else 1 with the first
 * element holding one out of range: *tet (0 a triangle, 1 a tet), its
 * number *elem and the index *vertex. */
int tb_mesh_bad_index(const tb_mesh *m, int *tet, long *elem, int *vertex);

void tb_mesh_bbox(const tb_mesh *m, tb_vec3 *lo, tb_vec3 *hi);
/* Sum of signed tet volumes when the mesh has tets, else the volume the
 * triangles enclose (divergence theorem; meaningful when closed). */
double tb_mesh_volume(const tb_mesh *m);
double tb_mesh_area(const tb_mesh *m);
/* Removes vertices no triangle or tet uses, renumbering the elements
 * (order kept). Returns how many were removed, or -1 when out of memory
 * (m unchanged). */
int tb_mesh_drop_unused(tb_mesh *m);
/* Smallest signed tet volume (0 when there are no tets). */
double tb_mesh_min_tet_volume(const tb_mesh *m);
/* Topology of the triangles only; tets are ignored. */
tb_mesh_topo tb_mesh_topology(const tb_mesh *m);

/* Distinct undirected edges of the tets (or, with no tets, of the
 * triangles), as 2*n sorted index pairs in lexicographic order; *edges is
 * malloc'ed. Returns n, or -1 when out of memory. */
int tb_mesh_edges(const tb_mesh *m, int **edges);
/* All distinct triangles (faces) of the tets, 3*n, each sorted ascending,
 * in lexicographic order: the thesis's "9313 triangles". */
int tb_mesh_tet_faces(const tb_mesh *m, int **faces);
/* Faces used by exactly one tet, oriented outward. */
int tb_mesh_tet_boundary(const tb_mesh *m, int **faces);

#endif
