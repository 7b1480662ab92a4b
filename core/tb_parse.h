/* Strict parsing of values given as text on the command line: three
 * comma-separated finite numbers "x,y,z"; and inih's settings for every
 * INI file tissuebench reads. */
#ifndef TB_PARSE_H
#define TB_PARSE_H

#include "tb_math.h"

/* Parses "x,y,z" at the start of s into *out; *rest (may be NULL) points
 * past the third number. Returns -1 (out untouched) when s does not start
 * with three finite numbers separated by commas. */
int tb_parse_vec3(const char *s, tb_vec3 *out, const char **rest);

/* inih with one behaviour for every INI file (scenes, shard.ini,
 * cases.ini): no continuation lines, '#' and ';' comments, lines of any
 * length, the first error ends the parse. Call before ini_parse_*. */
void tb_ini_setup(void);

#endif
