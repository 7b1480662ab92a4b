/* Error reports for everything that reads input: "FILE:LINE: reason".
 * Functions that can fail take a tb_error* last and return 0 on success,
 * non-zero on failure with err->msg filled in. err may be NULL. */
#ifndef TB_ERROR_H
#define TB_ERROR_H

typedef struct tb_error {
  char msg[512];
} tb_error;

/* Formats "file:line: reason" (line 0 prints "file: reason") into err and
 * returns -1, so callers can write `return tb_error_set(err, f, n, "...")`. */
int tb_error_set(tb_error *err, const char *file, long line, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif
