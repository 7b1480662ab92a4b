/* VTK XML output for ParaView: one .vtu file (UnstructuredGrid) of one or
 * more pieces with point and cell data, a .vtm multiblock naming several
 * such files, a .pvd collection of files over time, and a reader for the
 * .vtu files written here.
 *
 * File layout ("VTK File Formats", Kitware, XML section): version 1.0,
 * byte_order="LittleEndian", header_type="UInt64"; every DataArray is
 * format="binary": base64 of one 8-byte little-endian byte count followed by
 * the values, encoded as one stream, no compression. Points are Float64 x3;
 * cells are Int64 connectivity and offsets and UInt8 types: each piece's
 * tets (VTK_TETRA, 10) first, then its triangles (VTK_TRIANGLE, 5). */
#ifndef TB_VTU_H
#define TB_VTU_H

#include "tb_error.h"
#include "tb_mesh.h"

/* One named array of a piece. Point data has one tuple per point (nv);
 * cell data one per cell, tets first then triangles (ntet + ntri). Values
 * are Float64 from data, or UInt8 flags from u8 (ncomp 1). */
typedef struct tb_vtu_array {
  const char *name;        /* non-empty, unique among the piece's point (cell) arrays */
  int ncomp;               /* 1 or 3 */
  const double *data;      /* ncomp values per tuple, or NULL when u8 is given */
  const unsigned char *u8; /* one flag per tuple, or NULL */
  int on_cells;            /* 0: point data, 1: cell data */
} tb_vtu_array;

/* One piece: points, tets and/or triangles (0-based indices into x), arrays.
 * Every piece of a file carries every array any piece names (ParaView takes
 * the array list from the first piece): where a piece lacks one, the
 * writer fills it with zeros. An array name must keep one ncomp, type and
 * point/cell kind across the pieces. */
typedef struct tb_vtu_piece {
  int nv;
  const tb_vec3 *x;
  int ntri;
  const int *tri; /* 3*ntri */
  int ntet;
  const int *tet; /* 4*ntet */
  int narrays;
  const tb_vtu_array *arrays;
} tb_vtu_piece;

/* Writes npieces >= 1 pieces to path. Returns 0, or -1 with "path: reason"
 * (bad indices, non-finite values, clashing arrays, I/O errors). */
int tb_vtu_write(const char *path, const tb_vtu_piece *pieces, int npieces, tb_error *err);

/* Writes a ParaView collection: n DataSets, times[i] and files[i] (names as
 * given, normally relative to the .pvd's folder), in that order. */
int tb_pvd_write(const char *path, int n, const double *times, const char *const *files,
                 tb_error *err);

/* Writes a multiblock data set (.vtm): n named blocks, each one data set
 * file (relative to the .vtm's folder), in that order; ParaView shows each
 * block as its own object. */
int tb_vtm_write(const char *path, int n, const char *const *names, const char *const *files,
                 tb_error *err);

/* An array to fetch while reading: set name and on_cells; the reader fills
 * ncomp, ntuples (all pieces, in order; cell data counts every cell, skipped
 * kinds too) and data (malloc'ed, ncomp*ntuples doubles, integer types
 * converted; free with free()). */
typedef struct tb_vtu_field {
  const char *name;
  int on_cells;
  int ncomp, ntuples;
  double *data;
} tb_vtu_field;

/* Reads a .vtu file as tb_vtu_write writes it (binary, uncompressed; UInt32
 * or UInt64 headers; Float32/64 points; Int32/64 connectivity): the pieces
 * merged into one mesh, tets and triangles kept, other linear cell types
 * counted in m->nskipped. When field is not NULL its named array is read too
 * (a missing array is an error). Errors are "FILE:LINE: reason". */
int tb_vtu_read(const char *path, tb_mesh *m, tb_vtu_field *field, tb_error *err);

#endif
