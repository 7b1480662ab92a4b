/* Error reports: "FILE:LINE: reason" strings for tb_error. Messages quote
 * text from files and command lines, so they are escaped once, here: control
 * bytes (C0, DEL, C1) and bytes that are not valid UTF-8 print as \xNN, so no
 * escape sequence from a file ever reaches the terminal. */
#include "tb_error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* Length of the valid UTF-8 sequence at s (1..4), 0 when not valid (RFC 3629:
 * shortest form, no surrogates, at most U+10FFFF). */
static int utf8_len(const unsigned char *s) {
  unsigned c = s[0];
  int n;
  unsigned lo = 0x80, hi = 0xBF;
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF)
    n = 2;
  else if (c >= 0xE0 && c <= 0xEF)
    n = 3;
  else if (c >= 0xF0 && c <= 0xF4)
    n = 4;
  else
    return 0;
  if (c == 0xE0) lo = 0xA0;
  if (c == 0xED) hi = 0x9F;
  if (c == 0xF0) lo = 0x90;
  if (c == 0xF4) hi = 0x8F;
  if (s[1] < lo || s[1] > hi) return 0;
  for (int k = 2; k < n; k++)
    if (s[k] < 0x80 || s[k] > 0xBF) return 0;
  return n;
}

static size_t tb_error_escape(char *out, size_t cap, const char *in) {
  const unsigned char *s = (const unsigned char *)in;
  size_t o = 0;
  if (cap == 0) return 0;
  while (*s) {
    int n = utf8_len(s);
    int ctl = n == 1 ? (s[0] < 0x20 || s[0] == 0x7F) : n == 2 && s[0] == 0xC2 && s[1] < 0xA0;
    if (n == 0 || ctl) {
      int k = n ? n : 1; /* a C1 control is escaped byte by byte */
      if (o + 4 * (size_t)k >= cap) break;
      for (int j = 0; j < k; j++) o += (size_t)snprintf(out + o, cap - o, "\\x%02X", s[j]);
      s += k;
    } else {
      if (o + (size_t)n >= cap) break;
      memcpy(out + o, s, (size_t)n);
      o += (size_t)n;
      s += n;
    }
  }
  out[o] = 0;
  return o;
}

int tb_error_set(tb_error *err, const char *file, long line, const char *fmt, ...) {
  if (!err) return -1;
  char reason[400], raw[sizeof err->msg];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(reason, sizeof reason, fmt, ap);
  va_end(ap);
  if (line > 0)
    snprintf(raw, sizeof raw, "%s:%ld: %s", file, line, reason);
  else
    snprintf(raw, sizeof raw, "%s: %s", file, reason);
  tb_error_escape(err->msg, sizeof err->msg, raw);
  return -1;
}
