/* Mesh files: OBJ, OFF, STL (ASCII and binary), TetGen .node/.ele/.face,
 * Gmsh .msh v1, v2 and v4 (ASCII), VTK XML .vtu (binary, core/tb_vtu.h) and
 * VTK legacy ASCII .vtk; writers for OBJ, OFF, .node/.ele and VTK legacy. Every reader reports
 * malformed input as "FILE:LINE: reason". */
#ifndef TB_MESH_IO_H
#define TB_MESH_IO_H

#include "tb_error.h"
#include "tb_mesh.h"

/* Reads any supported format, chosen by extension (.obj .off .stl .node .ele
 * .msh .vtu .vtk; a TetGen base name with .node reads the .ele and .face beside it).
 * On failure *m is left empty and err holds "FILE:LINE: reason". */
int tb_mesh_read(const char *path, tb_mesh *m, tb_error *err);

/* Writes by extension: .obj/.off/.stl (triangles; STL in ASCII), .node (with .ele beside it,
 * tets), .vtk (unstructured grid when the mesh has tets, else polydata),
 * .msh (Gmsh 2.2: triangles and tets).
 * Files holding only triangles (.obj, .off, polydata .vtk) carry only the
 * vertices the triangles use, renumbered in their original order. */
int tb_mesh_write(const char *path, const tb_mesh *m, tb_error *err);
/* The extensions tb_mesh_write knows, and whether path has one of them. */
#define TB_MESH_WRITES ".obj .off .stl .node .vtk .msh"
int tb_mesh_writable(const char *path);

#endif
