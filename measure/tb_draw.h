/* Drawing a simulation with the renderer (render/tb_render.h), shared by
 * `render` and the figures suite: the body (flat colour or a colour map),
 * its instrument and ground, the model's structure (what its class's
 * spheres or groups hook gives, else the tet edges: msm's springs, fem's
 * elements) and the surface triangles the BVH finds crossing the
 * instrument. */
#ifndef TB_DRAW_H
#define TB_DRAW_H

#include "render/tb_render.h"
#include "scenes/tb_sim.h"

extern const float tb_draw_body_rgb[3], tb_draw_tool_rgb[3];

/* The ground (if any, also one the scene turned off: ground = 0), the body's current surface
 * coloured by value (per node, over [lo, hi], clamped; NULL: flat) with its colour bar named
 * label, and the instrument (if any). */
void tb_draw_sim(tb_renderer *r, tb_sim *s, const double *value, double lo, double hi,
                 const char *label, int wireframe);
/* Each surface point's distance from its rest position into value[su.nv]
 * (su = tb_model_surface: points beyond the mesh's nodes, a finer level of
 * msm-vvs, measured from their own rest positions); returns the largest. */
double tb_draw_displacement(const tb_sim *s, double *value);
/* Every tet edge of m at positions x as a thin dark line. */
void tb_draw_edges(tb_renderer *r, const tb_mesh *m, const tb_vec3 *x);
/* The model's structure: its spheres (at half their radius) and links
 * (the class's spheres hook), its point groups (the groups hook: each
 * point coloured by its first group; shape matching's clusters), else the
 * tet edges. */
int tb_draw_structure(tb_renderer *r, const tb_sim *s, tb_error *err);
/* The body's surface triangles crossing the instrument at the last step,
 * in red over the surface; returns how many. */
int tb_draw_contacts(tb_renderer *r, const tb_sim *s);

/* Spheres (centres c, radii rad scaled by scale; only those with show[i]
 * != 0 when show is not NULL) as shaded balls of one colour: the metaball
 * model's volume. */
int tb_draw_spheres(tb_renderer *r, int n, const tb_vec3 *c, const double *rad,
                    const unsigned char *show, double scale, const float rgb[3], tb_error *err);
/* n links (2n indices into c) as lines: the spheres' stretch constraints. */
void tb_draw_links(tb_renderer *r, int n, const int *pairs, const tb_vec3 *c, const float rgb[3],
                   float width);

#endif
