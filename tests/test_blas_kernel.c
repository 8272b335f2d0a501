/* The OpenBLAS kernel choice (lib/io/blas_kernel.c): the ranking of core
 * names, the best core of a CPU's flags, the decision (left alone when
 * OPENBLAS_CORETYPE is set or the detected core is as good; a candidate only
 * for a fallback), the self-test's error measure and the self-test itself,
 * and the provenance and warning for injected detections
 * (CB_BLAS_TEST_CORENAME, CB_BLAS_TEST_CPUFLAGS). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "blas_kernel.h"

#define AVX512 "avx avx2 fma avx512f avx512bw avx512vl avx512dq"

Test(blas_kernel, levels) {
  cr_expect_eq(cb_blas_core_level("Prescott"), 0);
  cr_expect_eq(cb_blas_core_level("prescott"), 0, "case-insensitive");
  cr_expect_eq(cb_blas_core_level("Sandybridge"), 1);
  cr_expect_eq(cb_blas_core_level("Haswell"), 2);
  cr_expect_eq(cb_blas_core_level("Zen"), 2);
  cr_expect_eq(cb_blas_core_level("SkylakeX"), 3);
  cr_expect_eq(cb_blas_core_level("Cooperlake"), 3);
  cr_expect_eq(cb_blas_core_level("NoSuchCore"), -1);
  cr_expect_eq(cb_blas_core_level(NULL), -1);
}

Test(blas_kernel, best_core_of_flags) {
  cr_expect_str_eq(cb_blas_best_core(AVX512), "SkylakeX");
  cr_expect_str_eq(cb_blas_best_core("fma,avx2,avx512f,avx512bw,avx512vl"), "Haswell", "avx512dq missing: Haswell");
  cr_expect_str_eq(cb_blas_best_core("avx2 fma"), "Haswell");
  cr_expect_null(cb_blas_best_core("avx avx2"), "AVX2 without FMA");
  cr_expect_null(cb_blas_best_core("avx2fma avx512fx"), "whole words only");
  cr_expect_null(cb_blas_best_core(""));
}

Test(blas_kernel, plan) {
  cb_blas_plan p;
  cb_blas_plan_make(NULL, "Prescott", AVX512, &p);
  cr_expect_str_eq(p.candidate, "SkylakeX", "%s", p.why);
  cb_blas_plan_make("", "Prescott", "avx2 fma", &p);
  cr_expect_str_eq(p.candidate, "Haswell", "an empty OPENBLAS_CORETYPE counts as unset: %s", p.why);
  cb_blas_plan_make("Prescott", "Prescott", AVX512, &p);
  cr_expect_null(p.candidate, "a set OPENBLAS_CORETYPE is left alone");
  cr_expect(strstr(p.why, "OPENBLAS_CORETYPE=Prescott"), "%s", p.why);
  cb_blas_plan_make(NULL, "Cooperlake", AVX512, &p);
  cr_expect_null(p.candidate, "a detected AVX-512 core is kept: %s", p.why);
  cb_blas_plan_make(NULL, "Zen", AVX512, &p);
  cr_expect_str_eq(p.candidate, "SkylakeX", "Zen (AVX2) below AVX-512: %s", p.why);
  cb_blas_plan_make(NULL, "Haswell", "avx2 fma", &p);
  cr_expect_null(p.candidate, "%s", p.why);
  cb_blas_plan_make(NULL, "Prescott", "avx sse3", &p);
  cr_expect_null(p.candidate, "no AVX2: %s", p.why);
  cb_blas_plan_make(NULL, "NewCore", AVX512, &p);
  cr_expect_null(p.candidate, "an unknown core is not replaced: %s", p.why);
}

Test(blas_kernel, rel_error) {
  const double ref[3] = {1, -4, 2}, same[3] = {1, -4, 2}, off[3] = {1, -4 + 4e-11, 2};
  cr_expect_eq(cb_blas_rel_error(same, ref, 3), 0);
  cr_expect(fabs(cb_blas_rel_error(off, ref, 3) - 1e-11) < 1e-15);
  cr_expect(cb_blas_rel_error(off, ref, 3) > CB_BLAS_SELFTEST_TOL, "an error of 1e-11 fails the 1e-12 test");
  const double nan3[3] = {1, NAN, 2}, zero[3] = {0, 0, 0};
  cr_expect(isinf(cb_blas_rel_error(nan3, ref, 3)));
  cr_expect_eq(cb_blas_rel_error(ref, zero, 3), 1);
  cr_expect_eq(cb_blas_rel_error(zero, zero, 3), 0);
}

/* the running kernel (whatever this machine detects) passes, and names a routine */
Test(blas_kernel, selftest_passes_on_the_running_kernel) {
  char msg[200];
  double e = cb_blas_selftest(msg, sizeof msg);
  cr_expect(e >= 0 && e <= CB_BLAS_SELFTEST_TOL, "max rel. error %g (%s)", e, msg);
  cr_expect(strstr(msg, "dgemm") || strstr(msg, "dsyrk") || strstr(msg, "dtrsm") || strstr(msg, "dpotrf"), "%s", msg);
}

static void clear_env(void) {
  unsetenv("OPENBLAS_CORETYPE");
  unsetenv("CB_BLAS_CHOICE");
  unsetenv("CB_BLAS_TEST_CORENAME");
  unsetenv("CB_BLAS_TEST_CPUFLAGS");
}

/* an injected fallback detection: recorded as such, and warned about */
Test(blas_kernel, injected_fallback_is_recorded_and_warned, .init = clear_env) {
  setenv("CB_BLAS_TEST_CORENAME", "Prescott", 1);
  setenv("CB_BLAS_TEST_CPUFLAGS", AVX512, 1);
  const char *core;
  char how[1024];
  cb_blas_kernel_describe(&core, how, sizeof how);
  cr_expect_str_eq(core, "Prescott");
  cr_expect(strstr(how, "detected (CB_BLAS_TEST_CORENAME)") && strstr(how, "OPENBLAS_CORETYPE=SkylakeX"), "%s", how);
  char *buf = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&buf, &len);
  cr_assert(f);
  cr_expect_eq(cb_blas_kernel_warning(f, "simulate"), 1);
  fclose(f);
  cr_expect(strstr(buf, "simulate: warning:") && strstr(buf, "OPENBLAS_CORETYPE=SkylakeX"), "%s", buf);
  cr_expect_eq(strchr(buf, '\n') - buf, (long)len - 1, "one line: %s", buf);
  free(buf);
  /* a refusal recorded by build/blas-kernel: no warning, the reason in the provenance */
  setenv("CB_BLAS_CHOICE",
         "refused SkylakeX; the detected Prescott is a fallback; self-test failed: dtrsm left: 3e-09 > 1e-12", 1);
  cb_blas_kernel_describe(&core, how, sizeof how);
  cr_expect(strstr(how, "refused SkylakeX") && strstr(how, "self-test failed"), "%s", how);
  f = fopen("/dev/null", "w");
  cr_expect_eq(cb_blas_kernel_warning(f, "simulate"), 0, "refused: nothing to suggest");
  fclose(f);
}

/* the detected core (this machine's, or injected as AVX-512) with matching flags: no warning */
Test(blas_kernel, detected_best_is_not_warned, .init = clear_env) {
  setenv("CB_BLAS_TEST_CORENAME", "Cooperlake", 1);
  setenv("CB_BLAS_TEST_CPUFLAGS", AVX512, 1);
  const char *core;
  char how[1024];
  cb_blas_kernel_describe(&core, how, sizeof how);
  cr_expect(strncmp(how, "detected", 8) == 0 && strstr(how, "at least"), "%s", how);
  FILE *f = fopen("/dev/null", "w");
  cr_expect_eq(cb_blas_kernel_warning(f, "simulate"), 0);
  fclose(f);
}

/* OPENBLAS_CORETYPE in the environment: "set by the environment", unless
 * CB_BLAS_CHOICE says clothbench chose exactly that core and it runs */
Test(blas_kernel, environment_and_chosen, .init = clear_env) {
  const char *running = openblas_get_corename();
  setenv("OPENBLAS_CORETYPE", running, 1);
  const char *core;
  char how[1024];
  cb_blas_kernel_describe(&core, how, sizeof how);
  cr_expect(strncmp(how, "set by the environment", 22) == 0, "%s", how);
  char ch[256];
  snprintf(ch, sizeof ch, "chosen %s; the detected Prescott is a fallback below the CPU's %s; self-test passed: ...",
           running, running);
  setenv("CB_BLAS_CHOICE", ch, 1);
  cb_blas_kernel_describe(&core, how, sizeof how);
  cr_expect_str_eq(how, ch);
  setenv("CB_BLAS_CHOICE", "chosen NotTheRunningOne; x; self-test passed", 1);
  cb_blas_kernel_describe(&core, how, sizeof how);
  cr_expect(strncmp(how, "set by the environment", 22) == 0,
            "a choice that does not match what runs is not believed: %s", how);
}
