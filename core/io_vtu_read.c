/* .vtu reader (core/tb_vtu.h): the XML is parsed by expat; inline binary
 * DataArrays are base64-decoded as their text arrives (whitespace skipped,
 * '=' padding allowed mid-stream, so a header encoded apart from its data
 * also reads) and checked against their byte-count header and the piece's
 * declared counts. Points, cells and the optional requested array are kept;
 * every other array is decoded (to check it) and dropped. Arrays grow with
 * the data present, never sized by a count the file declares. */
#include <errno.h>
#include <expat.h>
#include <limits.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"
#include "tb_vtu.h"

enum { SEC_NONE, SEC_POINTDATA, SEC_CELLDATA, SEC_POINTS, SEC_CELLS };
enum { ARR_SKIP, ARR_POINTS, ARR_CONN, ARR_OFFS, ARR_TYPES, ARR_FIELD };

/* Bytes of one value of a VTK scalar type, 0 for unknown; *real: floating. */
static int type_size(const char *t, int *real) {
  static const struct {
    const char *name;
    int size, real;
  } types[] = {{"Int8", 1, 0},    {"UInt8", 1, 0},   {"Int16", 2, 0}, {"UInt16", 2, 0},
               {"Int32", 4, 0},   {"UInt32", 4, 0},  {"Int64", 8, 0}, {"UInt64", 8, 0},
               {"Float32", 4, 1}, {"Float64", 8, 1}, {"Char", 1, 0},  {"UChar", 1, 0}};
  for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
    if (!strcmp(t, types[i].name)) return *real = types[i].real, types[i].size;
  return 0;
}

typedef struct vr {
  const char *path;
  tb_error *err;
  XML_Parser xp;
  tb_build *b;
  tb_vtu_field *field;
  int fieldcap, failed, depth, root, header8, section, in_piece, npieces;
  long piece_nv, piece_ncell, cells_before; /* cells of earlier pieces */
  int vbase;                                /* points of earlier pieces */
  /* the DataArray being read */
  int arr, adepth, size, real, sign, ncomp; /* adepth: its element depth */
  long line;
  unsigned char *bytes;
  long nbytes;
  int capbytes;
  int quad[4], nq, npad;
  /* the current piece's cells, as read */
  long long *cell[3]; /* connectivity, offsets, types */
  long ncell[3], cline[3];
  int have_points, field_in_piece;
  long nl, lastline; /* newlines read; the file's last line (0: empty) */
} vr;

static int fail(vr *r, long line, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail(vr *r, long line, const char *fmt, ...) {
  char reason[400];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(reason, sizeof reason, fmt, ap);
  va_end(ap);
  if (!r->failed) tb_error_set(r->err, r->path, line, "%s", reason);
  r->failed = 1;
  XML_StopParser(r->xp, XML_FALSE);
  return -1;
}

static long here(vr *r) { return (long)XML_GetCurrentLineNumber(r->xp); }

static const char *attr(const char **a, const char *key) {
  for (; a[0]; a += 2)
    if (!strcmp(a[0], key)) return a[1];
  return NULL;
}

/* A count attribute 0..INT_MAX (absent: dflt, or an error when dflt < 0). */
static int count_attr(vr *r, const char **a, const char *key, long dflt, long *v) {
  const char *s = attr(a, key);
  if (!s) {
    if (dflt >= 0) return *v = dflt, 0;
    return fail(r, here(r), "missing attribute %s", key);
  }
  if (tb_parse_long(s, v) || *v < 0 || *v > INT_MAX)
    return fail(r, here(r), "%s=\"%.40s\" is not a count", key, s);
  return 0;
}

/* ---- little-endian values ---- */
static uint64_t get_bits(const unsigned char *p, int size) {
  uint64_t u = 0;
  for (int k = 0; k < size; k++) u |= (uint64_t)p[k] << (8 * k);
  return u;
}

static double get_real(const vr *r, const unsigned char *p) {
  uint64_t u = get_bits(p, r->size);
  if (r->real && r->size == 8) {
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
  }
  if (r->real) {
    uint32_t w = (uint32_t)u;
    float f;
    memcpy(&f, &w, sizeof f);
    return f;
  }
  if (r->sign && r->size < 8 && (u >> (8 * r->size - 1)) & 1) u |= ~(uint64_t)0 << (8 * r->size);
  return r->sign ? (double)(int64_t)u : (double)u;
}

/* An integer value; 0, or -1 when it does not fit a long long. */
static int get_int(const vr *r, const unsigned char *p, long long *v) {
  uint64_t u = get_bits(p, r->size);
  if (r->sign && r->size < 8 && (u >> (8 * r->size - 1)) & 1) u |= ~(uint64_t)0 << (8 * r->size);
  if (!r->sign && u > (uint64_t)LLONG_MAX) return -1;
  *v = (long long)u;
  return 0;
}

/* ---- base64 ---- */
static int sextet(int c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  return c == '+' ? 62 : c == '/' ? 63 : -1;
}

static int put_byte(vr *r, unsigned char c) {
  if (r->nbytes >= r->capbytes) {
    unsigned char *p = tb_io_grow(r->bytes, &r->capbytes, r->nbytes + 1, 1);
    if (!p) return fail(r, r->line, "out of memory (DataArray of %ld bytes)", r->nbytes);
    r->bytes = p;
  }
  r->bytes[r->nbytes++] = c;
  return 0;
}

static void XMLCALL on_text(void *ud, const XML_Char *s, int len) {
  vr *r = ud;
  if (r->failed || !r->arr || r->depth != r->adepth) return; /* not in nested elements */
  for (int i = 0; i < len; i++) {
    int c = (unsigned char)s[i];
    if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    int v = c == '=' ? 0 : sextet(c);
    if (v < 0 || (c != '=' && r->npad) || (c == '=' && r->nq < 2)) {
      fail(r, here(r), "DataArray: invalid base64 data ('%c')", c);
      return;
    }
    r->npad += c == '=';
    r->quad[r->nq++] = v;
    if (r->nq < 4) continue;
    unsigned long w = (unsigned long)r->quad[0] << 18 | (unsigned long)r->quad[1] << 12 |
                      (unsigned long)r->quad[2] << 6 | (unsigned long)r->quad[3];
    for (int k = 0; k < 3 - r->npad; k++)
      if (put_byte(r, (unsigned char)(w >> (16 - 8 * k)))) return;
    r->nq = r->npad = 0;
  }
}

/* ---- elements ---- */
static void start_array(vr *r, const char **a) {
  const char *type = attr(a, "type"), *name = attr(a, "Name"), *format = attr(a, "format");
  long nc;
  r->line = here(r);
  r->arr = ARR_SKIP;
  r->adepth = r->depth;
  if (!type || !(r->size = type_size(type, &r->real))) {
    fail(r, r->line, "DataArray: unknown type '%.40s'", type ? type : "(none)");
    return;
  }
  r->sign = type[0] == 'I' || !strcmp(type, "Char");
  if (count_attr(r, a, "NumberOfComponents", 1, &nc)) return;
  if (nc < 1) {
    fail(r, r->line, "DataArray with 0 components");
    return;
  }
  r->ncomp = (int)nc;
  if (r->section == SEC_POINTS) {
    r->arr = ARR_POINTS;
  } else if (r->section == SEC_CELLS) {
    r->arr = !name                           ? ARR_SKIP
             : !strcmp(name, "connectivity") ? ARR_CONN
             : !strcmp(name, "offsets")      ? ARR_OFFS
             : !strcmp(name, "types")        ? ARR_TYPES
                                             : ARR_SKIP;
  } else if (r->field && name && !strcmp(name, r->field->name) &&
             (r->section == SEC_CELLDATA) == !!r->field->on_cells &&
             (r->section == SEC_CELLDATA || r->section == SEC_POINTDATA)) {
    r->arr = ARR_FIELD;
  }
  if (r->arr != ARR_SKIP && r->arr != ARR_POINTS && r->arr != ARR_FIELD && r->real) {
    fail(r, r->line, "DataArray '%s' of type %s (expected an integer type)", name, type);
    return;
  }
  if (r->arr == ARR_POINTS && (!r->real || r->ncomp != 3)) {
    fail(r, r->line, "Points: %d-component %s (expected 3-component Float32/Float64)", r->ncomp,
         type);
    return;
  }
  if (r->arr == ARR_POINTS && r->have_points) {
    fail(r, r->line, "second Points array in one piece");
    return;
  }
  int binary = format && !strcmp(format, "binary");
  if (!binary && r->arr != ARR_SKIP) {
    fail(r, r->line, "DataArray format '%.20s' not supported (reads inline binary)",
         format ? format : "(none)");
    return;
  }
  /* arrays not kept: binary ones are decoded to check them (-1), others ignored */
  r->arr = r->arr != ARR_SKIP ? r->arr : binary ? -1 : ARR_SKIP;
  r->nbytes = 0;
  r->nq = r->npad = 0;
}

/* The decoded array's values (they start at values(r)): checks the header
 * against the data and the expected number of tuples (< 0: any); returns
 * the value count or -1. */
static const unsigned char *values(const vr *r) { return r->bytes + (r->header8 ? 8 : 4); }

static long payload(vr *r, const char *what, long tuples) {
  int h = r->header8 ? 8 : 4;
  if (r->nq)
    return fail(r, r->line, "%s: truncated base64 data (%d characters after the last group of 4)",
                what, r->nq);
  if (r->nbytes < h)
    return fail(r, r->line, "%s: %ld bytes of data, shorter than its %d-byte header", what,
                r->nbytes, h);
  uint64_t n = get_bits(r->bytes, h);
  if (n != (uint64_t)(r->nbytes - h))
    return fail(r, r->line, "%s: header says %llu bytes, the data holds %ld%s", what,
                (unsigned long long)n, r->nbytes - h,
                n > (uint64_t)(r->nbytes - h) ? " (truncated)" : "");
  long vals = (long)(n / (uint64_t)r->size);
  if (n % (uint64_t)r->size || vals % r->ncomp)
    return fail(r, r->line, "%s: %llu bytes is not a whole number of %d-component values", what,
                (unsigned long long)n, r->ncomp);
  if (tuples >= 0 && vals / r->ncomp != tuples)
    return fail(r, r->line, "%s: %ld tuples, the piece declares %ld", what, vals / r->ncomp,
                tuples);
  return vals;
}

static void end_array(vr *r) {
  int arr = r->arr;
  r->arr = ARR_SKIP;
  if (arr == ARR_POINTS) {
    long n = payload(r, "Points", r->piece_nv);
    if (n < 0) return;
    for (long i = 0; i < n; i += 3) {
      const unsigned char *p = values(r) + i * r->size;
      tb_vec3 x = tb_v3(get_real(r, p), get_real(r, p + r->size), get_real(r, p + 2 * r->size));
      int bad = tb_build_vert(r->b, x);
      if (bad > 0) {
        fail(r, r->line, "Points: point %ld (%g, %g, %g) is not finite or beyond +-%g", i / 3, x.x,
             x.y, x.z, TB_COORD_MAX);
        return;
      }
      if (bad) {
        fail(r, r->line, "out of memory");
        return;
      }
    }
    r->have_points = 1;
  } else if (arr == ARR_CONN || arr == ARR_OFFS || arr == ARR_TYPES) {
    static const char *const names[] = {"connectivity", "offsets", "types"};
    int k = arr - ARR_CONN;
    long n = payload(r, names[k], k == 0 ? -1 : r->piece_ncell);
    if (n < 0) return;
    if (r->cell[k]) {
      fail(r, r->line, "second '%s' array in one piece", names[k]);
      return;
    }
    r->cell[k] = malloc(sizeof(long long) * (size_t)(n > 0 ? n : 1));
    if (!r->cell[k]) {
      fail(r, r->line, "out of memory");
      return;
    }
    for (long i = 0; i < n; i++)
      if (get_int(r, values(r) + i * r->size, &r->cell[k][i])) {
        fail(r, r->line, "%s: value %ld out of range", names[k], i);
        return;
      }
    r->ncell[k] = n;
    r->cline[k] = r->line;
  } else if (arr == ARR_FIELD) {
    tb_vtu_field *f = r->field;
    long n = payload(r, f->name, f->on_cells ? r->piece_ncell : r->piece_nv);
    if (n < 0) return;
    if (r->field_in_piece++) {
      fail(r, r->line, "array '%s' twice in one piece", f->name);
      return;
    }
    if (f->ntuples > 0 && f->ncomp != r->ncomp) {
      fail(r, r->line, "array '%s' has %d components here, %d before", f->name, r->ncomp, f->ncomp);
      return;
    }
    f->ncomp = r->ncomp;
    long have = (long)f->ntuples * f->ncomp;
    double *d = tb_io_grow(f->data, &r->fieldcap, have + n, sizeof *d);
    if (!d) {
      fail(r, r->line, "out of memory");
      return;
    }
    f->data = d;
    for (long i = 0; i < n; i++) d[have + i] = get_real(r, values(r) + i * r->size);
    f->ntuples += (int)(n / r->ncomp);
  } else if (arr < 0) {
    payload(r, "DataArray", -1);
  }
}

/* Points per cell of the VTK linear and quadratic cell types we skip (0:
 * any count, as for polygons), -1 for types we do not know. */
static int skipped_type(long long t) {
  static const int npts[] = {-1, 1,  0,  2, 0, 3, 0,  0,  4,  4,  4, 8,  8,  6, 5,  -1, -1, -1,
                             -1, -1, -1, 3, 6, 8, 10, 20, 15, 13, 9, 27, 18, 6, 10, 12, 7,  13};
  return t >= 0 && t < (long long)(sizeof npts / sizeof npts[0]) ? npts[t] : -1;
}

static void end_piece(vr *r) {
  long long *conn = r->cell[0], *offs = r->cell[1], *types = r->cell[2];
  if (!r->have_points && r->piece_nv > 0) {
    fail(r, here(r), "piece %d declares %ld points but has no Points", r->npieces, r->piece_nv);
    return;
  }
  if (r->piece_ncell > 0 && (!conn || !offs || !types)) {
    fail(r, here(r), "piece %d declares %ld cells but lacks connectivity, offsets or types",
         r->npieces, r->piece_ncell);
    return;
  }
  long long prev = 0;
  for (long c = 0; c < r->piece_ncell; c++) {
    long long end = offs[c], n = end - prev, t = types[c];
    if (end < prev || end > r->ncell[0]) {
      fail(r, r->cline[1], "offsets: cell %ld ends at %lld (after %lld, %ld indices in all)", c,
           end, prev, r->ncell[0]);
      return;
    }
    int v[4];
    for (long long i = prev; i < end; i++)
      if (conn[i] < 0 || conn[i] >= r->piece_nv) {
        fail(r, r->cline[0], "connectivity: cell %ld uses point %lld of %ld", c, conn[i],
             r->piece_nv);
        return;
      } else if (i - prev < 4) {
        v[i - prev] = r->vbase + (int)conn[i];
      }
    int want = t == 10 ? 4 : t == 5 ? 3 : skipped_type(t);
    if (want < 0) {
      fail(r, r->cline[2], "types: unknown cell type %lld (cell %ld; reads 10 tetra, 5 triangle)",
           t, c);
      return;
    }
    if (want > 0 && n != want) {
      fail(r, r->cline[1], "offsets: cell %ld of type %lld has %lld points, not %d", c, t, n, want);
      return;
    }
    int bad = t == 10 ? tb_build_tet(r->b, v) : t == 5 ? tb_build_tri(r->b, v[0], v[1], v[2]) : 0;
    if (t != 10 && t != 5) r->b->m.nskipped++;
    if (bad) {
      fail(r, here(r), "out of memory");
      return;
    }
    prev = end;
  }
  if (prev != r->ncell[0]) {
    fail(r, r->cline[1], "offsets end at %lld, connectivity holds %ld indices", prev, r->ncell[0]);
    return;
  }
  if (r->field && r->field->ntuples > 0 && !r->field_in_piece) {
    fail(r, here(r), "array '%s' missing from piece %d", r->field->name, r->npieces);
    return;
  }
  r->vbase = r->b->m.nv;
  r->cells_before += r->piece_ncell;
}

static void free_cells(vr *r) {
  for (int k = 0; k < 3; k++) free(r->cell[k]), r->cell[k] = NULL, r->ncell[k] = 0;
}

static void XMLCALL on_start(void *ud, const XML_Char *name, const XML_Char **a) {
  vr *r = ud;
  if (r->failed) return;
  r->depth++;
  if (r->depth == 1) {
    const char *type = attr(a, "type"), *bo = attr(a, "byte_order"), *ht = attr(a, "header_type");
    if (strcmp(name, "VTKFile")) {
      fail(r, here(r), "not a VTK XML file (root element <%.40s>)", name);
    } else if (!type || strcmp(type, "UnstructuredGrid")) {
      fail(r, here(r), "VTKFile type '%.40s' not supported (reads UnstructuredGrid)",
           type ? type : "(none)");
    } else if (bo && strcmp(bo, "LittleEndian")) {
      fail(r, here(r), "byte_order '%.40s' not supported (reads LittleEndian)", bo);
    } else if (ht && strcmp(ht, "UInt32") && strcmp(ht, "UInt64")) {
      fail(r, here(r), "header_type '%.40s' not supported (UInt32 or UInt64)", ht);
    } else if (attr(a, "compressor")) {
      fail(r, here(r), "compressed data (%.60s) not supported", attr(a, "compressor"));
    }
    r->header8 = ht && !strcmp(ht, "UInt64");
    r->root = 1;
    return;
  }
  if (!strcmp(name, "AppendedData")) {
    fail(r, here(r), "appended data not supported (reads inline binary DataArrays)");
  } else if (!strcmp(name, "Piece")) {
    if (r->in_piece) {
      fail(r, here(r), "Piece inside a Piece");
      return;
    }
    r->in_piece = 1;
    r->have_points = r->field_in_piece = 0;
    free_cells(r);
    if (count_attr(r, a, "NumberOfPoints", -1, &r->piece_nv) ||
        count_attr(r, a, "NumberOfCells", -1, &r->piece_ncell))
      return;
    if ((long)r->b->m.nv + r->piece_nv > INT_MAX)
      fail(r, here(r), "more than %d points in all", INT_MAX);
  } else if (!strcmp(name, "DataArray")) {
    if (r->in_piece && r->section != SEC_NONE) start_array(r, a); /* else: field data, ignored */
  } else if (r->in_piece && r->section == SEC_NONE) {
    r->section = !strcmp(name, "PointData")  ? SEC_POINTDATA
                 : !strcmp(name, "CellData") ? SEC_CELLDATA
                 : !strcmp(name, "Points")   ? SEC_POINTS
                 : !strcmp(name, "Cells")    ? SEC_CELLS
                                             : SEC_NONE;
  }
}

static void XMLCALL on_end(void *ud, const XML_Char *name) {
  vr *r = ud;
  if (r->failed) return;
  int depth = r->depth--;
  if (r->arr && depth == r->adepth) { /* the DataArray itself, not an element inside it */
    end_array(r);
    return;
  }
  if (r->in_piece && !strcmp(name, "Piece")) {
    end_piece(r);
    free_cells(r);
    r->in_piece = 0;
    r->npieces++;
  } else if (r->section != SEC_NONE && (!strcmp(name, "PointData") || !strcmp(name, "CellData") ||
                                        !strcmp(name, "Points") || !strcmp(name, "Cells"))) {
    r->section = SEC_NONE;
  }
}

static int parse(vr *r) {
  FILE *f = tb_io_open(r->path, r->err);
  if (!f) return -1;
  int rc = 0;
  for (int done = 0; !done && rc == 0;) {
    void *buf = XML_GetBuffer(r->xp, 1 << 16);
    if (!buf) {
      rc = tb_error_set(r->err, r->path, 0, "out of memory");
      break;
    }
    size_t n = fread(buf, 1, 1 << 16, f);
    if (ferror(f)) {
      rc = tb_error_set(r->err, r->path, 0, "read error: %s", strerror(errno));
      break;
    }
    done = n < (1 << 16);
    for (size_t i = 0; i < n; i++) r->nl += ((const char *)buf)[i] == '\n';
    if (n) r->lastline = r->nl + (((const char *)buf)[n - 1] != '\n');
    if (XML_ParseBuffer(r->xp, (int)n, done) != XML_STATUS_OK) {
      long line = (long)XML_GetCurrentLineNumber(r->xp); /* past the end at end of file */
      rc = r->failed ? -1
                     : tb_error_set(r->err, r->path, line < r->lastline ? line : r->lastline,
                                    "XML error: %s", XML_ErrorString(XML_GetErrorCode(r->xp)));
    }
  }
  fclose(f);
  if (rc == 0 && r->failed) rc = -1;
  return rc;
}

static int read_vtu(const char *path, tb_build *b, tb_vtu_field *field, tb_error *err) {
  vr r;
  memset(&r, 0, sizeof r);
  r.path = path, r.err = err, r.b = b, r.field = field;
  if (field) field->ncomp = field->ntuples = 0, field->data = NULL;
  if (field && (!field->name || !*field->name))
    return tb_error_set(err, path, 0, "no array name requested");
  r.xp = XML_ParserCreate(NULL);
  if (!r.xp) return tb_error_set(err, path, 0, "out of memory");
  XML_SetUserData(r.xp, &r);
  XML_SetElementHandler(r.xp, on_start, on_end);
  XML_SetCharacterDataHandler(r.xp, on_text);
  int rc = parse(&r);
  long lines = r.lastline; /* errors at end of file cite its last line */
  XML_ParserFree(r.xp);
  free_cells(&r);
  free(r.bytes);
  if (rc == 0 && r.npieces == 0) rc = tb_error_set(err, path, lines, "no Piece");
  if (rc == 0 && b->m.nv == 0) rc = tb_error_set(err, path, lines, "no points");
  if (rc == 0 && field && field->ntuples == 0)
    rc = tb_error_set(err, path, 0, "no %s array '%s'",
                      field->on_cells ? "cell-data" : "point-data", field->name);
  if (rc == 0 && field && field->ntuples != (field->on_cells ? r.cells_before : b->m.nv))
    rc = tb_error_set(err, path, 0, "array '%s' is not in every piece", field->name);
  if (rc && field) free(field->data), field->data = NULL, field->ncomp = field->ntuples = 0;
  return rc;
}

int tb_read_vtu(const char *path, tb_build *b, tb_error *err) {
  return read_vtu(path, b, NULL, err);
}

int tb_vtu_read(const char *path, tb_mesh *m, tb_vtu_field *field, tb_error *err) {
  tb_build b;
  memset(&b, 0, sizeof b);
  memset(m, 0, sizeof *m);
  if (read_vtu(path, &b, field, err)) {
    tb_build_free(&b);
    return -1;
  }
  *m = b.m;
  return 0;
}
