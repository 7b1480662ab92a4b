/* The renderer's state, shared by render/render.c (OSMesa, meshes, the
 * image) and render/text.c (FreeType labels); private to render/. */
#ifndef TB_RENDER_PRIV_H
#define TB_RENDER_PRIV_H

#include <GL/osmesa.h>

#include "tb_render.h"

/* FreeType's library and face, opaque here. */
typedef struct tb_text {
  void *lib, *face;
} tb_text;
int tb_text_open(tb_text *t, tb_error *err);
void tb_text_close(tb_text *t);

/* A label waiting to be drawn: text goes into the image after the last GL
 * draw (OSMesa may write its tiles back over anything drawn into the buffer
 * in between). */
typedef struct tb_label {
  double x, y, size;
  int align;
  float rgb[3];
  char text[120];
} tb_label;
#define TB_MAX_LABELS 64
/* Draws the labels into the buffer (render/text.c). */
void tb_text_draw(tb_renderer *r);

struct tb_renderer {
  OSMesaContext ctx;
  int w, h, ss;          /* image size, samples per pixel side */
  unsigned char *buf;    /* (w ss) x (h ss) RGBA, bottom row first (GL's order) */
  unsigned char *image;  /* w x h RGB, top row first */
  GLfloat *vx, *vn, *vc; /* scratch: per-vertex position, normal, colour */
  int cap;
  tb_text text;
  tb_label label[TB_MAX_LABELS];
  int nlabels;
};

#endif
