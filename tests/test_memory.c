/* The peak-memory probe (lib/instruments/memory.h) against allocations of known size. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "memory.h"

/* Touches n bytes (every page), frees them: the peak must see them, the resident set after need not. */
static void touch_and_free(size_t n) {
  char *p = malloc(n);
  cr_assert_not_null(p);
  memset(p, 1, n);
  volatile char sink = p[n - 1];
  (void)sink;
  free(p);
}

Test(memory, sees_a_freed_peak_of_known_size) {
  cb_mem_probe m;
  cr_assert_eq(cb_mem_probe_begin(&m), 0, "this Linux has /proc/self/clear_refs");
  const size_t n = 64u << 20;
  touch_and_free(n);
  double peak = cb_mem_probe_end(&m);
  cr_expect(peak >= 0.95 * (double)n, "peak %.0f bytes after touching %zu", peak, n);
  cr_expect(peak <= (double)n + (16u << 20), "peak %.0f bytes: more than the block and 16 MiB of slack", peak);
}

Test(memory, resets_between_probes) {
  cb_mem_probe m;
  cr_assert_eq(cb_mem_probe_begin(&m), 0);
  touch_and_free(96u << 20);
  double first = cb_mem_probe_end(&m);
  cr_assert_eq(cb_mem_probe_begin(&m), 0);
  touch_and_free(8u << 20);
  double second = cb_mem_probe_end(&m);
  cr_expect(first >= 90.0 * (1 << 20), "first %.0f", first);
  cr_expect(second < 40.0 * (1 << 20), "the second probe still saw the first peak: %.0f bytes", second);
}

Test(memory, not_begun_is_nan) {
  cb_mem_probe m = {.base_bytes = NAN};
  cr_expect(isnan(cb_mem_probe_end(&m)));
}
