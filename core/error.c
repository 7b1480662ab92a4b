/* Error reports: "FILE:LINE: reason" strings for tb_error. */
#include "tb_error.h"

#include <stdarg.h>
#include <stdio.h>

int tb_error_set(tb_error *err, const char *file, long line, const char *fmt, ...) {
  if (!err) return -1;
  char reason[400];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(reason, sizeof reason, fmt, ap);
  va_end(ap);
  if (line > 0)
    snprintf(err->msg, sizeof err->msg, "%s:%ld: %s", file, line, reason);
  else
    snprintf(err->msg, sizeof err->msg, "%s: %s", file, reason);
  return -1;
}
