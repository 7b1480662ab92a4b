/* Zorin, Schröder & Sweldens' modified butterfly subdivision (SIGGRAPH 1996) as Bao 2006 §3.1
 * states it: an interpolating 1-to-4 split of a closed triangle surface; each edge gets one new
 * point from a stencil of nearby old points (rules in core/butterfly.c).
 *
 * Levels of detail as a forest of quadtrees (Bao 2006, §3.4): with the numbering of
 * tb_butterfly, triangle f of level L has the children 4f, 4f+1, 4f+2, 4f+3 at level L+1 and
 * the parent f/4 at level L-1; so level L's triangle t descends from base triangle t / 4^L.
 * The triangles of all levels form a linear (pointerless) quadtree per base triangle, one
 * tree per base triangle: the paper's forest. Old vertices keep their indices, so vertex i
 * first appears at the first level with more than i vertices (its LOD value in the paper). */
#ifndef TB_BUTTERFLY_H
#define TB_BUTTERFLY_H

#include "tb_error.h"
#include "tb_halfedge.h"
#include "tb_mesh.h"

/* The new point of the edge of half-edge h of the closed surface he with positions x. */
tb_vec3 tb_butterfly_point(const tb_halfedge *he, const tb_vec3 *x, int h);
/* One level: in (a closed 2-manifold triangle surface, ntet == 0) -> out with in->nv + ne
 * vertices and 4 nf triangles. Interpolating: vertices 0..nv-1 keep their index and position;
 * edge e's new vertex is nv + e, edges numbered in order of their smallest half-edge index.
 * Triangle f = (a, b, c) of in gives out's triangles 4f+k: k=0 (a, m_ab, m_ca), 1 (m_ab, b, m_bc),
 * 2 (m_ca, m_bc, c), 3 (m_ab, m_bc, m_ca). If midpoint != NULL, *midpoint gets a malloc'd array
 * of 3 nf: the new vertex on half-edge h's edge (the same for h and its pair).
 * Errors ("butterfly: reason", *out left empty): a tet mesh, every surface
 * tb_halfedge_build refuses (open, non-manifold, misoriented, unused vertices), and a vertex
 * of valence 2 (two triangles on the same three vertices). The output is then again a closed,
 * oriented 2-manifold with the same Euler characteristic and no vertex of valence 2. */
int tb_butterfly(const tb_mesh *in, tb_mesh *out, int **midpoint, tb_error *err);

#endif
