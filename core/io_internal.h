/* Private to the mesh readers and writers (core/io_*.c, core/mesh_io.c): a
 * line-oriented tokenizer that knows FILE:LINE, strict number parsing, a
 * mesh under construction whose arrays grow as data arrives (never sized by
 * a count a file declares), and the per-format entry points. */
#ifndef TB_IO_INTERNAL_H
#define TB_IO_INTERNAL_H

#include <stddef.h>
#include <stdio.h>

#include "tb_error.h"
#include "tb_mesh.h"

/* ---- a mesh under construction ---- */
typedef struct tb_build {
  tb_mesh m;
  int capv, captri, captet;
} tb_build;

/* Grows array p (elements of size sz, capacity *cap) to hold need >= 1
 * elements; returns the array, or NULL when out of memory (p untouched). */
void *tb_io_grow(void *p, int *cap, long need, size_t sz);
/* Appends vertex x: 0 done, 1 refused (not tb_coord_ok: non-finite or
 * beyond +-TB_COORD_MAX), -1 out of memory. Every reader adds its vertices
 * here, so no reader can return a coordinate outside the bound. */
int tb_build_vert(tb_build *b, tb_vec3 x);
int tb_build_tri(tb_build *b, int a, int c, int d);
int tb_build_tet(tb_build *b, const int v[4]);
void tb_build_free(tb_build *b);

/* ---- tokenizer ---- */
typedef struct tb_lex {
  FILE *f;
  const char *path;
  tb_error *err;
  char *buf; /* the current line, comment removed, NUL-terminated */
  size_t cap;
  char *cur;   /* next unread character of buf */
  long line;   /* 1-based line of buf; at end of file, the line the end is on */
  long nl;     /* newlines read so far */
  int comment; /* comment character ('#') or 0 */
  int eof;
  int seen;  /* a line with a token was read */
  long last; /* the last physical line read (0 none) */
} tb_lex;

/* Opens path (binary mode) for reading; a directory or any other path that
 * is not a regular file is refused ("is a directory", "not a regular file").
 * NULL with err set on failure. */
FILE *tb_io_open(const char *path, tb_error *err);
/* Opens path with tb_io_open; comment is '#' or 0. A UTF-8 byte-order mark
 * at the start of the file is skipped; one anywhere else is an error. */
int tb_lex_open(tb_lex *lx, const char *path, int comment, tb_error *err);
void tb_lex_close(tb_lex *lx);
/* Advances to the next line holding a token: 1 found, 0 end of file, -1 a
 * read error, a NUL byte or an over-long line (err set). */
int tb_lex_line(tb_lex *lx);
/* Like tb_lex_line but end of file is an error "unexpected end of file
 * (expected WHAT)"; returns 0 or -1. */
int tb_lex_need(tb_lex *lx, const char *what);
/* tb_lex_need for item i (0-based) of n: "expected WHAT i+1 of n". */
int tb_lex_item(tb_lex *lx, long i, long n, const char *what);
/* Next token of the current line (NUL-terminated in place), or NULL. */
char *tb_lex_word(tb_lex *lx);
/* Tokens left on the current line, without consuming them. */
int tb_lex_left(const tb_lex *lx);
/* Next token parsed as a finite double / an integer; a missing, malformed
 * or non-finite token is an error naming WHAT. Return 0 or -1. */
int tb_lex_real(tb_lex *lx, double *v, const char *what);
int tb_lex_long(tb_lex *lx, long *v, const char *what);
/* tb_lex_long, then an error unless lo <= *v <= hi. */
int tb_lex_range(tb_lex *lx, long *v, long lo, long hi, const char *what);
/* Error when the current line still has tokens. */
int tb_lex_end(tb_lex *lx);
/* Error "unexpected data after AFTER" unless the file ends here. */
int tb_lex_trailing(tb_lex *lx, const char *after);
/* Error "no vertices" (or "empty file") when b has no vertex; else 0. */
int tb_lex_done(tb_lex *lx, const tb_build *b);
/* tb_build_vert reporting failure at the current line ("coordinate beyond
 * +-1e+90", "out of memory"); returns 0 or -1. */
int tb_lex_vert(tb_lex *lx, tb_build *b, tb_vec3 x);
/* Reports "path:line: reason" at the current line; returns -1. */
int tb_lex_fail(tb_lex *lx, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Whole-string parsers: 0 ok, 1 not a number, 2 not finite / out of range. */
int tb_parse_real(const char *s, double *v);
int tb_parse_long(const char *s, long *v);

/* ---- formats: readers fill b (freed by the caller on failure) ---- */
int tb_read_obj(const char *path, tb_build *b, tb_error *err);
int tb_read_off(const char *path, tb_build *b, tb_error *err);
int tb_read_stl(const char *path, tb_build *b, tb_error *err);
int tb_read_tetgen(const char *path, tb_build *b, tb_error *err); /* .node or .ele */
int tb_read_msh(const char *path, tb_build *b, tb_error *err);
int tb_read_vtu(const char *path, tb_build *b, tb_error *err); /* VTK XML UnstructuredGrid */
int tb_read_vtk(const char *path, tb_build *b, tb_error *err); /* VTK legacy ASCII */

int tb_write_obj(const char *path, const tb_mesh *m, tb_error *err);
int tb_write_off(const char *path, const tb_mesh *m, tb_error *err);
int tb_write_stl(const char *path, const tb_mesh *m, tb_error *err); /* ASCII */
int tb_write_tetgen(const char *path, const tb_mesh *m, tb_error *err); /* .node + .ele */
int tb_write_vtk(const char *path, const tb_mesh *m, tb_error *err);
int tb_write_msh(const char *path, const tb_mesh *m, tb_error *err); /* Gmsh 2.2 ASCII */

#endif
