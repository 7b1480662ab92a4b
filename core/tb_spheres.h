/* Sphere sets, e.g. the metaballs ("元球") that fill an organ in the
 * metaball hybrid-cutting patent, and SOFA's .sph files that hold them
 * (SOFA's SphereLoader format): a first line "sph 1.0", comment lines "#...",
 * one "sphe ID X Y Z R" line per sphere.
 *
 * Reading is strict, like the mesh readers (core/tb_mesh_io.h): every error
 * is "FILE:LINE: reason"; the header must be the first statement; a line is
 * "sphe" and exactly five numbers (ID an integer, X Y Z R finite, R > 0), an
 * optional trailing "#..." comment; any other statement is refused.
 *
 * The header count: SOFA writes a comment "#nums N", which its loader only
 * uses to reserve space. Here it is advisory too: it is recorded in
 * `declared` (-1 when absent or not a whole number) but never sizes an array
 * and never refuses a file; the spheres are those the file lists (SOFA's own
 * liver.sph says "#nums 27" and lists 34, and loads with 34). The ID field is
 * read and checked to be an integer but not kept (liver.sph gives every
 * sphere ID 1); the writer numbers the spheres 1..n. */
#ifndef TB_SPHERES_H
#define TB_SPHERES_H

#include "tb_error.h"
#include "tb_math.h"

typedef struct tb_spheres {
  int n;
  tb_vec3 *c;   /* n centres */
  double *r;    /* n radii, > 0 */
  int declared; /* "#nums N" of the file read, -1 when none */
} tb_spheres;

void tb_spheres_free(tb_spheres *s);
/* Appends a sphere; 0 or -1 out of memory (s unchanged). */
int tb_spheres_push(tb_spheres *s, tb_vec3 c, double r);

/* On failure *s is left empty and err holds "FILE:LINE: reason" (or
 * "FILE: reason" when the file cannot be opened). */
int tb_spheres_read(const char *path, tb_spheres *s, tb_error *err);
/* Writes "sph 1.0", "#nums n" and one "sphe i x y z r" line per sphere with
 * %.17g, so reading the file back gives the same doubles bit for bit. */
int tb_spheres_write(const char *path, const tb_spheres *s, tb_error *err);

#endif
