/* Status codes and error messages shared by every module.
 *
 * Convention (CHOLMOD's common->status): 0 is ok, negative is an error in the
 * input or the environment, positive is a numerical event that the caller
 * records as a status and never turns into a crash. */
#ifndef CB_STATUS_H
#define CB_STATUS_H

#include <stddef.h>

enum {
  CB_OK = 0,
  CB_EINVAL = -1, /* bad input: malformed config, broken OBJ, degenerate mesh */
  CB_ENOMEM = -2, /* out of memory */
  CB_EIO = -3,    /* a file could not be read or written */

  CB_NOT_SPD = 1,       /* Cholesky met a non-positive pivot */
  CB_NOT_CONVERGED = 2, /* an iteration stopped at max_iters above tolerance */
  CB_DIVERGED = 3,      /* NaN/Inf, or growth past a documented bound */
  CB_INDEFINITE = 4,    /* CG breakdown: p^T A p <= 0 */
  CB_LS_FAILED = 5,     /* line search found no decrease (not a descent direction) */
  CB_LINEAR_FAILED = 6  /* the inner linear solve failed (its own status is recorded); out of memory
                           in it is CB_ENOMEM instead */
};

/* Short snake_case name of a status, as written to CSV ("ok", "not_spd", ...). */
const char *cb_status_name(int status);

/* The last error message set in this thread (never NULL; "" if none). */
const char *cb_error_message(void);
/* Sets the message (printf-style) and returns CB_EINVAL, for `return cb_fail(...)`. */
int cb_fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Same, with an explicit status to return. */
int cb_fail_status(int status, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void cb_error_clear(void);

/* Whether a step status ends a trajectory: everything but ok and
 * not_converged (Newton at max_iters, e.g. Baraff-Witkin's single iteration). */
int cb_status_is_fatal(int status);

/* malloc/calloc/realloc that set an error message (and CB_ENOMEM's) on
 * failure. n*size overflow is checked. cb_realloc leaves p allocated when it
 * fails, as realloc does. */
void *cb_calloc(size_t n, size_t size);
void *cb_malloc(size_t n, size_t size);
void *cb_realloc(void *p, size_t n, size_t size);
/* cb_calloc at a cache line's boundary (CB_CACHE_LINE bytes: no 32-byte entry of the array straddles two
 * lines), for the kernels' vector arrays; freed with free(). */
enum { CB_CACHE_LINE = 64 };
void *cb_calloc_aligned(size_t n, size_t size);

/* Allocation-failure injection, a test mode (tests/test_enomem.c, CHOLMOD's
 * Tcov habit). cb_alloc_fail_at(k), k >= 1, makes the k-th allocation that
 * this thread makes from now on fail as if out of memory, once; k = 0 turns
 * it off. Either way it restarts the count. While armed, every cb_malloc,
 * cb_calloc and cb_realloc counts; cb_alloc_tick counts one allocation made
 * elsewhere (a test routes CHOLMOD's SuiteSparse_config hooks through it) and
 * returns 1 when that one must fail. cb_alloc_count: allocations counted
 * since the last cb_alloc_fail_at. cb_alloc_fail_at(LONG_MAX) counts without
 * failing. Off (the default), nothing is counted. */
void cb_alloc_fail_at(long k);
long cb_alloc_count(void);
int cb_alloc_tick(void);

#endif
