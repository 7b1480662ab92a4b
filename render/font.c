/* A stroke font for the renderer's labels (colour-bar numbers and names):
 * each glyph is line segments on a 4 x 6 grid, drawn with GL lines, so
 * pictures never depend on a font file. Upper and lower case draw alike;
 * characters without a glyph leave a space. */
#include <GL/gl.h>
#include <ctype.h>
#include <string.h>

/* Glyph segments as "x1y1x2y2" digit quadruples, separated by spaces. */
static const char *glyph(char c) {
  static const struct {
    char c;
    const char *s;
  } g[] = {
      {'0', "0040 4046 4606 0600 0046"},
      {'1', "2026 2615 1030"},
      {'2', "0646 4643 4303 0300 0040"},
      {'3', "0646 4640 4000 1343"},
      {'4', "0603 0343 4640"},
      {'5', "4606 0603 0343 4340 4000"},
      {'6', "4606 0600 0040 4043 4303"},
      {'7', "0646 4620"},
      {'8', "0040 4046 4606 0600 0343"},
      {'9', "4303 0306 0646 4640 4000"},
      {'.', "2021"},
      {'-', "0343"},
      {'+', "0343 2125"},
      {'e', "0242 4244 4404 0400 0040"},
      {'a', "0444 4440 4000 0002 0242"},
      {'b', "0006 0040 4043 4303"},
      {'c', "4303 0300 0040"},
      {'d', "4046 4003 0300 0040"},
      {'f', "1016 1646 0333"},
      {'g', "4303 0300 0040 4142 4346"},
      {'h', "0006 0343 4340"},
      {'i', "2023 2425"},
      {'k', "0006 0246 0240"},
      {'l', "2026"},
      {'m', "0003 0343 4340 2023"},
      {'n', "0003 0343 4340"},
      {'o', "0040 4043 4303 0300"},
      {'p', "0006 0646 4643 4303"},
      {'r', "0003 0343"},
      {'s', "4303 0302 0242 4240 4000"},
      {'t', "2026 1333 2040"},
      {'u', "0300 0040 4043"},
      {'v', "0320 2043"},
      {'w', "0300 0040 4043 2023"},
      {'x', "0043 0340"},
      {'y', "0320 4310"},
      {'z', "0343 4300 0040"},
      {'(', "3616 1610 1030"},
      {')', "1636 3630 3010"},
      {'/', "0046"},
      {'%', "0046 0515 3141"},
      {'_', "0040"},
  };
  c = (char)tolower((unsigned char)c);
  for (size_t k = 0; k < sizeof g / sizeof g[0]; k++)
    if (g[k].c == c) return g[k].s;
  return "";
}

/* Draws s with its lower-left corner at (x, y), glyphs size high. */
void tb_stroke_text(double x, double y, double size, const char *s) {
  double u = size / 6;
  glBegin(GL_LINES);
  for (; *s; s++, x += 5.5 * u) {
    const char *g = glyph(*s);
    for (size_t k = 0; k + 4 <= strlen(g); k += 5) {
      glVertex2d(x + u * (g[k] - '0'), y + u * (g[k + 1] - '0'));
      glVertex2d(x + u * (g[k + 2] - '0'), y + u * (g[k + 3] - '0'));
    }
  }
  glEnd();
}
