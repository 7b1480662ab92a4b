/* Private to the scene-file reader (scenes/scene_file.c, scene_values.c). */
#ifndef TB_SCENE_PRIV_H
#define TB_SCENE_PRIV_H

#include "tb_scene_file.h"

/* "1.5", "amplitude", "0.5*release", "-amplitude" into e; -1 when not. */
int tb_scene_parse_expr(const char *s, tb_expr *e);
/* Comma-separated expressions, between nmin and n of them; the count or -1. */
int tb_scene_parse_list(const char *s, tb_expr *out, int nmin, int n);

#endif
