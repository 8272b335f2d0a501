/* status.c: the status names, the allocators' overflow check and message,
 * and the allocation-failure injection's contract (status.h). */
#include <criterion/criterion.h>
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

Test(status, every_status_has_its_own_name) {
  static const struct {
    int status;
    const char *name;
  } known[] = {{CB_OK, "ok"},
               {CB_EINVAL, "bad_input"},
               {CB_ENOMEM, "out_of_memory"},
               {CB_EIO, "io_error"},
               {CB_NOT_SPD, "not_spd"},
               {CB_NOT_CONVERGED, "max_iters"},
               {CB_DIVERGED, "diverged"},
               {CB_INDEFINITE, "indefinite"},
               {CB_LS_FAILED, "line_search_failed"},
               {CB_LINEAR_FAILED, "linear_failed"}};
  for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
    cr_assert_str_eq(cb_status_name(known[i].status), known[i].name);
  cr_assert_str_eq(cb_status_name(99), "unknown");
  cr_assert_str_eq(cb_status_name(-99), "unknown");
  /* fatal: everything but ok and not_converged */
  cr_assert(!cb_status_is_fatal(CB_OK));
  cr_assert(!cb_status_is_fatal(CB_NOT_CONVERGED));
  cr_assert(cb_status_is_fatal(CB_ENOMEM));
  cr_assert(cb_status_is_fatal(CB_NOT_SPD));
}

Test(status, messages) {
  cb_error_clear();
  cr_assert_str_eq(cb_error_message(), "");
  cr_assert_eq(cb_fail("bad %s %d", "key", 3), CB_EINVAL);
  cr_assert_str_eq(cb_error_message(), "bad key 3");
  cr_assert_eq(cb_fail_status(CB_EIO, "disk %d", 7), CB_EIO);
  cr_assert_str_eq(cb_error_message(), "disk 7");
}

/* n * size past SIZE_MAX: NULL and a message, never a short block */
Test(status, allocation_overflow) {
  size_t huge = SIZE_MAX / 2 + 2;
  cb_error_clear();
  cr_assert_null(cb_malloc(huge, 2));
  cr_assert(strstr(cb_error_message(), "overflows"), "%s", cb_error_message());
  cb_error_clear();
  cr_assert_null(cb_calloc(2, huge));
  cr_assert(strstr(cb_error_message(), "overflows"), "%s", cb_error_message());
  cb_error_clear();
  int *p = cb_malloc(4, sizeof(int));
  cr_assert_not_null(p);
  cr_assert_null(cb_realloc(p, huge, 2)); /* p stays allocated */
  cr_assert(strstr(cb_error_message(), "overflows"), "%s", cb_error_message());
  p[3] = 1;
  free(p);
  /* zero sizes give a block that can be freed */
  void *z = cb_malloc(0, 8), *zc = cb_calloc(3, 0);
  cr_assert(z && zc);
  free(z);
  free(zc);
}

Test(status, injection_fails_the_kth_allocation_once) {
  cb_alloc_fail_at(3);
  void *a = cb_malloc(1, 8), *b = cb_calloc(1, 8);
  cr_assert(a && b);
  cb_error_clear();
  void *c = cb_malloc(1, 8); /* the third */
  cr_assert_null(c);
  cr_assert(strstr(cb_error_message(), "out of memory allocating 8 bytes"), "%s", cb_error_message());
  void *d = cb_realloc(a, 2, 8); /* the fourth: succeeds */
  cr_assert_not_null(d);
  cr_assert_eq(cb_alloc_count(), 4);
  cb_alloc_fail_at(0); /* off: nothing counted, nothing fails */
  void *e = cb_malloc(1, 8);
  cr_assert_not_null(e);
  cr_assert_eq(cb_alloc_count(), 0);
  cr_assert_eq(cb_alloc_tick(), 0);
  free(b);
  free(d);
  free(e);
}

Test(status, injection_realloc_keeps_the_block_and_tick_counts) {
  int *p = cb_malloc(2, sizeof(int));
  cr_assert_not_null(p);
  p[0] = 42;
  cb_alloc_fail_at(2);
  cr_assert_eq(cb_alloc_tick(), 0); /* one made elsewhere (CHOLMOD's hooks) */
  cr_assert_null(cb_realloc(p, 100, sizeof(int)));
  cr_assert_eq(p[0], 42); /* still ours */
  cr_assert_eq(cb_alloc_count(), 2);
  cb_alloc_fail_at(LONG_MAX); /* counts, fails nothing */
  for (int k = 0; k < 5; k++) cr_assert_eq(cb_alloc_tick(), 0);
  cr_assert_eq(cb_alloc_count(), 5);
  cb_alloc_fail_at(0);
  free(p);
}

/* cb_calloc_aligned: a zeroed block at a cache line (the kernels' 4-vectors never straddle two lines), that
 * free() frees; an overflowing size and an injected failure give NULL and a message */
Test(status, aligned_allocation_is_zeroed_at_a_cache_line) {
  for (size_t n = 1; n < 200; n += 37) {
    double *p = cb_calloc_aligned(n, sizeof(double));
    cr_assert_not_null(p);
    cr_assert_eq((uintptr_t)p % CB_CACHE_LINE, 0, "%zu doubles at %p", n, (void *)p);
    for (size_t i = 0; i < n; i++) cr_assert_eq(p[i], 0.0);
    free(p);
  }
  cb_error_clear();
  cr_assert_null(cb_calloc_aligned(2, SIZE_MAX / 2 + 2));
  cr_assert(strstr(cb_error_message(), "overflows"), "%s", cb_error_message());
  cb_alloc_fail_at(1);
  cr_assert_null(cb_calloc_aligned(4, 8));
  cr_assert(strstr(cb_error_message(), "out of memory allocating 32 bytes"), "%s", cb_error_message());
  cb_alloc_fail_at(0);
}
