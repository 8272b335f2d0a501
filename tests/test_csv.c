/* cb_csv_printf (lib/io/csv.h): NaN of either sign is `nan`,
 * infinities `inf` / `-inf`, cb_csv_na() the empty field, and every other
 * conversion what fprintf writes. Expected strings are spelled out here. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"

/* cb_csv_printf into a string (the format checked by the compiler) */
#define PRINT(buf, ...) \
  do { \
    char *mem_ = NULL; \
    size_t len_ = 0; \
    FILE *f_ = open_memstream(&mem_, &len_); \
    cr_assert_not_null(f_); \
    int n_ = cb_csv_printf(f_, __VA_ARGS__); \
    cr_assert_eq(fclose(f_), 0); \
    cr_assert_eq(n_, (int)len_, "returned %d, wrote %zu bytes", n_, len_); \
    snprintf(buf, sizeof buf, "%s", mem_); \
    free(mem_); \
  } while (0)

Test(csv, non_finite_values_have_one_spelling) {
  char s[256];
  volatile double zero = 0.0;
  double quotient = zero / zero; /* 0/0: x86 gives a NaN with the sign bit set, which glibc prints "-nan" */
  double neg_nan = copysign(quotient, -1.0), pos_nan = copysign(quotient, 1.0);
  cr_assert(signbit(neg_nan) && !signbit(pos_nan));
  PRINT(s, "%.17g,%.17g,%.17g,%.17g,%.17g", neg_nan, pos_nan, quotient, INFINITY, -INFINITY);
  cr_assert_str_eq(s, "nan,nan,nan,inf,-inf");
  PRINT(s, "%.6f|%e|%G|%a|%10.3f", neg_nan, -INFINITY, NAN, INFINITY, neg_nan);
  cr_assert_str_eq(s, "nan|-inf|nan|inf|nan");
  PRINT(s, "%Lg,%Lg", (long double)neg_nan, -(long double)INFINITY);
  cr_assert_str_eq(s, "nan,-inf");
}

Test(csv, not_applicable_is_the_empty_field) {
  char s[256];
  PRINT(s, "a,%.17g,%.6f,b,%g", cb_csv_na(), cb_csv_na(), -cb_csv_na());
  cr_assert_str_eq(s, "a,,,b,");
  cr_assert(isnan(cb_csv_na()));
  cr_assert(cb_csv_is_na(cb_csv_na()) && cb_csv_is_na(-cb_csv_na()));
  cr_assert(!cb_csv_is_na(NAN) && !cb_csv_is_na(0.0) && !cb_csv_is_na(INFINITY));
  cr_assert(cb_csv_is_na(cb_csv_na_if_nan(NAN)));
  cr_assert_eq(cb_csv_na_if_nan(2.5), 2.5);
  cr_assert_eq(cb_csv_na_if_nan(-INFINITY), -INFINITY);
  double copy = cb_csv_na(); /* copies keep it */
  PRINT(s, "%.17g", copy);
  cr_assert_str_eq(s, "");
}

Test(csv, finite_numbers_and_other_conversions_are_fprintfs) {
  char s[512], want[512];
  long l = -1234567890123L;
  size_t z = 42;
  PRINT(s, "%d,%ld,%zu,%s,%c,%.17g,%.6f,%.3f,%.6g,%g,%%,%5d|%-4s|%x,%lld,%u,%hd,%.*f,%*d", -7, l, z, "ok", 'q', 0.1,
        1.0 / 3, 2.5, 1e-300, 1e21, 12, "ab", 255U, -5LL, 3U, (short)-2, 2, 3.14159, 4, 9);
  snprintf(want, sizeof want, "%d,%ld,%zu,%s,%c,%.17g,%.6f,%.3f,%.6g,%g,%%,%5d|%-4s|%x,%lld,%u,%hd,%.*f,%*d", -7, l, z,
           "ok", 'q', 0.1, 1.0 / 3, 2.5, 1e-300, 1e21, 12, "ab", 255U, -5LL, 3U, (short)-2, 2, 3.14159, 4, 9);
  cr_assert_str_eq(s, want);
  cr_assert_str_eq(s, "-7,-1234567890123,42,ok,q,0.10000000000000001,0.333333,2.500,1e-300,1e+21,%,   12|ab  "
                      "|ff,-5,3,-2,3.14,   9");
  PRINT(s, "%.17g,%.17g,%.17g", -0.0, 5e-324, 1.7976931348623157e308);
  cr_assert_str_eq(s, "-0,4.9406564584124654e-324,1.7976931348623157e+308");
  PRINT(s, "no conversions\n");
  cr_assert_str_eq(s, "no conversions\n");
}
