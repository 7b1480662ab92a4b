/* VTK XML writers (core/tb_vtu.h): .vtu UnstructuredGrid files of several
 * pieces with inline base64 binary data arrays (UInt64 byte-count header,
 * little-endian, written byte by byte so the host's order does not matter)
 * and .pvd collections. Everything is checked before the file is opened;
 * the base64 encoder streams through a fixed buffer (no allocation per
 * value). */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_vtu.h"

/* ---- base64 output ---- */
typedef struct b64 {
  FILE *f;
  unsigned char in[3];
  int nin, nout;
  char out[4096];
} b64;

static const char b64_alphabet[] =
    "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

static void b64_flush(b64 *e) {
  fwrite(e->out, 1, (size_t)e->nout, e->f);
  e->nout = 0;
}

/* Encodes the nin (1..3) pending bytes as four characters, '=' padded. */
static void b64_quantum(b64 *e) {
  unsigned char *i = e->in;
  unsigned long v = (unsigned long)i[0] << 16 | (unsigned long)(e->nin > 1 ? i[1] : 0) << 8 |
                    (e->nin > 2 ? i[2] : 0);
  char *o = e->out + e->nout;
  o[0] = b64_alphabet[v >> 18 & 63];
  o[1] = b64_alphabet[v >> 12 & 63];
  o[2] = e->nin > 1 ? b64_alphabet[v >> 6 & 63] : '=';
  o[3] = e->nin > 2 ? b64_alphabet[v & 63] : '=';
  e->nout += 4;
  e->nin = 0;
  if (e->nout + 4 > (int)sizeof e->out) b64_flush(e);
}

static void b64_byte(b64 *e, unsigned char c) {
  e->in[e->nin++] = c;
  if (e->nin == 3) b64_quantum(e);
}

static void b64_u64(b64 *e, uint64_t u) {
  for (int k = 0; k < 8; k++) b64_byte(e, (unsigned char)(u >> (8 * k)));
}

static void b64_f64(b64 *e, double d) {
  uint64_t u;
  memcpy(&u, &d, sizeof u);
  b64_u64(e, u);
}

static void b64_end(b64 *e) {
  if (e->nin) b64_quantum(e);
  b64_flush(e);
}

/* ---- XML pieces ---- */
static void put_escaped(FILE *f, const char *s) {
  for (; *s; s++) switch (*s) {
      case '&':
        fputs("&amp;", f);
        break;
      case '<':
        fputs("&lt;", f);
        break;
      case '>':
        fputs("&gt;", f);
        break;
      case '"':
        fputs("&quot;", f);
        break;
      default:
        fputc(*s, f);
    }
}

/* Starts a DataArray of nbytes bytes of values: the tag, then the header. */
static void array_open(FILE *f, b64 *e, const char *type, const char *name, int ncomp,
                       uint64_t nbytes) {
  fprintf(f, "        <DataArray type=\"%s\"", type);
  if (name) {
    fputs(" Name=\"", f);
    put_escaped(f, name);
    fputc('"', f);
  }
  if (ncomp > 1) fprintf(f, " NumberOfComponents=\"%d\"", ncomp);
  fputs(" format=\"binary\">\n          ", f);
  memset(e, 0, sizeof *e);
  e->f = f;
  b64_u64(e, nbytes);
}

static void array_close(FILE *f, b64 *e) {
  b64_end(e);
  fputs("\n        </DataArray>\n", f);
}

/* ---- checks ---- */
static int is_u8(const tb_vtu_array *a) { return a->u8 != NULL; }

static int check_piece(const char *path, const tb_vtu_piece *p, int k, tb_error *err) {
  if (p->nv < 0 || p->ntri < 0 || p->ntet < 0 || p->narrays < 0 || (p->nv && !p->x) ||
      (p->ntri && !p->tri) || (p->ntet && !p->tet) || (p->narrays && !p->arrays))
    return tb_error_set(err, path, 0, "cannot write: piece %d has inconsistent counts", k);
  for (int i = 0; i < p->nv; i++)
    if (!tb_isfinite3(p->x[i]))
      return tb_error_set(err, path, 0, "cannot write: piece %d, point %d is not finite", k, i);
  for (long i = 0; i < 3L * p->ntri; i++)
    if (p->tri[i] < 0 || p->tri[i] >= p->nv)
      return tb_error_set(err, path, 0, "cannot write: piece %d, triangle %ld uses point %d of %d",
                          k, i / 3, p->tri[i], p->nv);
  for (long i = 0; i < 4L * p->ntet; i++)
    if (p->tet[i] < 0 || p->tet[i] >= p->nv)
      return tb_error_set(err, path, 0, "cannot write: piece %d, tet %ld uses point %d of %d", k,
                          i / 4, p->tet[i], p->nv);
  for (int a = 0; a < p->narrays; a++) {
    const tb_vtu_array *r = &p->arrays[a];
    const char *name = r->name ? r->name : "(null)";
    if (!r->name || !*r->name)
      return tb_error_set(err, path, 0, "cannot write: piece %d, array %d has no name", k, a);
    if (r->ncomp != 1 && r->ncomp != 3)
      return tb_error_set(err, path, 0, "cannot write: array '%s' has %d components (1 or 3)", name,
                          r->ncomp);
    if ((r->data && r->u8) || (r->u8 && r->ncomp != 1))
      return tb_error_set(err, path, 0,
                          "cannot write: array '%s' needs either data or (1-component) u8 flags",
                          name);
    if ((r->on_cells ? (long)p->ntet + p->ntri : p->nv) > 0 && !r->data && !r->u8)
      return tb_error_set(err, path, 0, "cannot write: array '%s' has no values", name);
    for (int b = 0; b < a; b++)
      if (!strcmp(p->arrays[b].name, r->name) && !p->arrays[b].on_cells == !r->on_cells)
        return tb_error_set(err, path, 0, "cannot write: piece %d names %s array '%s' twice", k,
                            r->on_cells ? "cell" : "point", name);
  }
  return 0;
}

/* The array named like a (same kind) in piece p, or NULL. */
static const tb_vtu_array *find(const tb_vtu_piece *p, const tb_vtu_array *a) {
  for (int i = 0; i < p->narrays; i++)
    if (!p->arrays[i].on_cells == !a->on_cells && !strcmp(p->arrays[i].name, a->name))
      return &p->arrays[i];
  return NULL;
}

/* The distinct arrays over all pieces, first appearance first (*all is
 * malloc'ed); returns their number or -1 on a clash. */
static int union_arrays(const char *path, const tb_vtu_piece *pieces, int np,
                        const tb_vtu_array ***all, tb_error *err) {
  long total = 0;
  for (int k = 0; k < np; k++) total += pieces[k].narrays;
  *all = malloc(sizeof **all * (size_t)(total > 0 ? total : 1));
  if (!*all) return tb_error_set(err, path, 0, "out of memory");
  int n = 0;
  for (int k = 0; k < np; k++)
    for (int a = 0; a < pieces[k].narrays; a++) {
      const tb_vtu_array *r = &pieces[k].arrays[a];
      int i = 0;
      while (i < n && (!(*all)[i]->on_cells != !r->on_cells || strcmp((*all)[i]->name, r->name)))
        i++;
      if (i == n) {
        (*all)[n++] = r;
      } else if ((*all)[i]->ncomp != r->ncomp || is_u8((*all)[i]) != is_u8(r)) {
        free(*all);
        *all = NULL;
        return tb_error_set(err, path, 0,
                            "cannot write: array '%s' changes components or type between pieces",
                            r->name);
      }
    }
  return n;
}

/* ---- writing ---- */
static void put_array(FILE *f, b64 *e, const tb_vtu_array *kind, const tb_vtu_array *a, long n) {
  long nval = n * kind->ncomp;
  if (is_u8(kind)) {
    array_open(f, e, "UInt8", kind->name, 1, (uint64_t)n);
    for (long i = 0; i < n; i++) b64_byte(e, a ? (a->u8[i] ? 1 : 0) : 0);
  } else {
    array_open(f, e, "Float64", kind->name, kind->ncomp, 8 * (uint64_t)nval);
    for (long i = 0; i < nval; i++) b64_f64(e, a ? a->data[i] : 0.0);
  }
  array_close(f, e);
}

static void put_piece(FILE *f, const tb_vtu_piece *p, const tb_vtu_array *const *all, int nall) {
  b64 e;
  long ncell = (long)p->ntet + p->ntri;
  fprintf(f, "    <Piece NumberOfPoints=\"%d\" NumberOfCells=\"%ld\">\n", p->nv, ncell);
  for (int cells = 0; cells < 2; cells++) {
    fputs(cells ? "      <CellData>\n" : "      <PointData>\n", f);
    for (int i = 0; i < nall; i++)
      if (!all[i]->on_cells == !cells)
        put_array(f, &e, all[i], find(p, all[i]), cells ? ncell : p->nv);
    fputs(cells ? "      </CellData>\n" : "      </PointData>\n", f);
  }
  fputs("      <Points>\n", f);
  array_open(f, &e, "Float64", NULL, 3, 24 * (uint64_t)p->nv);
  for (int i = 0; i < p->nv; i++) {
    b64_f64(&e, p->x[i].x);
    b64_f64(&e, p->x[i].y);
    b64_f64(&e, p->x[i].z);
  }
  array_close(f, &e);
  fputs("      </Points>\n      <Cells>\n", f);
  array_open(f, &e, "Int64", "connectivity", 1, 8 * (uint64_t)(4L * p->ntet + 3L * p->ntri));
  for (long i = 0; i < 4L * p->ntet; i++) b64_u64(&e, (uint64_t)p->tet[i]);
  for (long i = 0; i < 3L * p->ntri; i++) b64_u64(&e, (uint64_t)p->tri[i]);
  array_close(f, &e);
  array_open(f, &e, "Int64", "offsets", 1, 8 * (uint64_t)ncell);
  for (long i = 1; i <= ncell; i++)
    b64_u64(&e, (uint64_t)(i <= p->ntet ? 4 * i : 4L * p->ntet + 3 * (i - p->ntet)));
  array_close(f, &e);
  array_open(f, &e, "UInt8", "types", 1, (uint64_t)ncell);
  for (long i = 0; i < ncell; i++) b64_byte(&e, i < p->ntet ? 10 : 5);
  array_close(f, &e);
  fputs("      </Cells>\n    </Piece>\n", f);
}

static int close_out(FILE *f, const char *path, tb_error *err) {
  int bad = ferror(f), e = errno;
  if (fclose(f) != 0 || bad)
    return tb_error_set(err, path, 0, "write failed: %s", strerror(bad ? e : errno));
  return 0;
}

int tb_vtu_write(const char *path, const tb_vtu_piece *pieces, int npieces, tb_error *err) {
  if (npieces < 1 || !pieces) return tb_error_set(err, path, 0, "cannot write: no pieces");
  for (int k = 0; k < npieces; k++)
    if (check_piece(path, &pieces[k], k, err)) return -1;
  const tb_vtu_array **all;
  int nall = union_arrays(path, pieces, npieces, &all, err);
  if (nall < 0) return -1;
  FILE *f = fopen(path, "wb");
  if (!f) {
    free(all);
    return tb_error_set(err, path, 0, "cannot open for writing: %s", strerror(errno));
  }
  fputs(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
      "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n",
      f);
  for (int k = 0; k < npieces; k++) put_piece(f, &pieces[k], all, nall);
  fputs("  </UnstructuredGrid>\n</VTKFile>\n", f);
  free(all);
  return close_out(f, path, err);
}

int tb_pvd_write(const char *path, int n, const double *times, const char *const *files,
                 tb_error *err) {
  if (n < 0 || (n > 0 && (!times || !files)))
    return tb_error_set(err, path, 0, "cannot write: inconsistent collection");
  for (int i = 0; i < n; i++) {
    if (!files[i] || !*files[i])
      return tb_error_set(err, path, 0, "cannot write: data set %d has no file name", i);
    if (!isfinite(times[i]))
      return tb_error_set(err, path, 0, "cannot write: data set %d has a non-finite time", i);
  }
  FILE *f = fopen(path, "wb");
  if (!f) return tb_error_set(err, path, 0, "cannot open for writing: %s", strerror(errno));
  fputs(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
      "byte_order=\"LittleEndian\">\n  <Collection>\n",
      f);
  for (int i = 0; i < n; i++) {
    fprintf(f, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"", times[i]);
    put_escaped(f, files[i]);
    fputs("\"/>\n", f);
  }
  fputs("  </Collection>\n</VTKFile>\n", f);
  return close_out(f, path, err);
}

int tb_vtm_write(const char *path, int n, const char *const *names, const char *const *files,
                 tb_error *err) {
  for (int i = 0; i < n; i++)
    if (!names[i] || !*names[i] || !files[i] || !*files[i])
      return tb_error_set(err, path, 0, "cannot write: block %d has no name or file", i);
  FILE *f = fopen(path, "wb");
  if (!f) return tb_error_set(err, path, 0, "cannot open for writing: %s", strerror(errno));
  fputs(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" "
      "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <vtkMultiBlockDataSet>\n",
      f);
  for (int i = 0; i < n; i++) {
    fprintf(f, "    <DataSet index=\"%d\" name=\"", i);
    put_escaped(f, names[i]);
    fputs("\" file=\"", f);
    put_escaped(f, files[i]);
    fputs("\"/>\n", f);
  }
  fputs("  </vtkMultiBlockDataSet>\n</VTKFile>\n", f);
  return close_out(f, path, err);
}
