/* Metaballs: an organ filled with overlapping spheres driven by
 * position-based dynamics, and a surface skinned to them (the metaball
 * patent, SPEC §2.6, step 2: stretch, unit and energy constraints, fixed
 * spheres; Gaussian binding of each surface vertex to at most three
 * spheres). The cutting that turns spheres into a point set and back
 * works on this through tb_metaball_remove and the per-sphere forces. */
#ifndef TB_METABALL_H
#define TB_METABALL_H

#include "core/tb_error.h"
#include "core/tb_mesh.h"

typedef struct tb_metaball_settings {
  double density; /* mass per volume: a sphere's mass is density 4/3 pi r^3 */
  double stretch; /* stiffness in [0, 1] of the links between overlapping spheres */
  double unit;    /* stiffness in [0, 1] of the unit (shape-matching) constraints */
  double damping; /* per second: velocities decay as exp(-damping t) */
  double sigma;   /* the binding's Gaussian exp(-k^2 / (2 sigma^2)) of k = d / r */
  double overlap; /* spheres are linked when |c_i - c_j| < overlap (r_i + r_j) */
  int iterations; /* Gauss-Seidel sweeps per step */
} tb_metaball_settings;

/* The defaults: density 1, stretch 1, unit 0.5, damping 1, sigma 1,
 * overlap 1, 10 iterations. */
void tb_metaball_settings_default(tb_metaball_settings *s);

typedef struct tb_metaball tb_metaball;

/* Spheres (centres c, radii r > 0) at rest, and the closed surface skinned
 * to them (its vertices at rest; copied). */
tb_metaball *tb_metaball_create(int n, const tb_vec3 *c, const double *r, const tb_mesh *surface,
                                const tb_metaball_settings *set, tb_error *err);
void tb_metaball_destroy(tb_metaball *m);

/* Holds sphere i where it is (fixed != 0) or lets it go. */
void tb_metaball_fix(tb_metaball *m, int i, int fixed);
/* Removes sphere i logically (the patent's cut): its links and its place
 * in every unit constraint go, indices stay; it no longer moves. */
void tb_metaball_remove(tb_metaball *m, int i);
/* Removes the k spheres ids at once (one pass over links and skin). */
void tb_metaball_remove_set(tb_metaball *m, int k, const int *ids);
/* Moves every sphere (and its velocity) by a rigid motion x -> R x + t,
 * without stepping: for tests and placement. */
void tb_metaball_transform(tb_metaball *m, const double R[9], tb_vec3 t);

/* One step: gravity and per-sphere forces (NULL: none), prediction, the
 * sweeps, velocities, damping, then the skin. */
void tb_metaball_step(tb_metaball *m, double dt, tb_vec3 gravity, const tb_vec3 *force);

int tb_metaball_count(const tb_metaball *m);
const tb_vec3 *tb_metaball_centres(const tb_metaball *m);
const tb_vec3 *tb_metaball_velocities(const tb_metaball *m);
const double *tb_metaball_radii(const tb_metaball *m);
/* Sphere masses: density x 4/3 pi r^3. */
const double *tb_metaball_masses(const tb_metaball *m);
/* Links between overlapping spheres still alive: 2 n sphere pairs. */
int tb_metaball_links(const tb_metaball *m, const int **pairs);
/* The skinned surface vertices (the surface's nv), and how many vertices
 * found no sphere with d / r in [1, 2] and fell back to the nearest. */
const tb_vec3 *tb_metaball_skin(const tb_metaball *m);
int tb_metaball_fallbacks(const tb_metaball *m);
/* Vertex v's binding: up to 3 spheres and weights (summing to 1);
 * returns how many. */
int tb_metaball_binding(const tb_metaball *m, int v, int sphere[3], double weight[3]);

/* ---- cutting (models/metaball_cut.c; the patent's step 3 (1)-(4)) ----
 * Spheres the blade's folded plane touches turn into points of a meshless
 * body (models/tb_meshless.h) that never links across the cut; points
 * inside spheres still alive follow them and push back on them; when the
 * blade leaves, the points become spheres again, on the medial axis of
 * their boundary. Between tb_metaball_cut_begin and tb_metaball_cut_end run
 * tb_metaball_cut_step instead of tb_metaball_step. */
struct tb_fold;
struct tb_meshless;

typedef struct tb_metaball_cut_settings {
  double spacing;  /* the shared grid's spacing over the smallest radius (uniform sampling) */
  int per_sphere;  /* > 0: about this many points per sphere instead, spacing from each radius */
  double min_dist; /* per_sphere: no point closer than min_dist x its spacing to another */
  double E, nu;    /* the point set's Young's modulus and Poisson ratio */
  double density;  /* its mass per volume; 0: the spheres' */
  double damping;  /* per second, the point set's velocity decay */
  double coupling; /* share of the point set's elastic force on driven points fed to spheres */
  int substeps;    /* meshless steps per frame; 0: from the explicit bound (cfl) */
  double cfl;      /* substep = cfl x 2 / the point set's largest free frequency */
  double boundary_angle;  /* degrees: the patent's cone about a point's normal */
  double boundary_offset; /* neighbour-centroid offset over mean neighbour distance */
  double flatness;        /* point stencils with det A <= flatness (tr A / 3)^3 are inactive */
  double coarse;          /* per_sphere: spheres below coarse x the mean radius are sampled at the
                           * spacing of one of that radius (fewer points; 0: none) */
} tb_metaball_cut_settings;

/* spacing 0.3, per_sphere 0, min_dist 0.6, E 1000, nu 0.3, density 0,
 * damping 2, coupling 1, substeps 0, cfl 0.7, boundary_angle 45,
 * boundary_offset 0.25, flatness 0.02, coarse 0.3. */
void tb_metaball_cut_settings_default(tb_metaball_cut_settings *s);

/* Starts a cut (no points yet). Fails when a cut is running or on bad
 * settings. */
int tb_metaball_cut_begin(tb_metaball *m, const tb_metaball_cut_settings *s, tb_error *err);
/* The blade's folded plane so far (copied): spheres it newly touches become
 * points and are removed; the point set is rebuilt, its links re-cut.
 * Returns the spheres turned into points by this call, or -1 (err). */
int tb_metaball_cut_advance(tb_metaball *m, const struct tb_fold *f, tb_error *err);
/* One frame of the cut phase: the spheres (tb_metaball_step with the point
 * set's force on them added to `force`, which may be NULL), then the point
 * set in substeps with its driven points following their spheres. Allocates
 * nothing. 0, or -1 (err: no cut running, or the point set blew up). */
int tb_metaball_cut_step(tb_metaball *m, double dt, tb_vec3 gravity, const tb_vec3 *force,
                         tb_error *err);

typedef struct tb_metaball_cut_report {
  int removed, created;        /* spheres turned into points; spheres made from them */
  double removed_r, created_r; /* their mean radii */
  int points, boundary;        /* points at the end, of which on the boundary */
  int candidates;              /* Voronoi poles accepted as centres */
  int uncovered;               /* points no kept sphere reaches (within a spacing) */
  int dropped;                 /* new spheres that overlapped no other one, removed */
  int filled;                  /* of the created, spheres of the last pass centred at points */
  int driven, strays;          /* points inside alive spheres, points with no neighbour */
} tb_metaball_cut_report;

/* The blade has left: new spheres on the medial axis of the boundary
 * points, linked to overlapping spheres except across the cut; the points
 * go. rep may be NULL. 0, or -1 (err). */
int tb_metaball_cut_end(tb_metaball *m, tb_metaball_cut_report *rep, tb_error *err);

/* 1 between cut_begin and cut_end. */
int tb_metaball_cutting(const tb_metaball *m);
/* The point set's current positions (NULL when none); returns their count. */
int tb_metaball_cut_points(const tb_metaball *m, const tb_vec3 **x);
/* The point set itself (NULL when none), e.g. for its links. */
const struct tb_meshless *tb_metaball_cut_meshless(const tb_metaball *m);
/* Meshless steps the last tb_metaball_cut_step took. */
int tb_metaball_cut_substeps(const tb_metaball *m);
/* The bound of the point set's largest free frequency (rad/s) its
 * substeps follow (0 when not cutting). */
double tb_metaball_cut_omega(const tb_metaball *m);
/* Point i's sphere driving it (-1: free, -2: held where a fixed sphere was). */
int tb_metaball_cut_driver(const tb_metaball *m, int i);
/* 1 when sphere i has not been removed. */
int tb_metaball_alive(const tb_metaball *m, int i);

/* The skin after a cut (models/metaball_pieces.c). */
typedef struct tb_metaball_skin_def {
  int nv;                      /* vertices, at least the skin's count: the old ones first */
  const tb_vec3 *x;            /* their current positions */
  const tb_vec3 *v;            /* their velocities (NULL: at rest): a piece's new sphere's */
  const signed char *side;     /* +1 / -1: on that side of the last cut's crack; 0 (NULL: all) */
  const unsigned char *rebind; /* 1: bound anew (NULL: none but the new vertices) */
  int ntri;                    /* the surface's triangles (0: the pieces are not followed) */
  const int *tri;
  int first_new; /* spheres from this index on are the last cut's new ones */
  /* the vertices' rest positions (NULL: each found at the current
   * configuration by inverting its skin, see below) */
  const tb_vec3 *x0;
} tb_metaball_skin_def;

typedef struct tb_metaball_skin_report {
  int pieces;                        /* the surface's pieces */
  int outside;                       /* new spheres whose centre lay in no piece, removed */
  int links_cut;                     /* links between spheres of two pieces, removed */
  int joined;                        /* links added to join a piece's sphere groups into one */
  int anchored;                      /* links added to spheres that had fewer than five */
  int seeded;                        /* spheres made for pieces that had fewer than four */
  int rebound;                       /* vertices bound anew */
  int contacts;                      /* sphere pairs across the crack kept apart from now on */
  int zone_vertices, zone_triangles; /* the crack's faces and surroundings, kept apart */
} tb_metaball_skin_report;

/* Replaces the skin by d->nv vertices at current positions d->x (a surface
 * cutter keeps the old vertices first). New vertices, those with rebind set
 * and those bound to a removed sphere are bound anew at the current
 * configuration: the spheres with the smallest k = d / r in [1, 2] on
 * current positions, then the smallest k, with a rest offset so that the
 * skin formula gives x exactly; side +1 / -1 restricts a vertex to spheres
 * whose centre is on that side of the last cut's folded plane. With d->x0
 * the vertices bound anew take those rest positions instead (a rest shape
 * consistent with the old surface's; inverting each vertex's skin alone
 * puts neighbours' rest positions out of step where their spheres turn
 * differently, and the surface relaxes into a crumpled shape): the skin
 * then differs from x, and the difference fades out over 0.1 s
 * instead of jumping (TB_METABALL_BLEND, models/metaball_priv.h).
 *
 * With the surface's triangles (ntri > 0; a closed surface) the spheres
 * follow its pieces: each alive sphere belongs to the piece holding its
 * centre (a new sphere in none is removed, an old one goes with the piece
 * most of its vertices are on); links between two pieces go; a piece whose
 * spheres fall into groups has them joined by a link between the nearest
 * spheres (not across the last fold where another pair will do); a sphere
 * with fewer than five links gets links to its piece's nearest; a piece
 * with fewer than four spheres gets more, inside it. Every
 * vertex is then bound to spheres of its own piece only, and a vertex off
 * the cut to none whose centre lies across the last fold. Sphere pairs
 * across the last fold within reach of each other are kept from coming
 * closer than they are (the crack's faces do not pass through each other).
 * rep may be NULL. 0, or -1 (err). */
int tb_metaball_set_skin(tb_metaball *m, const tb_metaball_skin_def *d,
                         tb_metaball_skin_report *rep, tb_error *err);

#endif
