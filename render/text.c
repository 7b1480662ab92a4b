/* Text in pictures: FreeType renders DejaVu Sans (Debian's fonts-dejavu-core)
 * into the renderer's supersampled buffer, blended by the glyphs' coverage,
 * so labels are anti-aliased like the rest of the picture and the same text
 * gives the same pixels. Labels are queued and drawn over the finished
 * picture when its pixels are read. */
#include <GL/gl.h>
#include <ft2build.h>
#include FT_FREETYPE_H
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render_priv.h"

#define FONT_FILE "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"

int tb_text_open(tb_text *t, tb_error *err) {
  memset(t, 0, sizeof *t);
  FT_Library lib;
  FT_Face face;
  if (FT_Init_FreeType(&lib))
    return tb_error_set(err, "render", 0, "cannot start FreeType (libfreetype6)");
  if (FT_New_Face(lib, FONT_FILE, 0, &face)) {
    FT_Done_FreeType(lib);
    return tb_error_set(err, FONT_FILE, 0, "cannot load the font (fonts-dejavu-core)");
  }
  t->lib = lib, t->face = face;
  return 0;
}

void tb_text_close(tb_text *t) {
  if (t->face) FT_Done_Face((FT_Face)t->face);
  if (t->lib) FT_Done_FreeType((FT_Library)t->lib);
  memset(t, 0, sizeof *t);
}

/* The advance of s in pixels at the face's current size. */
static double width(FT_Face face, const char *s) {
  double w = 0;
  for (; *s; s++)
    if (!FT_Load_Char(face, (unsigned char)*s, FT_LOAD_DEFAULT)) w += face->glyph->advance.x / 64.0;
  return w;
}

void tb_renderer_text(tb_renderer *r, double x, double y, double size, int align,
                      const float rgb[3], const char *s) {
  if (r->nlabels == TB_MAX_LABELS) return;
  tb_label *l = &r->label[r->nlabels++];
  l->x = x, l->y = y, l->size = size, l->align = align;
  memcpy(l->rgb, rgb, sizeof l->rgb);
  snprintf(l->text, sizeof l->text, "%s", s);
}

/* One label into the buffer, blended by the glyphs' coverage. */
static void draw(tb_renderer *r, FT_Face face, const tb_label *l) {
  int ss = r->ss, W = r->w * ss, H = r->h * ss;
  int px = (int)lround(l->size * H);
  if (px < 1 || FT_Set_Pixel_Sizes(face, 0, (FT_UInt)px)) return;
  const char *s = l->text;
  double pen = l->x * W - (l->align > 0    ? width(face, s)
                           : l->align == 0 ? 0.5 * width(face, s)
                                           : 0);
  int base = (int)lround(l->y * H);
  for (; *s; s++) {
    if (FT_Load_Char(face, (unsigned char)*s, FT_LOAD_RENDER)) continue;
    FT_GlyphSlot g = face->glyph;
    int x0 = (int)lround(pen) + g->bitmap_left;
    for (unsigned j = 0; j < g->bitmap.rows; j++) {
      int yy = base + g->bitmap_top - 1 - (int)j; /* the buffer's first row is the bottom */
      if (yy < 0 || yy >= H) continue;
      for (unsigned i = 0; i < g->bitmap.width; i++) {
        int xx = x0 + (int)i;
        if (xx < 0 || xx >= W) continue;
        double a = g->bitmap.buffer[j * (unsigned)g->bitmap.pitch + i] / 255.0;
        unsigned char *p = r->buf + 4 * ((size_t)yy * W + xx);
        for (int c = 0; c < 3; c++)
          p[c] = (unsigned char)lround(p[c] * (1 - a) + 255 * l->rgb[c] * a);
      }
    }
    pen += g->advance.x / 64.0;
  }
}

void tb_text_draw(tb_renderer *r) {
  glFinish();
  for (int k = 0; r->text.face && k < r->nlabels; k++) draw(r, (FT_Face)r->text.face, &r->label[k]);
  r->nlabels = 0;
}
