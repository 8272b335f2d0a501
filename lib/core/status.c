#include <clothbench/status.h>

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static _Thread_local char message[1024];

const char *cb_status_name(int status) {
  switch (status) {
  case CB_OK: return "ok";
  case CB_EINVAL: return "bad_input";
  case CB_ENOMEM: return "out_of_memory";
  case CB_EIO: return "io_error";
  case CB_NOT_SPD: return "not_spd";
  case CB_NOT_CONVERGED: return "max_iters";
  case CB_DIVERGED: return "diverged";
  case CB_INDEFINITE: return "indefinite";
  case CB_LS_FAILED: return "line_search_failed";
  case CB_LINEAR_FAILED: return "linear_failed";
  default: return "unknown";
  }
}

const char *cb_error_message(void) { return message; }

void cb_error_clear(void) { message[0] = '\0'; }

static void vset(const char *fmt, va_list ap) { vsnprintf(message, sizeof message, fmt, ap); }

int cb_fail(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vset(fmt, ap);
  va_end(ap);
  return CB_EINVAL;
}

int cb_fail_status(int status, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vset(fmt, ap);
  va_end(ap);
  return status;
}

int cb_status_is_fatal(int status) { return status != CB_OK && status != CB_NOT_CONVERGED; }

void *cb_calloc(size_t n, size_t size) {
  if (n == 0 || size == 0) n = size = 1;
  if (n > SIZE_MAX / size) {
    cb_fail_status(CB_ENOMEM, "allocation of %zu x %zu bytes overflows", n, size);
    return NULL;
  }
  void *p = calloc(n, size);
  if (!p) cb_fail_status(CB_ENOMEM, "out of memory allocating %zu bytes", n * size);
  return p;
}

void *cb_malloc(size_t n, size_t size) {
  if (n == 0 || size == 0) n = size = 1;
  if (n > SIZE_MAX / size) {
    cb_fail_status(CB_ENOMEM, "allocation of %zu x %zu bytes overflows", n, size);
    return NULL;
  }
  void *p = malloc(n * size);
  if (!p) cb_fail_status(CB_ENOMEM, "out of memory allocating %zu bytes", n * size);
  return p;
}
