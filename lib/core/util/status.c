#include <clothbench/status.h>

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* Allocation-failure injection (status.h): the countdown to the failing
 * allocation of this thread, 0 when off, and the allocations counted since it
 * was armed. The normal path pays one thread-local test per allocation, and
 * allocations happen at set-up only. */
static _Thread_local long fail_at, counted;

void cb_alloc_fail_at(long k) {
  fail_at = k > 0 ? k : 0;
  counted = 0;
}

long cb_alloc_count(void) { return counted; }

int cb_alloc_tick(void) {
  if (fail_at <= 0) return 0;
  counted++;
  return fail_at > 0 && counted == fail_at;
}

/* n*size, or 0 when it overflows (after setting the message); n, size >= 1 */
static size_t checked_bytes(size_t n, size_t size) {
  if (n > SIZE_MAX / size) {
    cb_fail_status(CB_ENOMEM, "allocation of %zu x %zu bytes overflows", n, size);
    return 0;
  }
  return n * size;
}

static void *out_of_memory(size_t bytes) {
  cb_fail_status(CB_ENOMEM, "out of memory allocating %zu bytes", bytes);
  return NULL;
}

void *cb_calloc(size_t n, size_t size) {
  if (n == 0 || size == 0) n = size = 1;
  size_t bytes = checked_bytes(n, size);
  if (!bytes) return NULL;
  void *p = cb_alloc_tick() ? NULL : calloc(n, size);
  return p ? p : out_of_memory(bytes);
}

void *cb_calloc_aligned(size_t n, size_t size) {
  if (n == 0 || size == 0) n = size = 1;
  size_t bytes = checked_bytes(n, size);
  if (!bytes) return NULL;
  void *p = NULL;
  if (!cb_alloc_tick() && posix_memalign(&p, CB_CACHE_LINE, bytes) != 0) p = NULL;
  if (!p) return out_of_memory(bytes);
  memset(p, 0, bytes);
  return p;
}

void *cb_malloc(size_t n, size_t size) {
  if (n == 0 || size == 0) n = size = 1;
  size_t bytes = checked_bytes(n, size);
  if (!bytes) return NULL;
  void *p = cb_alloc_tick() ? NULL : malloc(bytes);
  return p ? p : out_of_memory(bytes);
}

void *cb_realloc(void *p, size_t n, size_t size) {
  if (n == 0 || size == 0) n = size = 1;
  size_t bytes = checked_bytes(n, size);
  if (!bytes) return NULL;
  void *q = cb_alloc_tick() ? NULL : realloc(p, bytes);
  return q ? q : out_of_memory(bytes);
}
