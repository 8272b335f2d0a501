#define _DEFAULT_SOURCE /* mkstemps */
#include "support.h"

#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void test_config(cb_config *c, const char *const *sets) {
  cb_config_defaults(c);
  for (int i = 0; sets && sets[i]; i++)
    if (cb_config_set(c, sets[i])) cr_assert_fail("config: %s", cb_error_message());
}

cb_scene *test_scene(const char *const *sets) {
  cb_config c;
  test_config(&c, sets);
  cb_scene *s = NULL;
  if (cb_scene_build(&c, &s)) cr_assert_fail("scene: %s", cb_error_message());
  return s;
}

const char *test_tmpfile(const char *suffix, const char *text) {
  static char path[256];
  snprintf(path, sizeof path, "/tmp/cbtest_XXXXXX%s", suffix);
  int fd = mkstemps(path, (int)strlen(suffix));
  cr_assert(fd >= 0, "mkstemps failed");
  size_t n = strlen(text);
  cr_assert(write(fd, text, n) == (ssize_t)n);
  close(fd);
  return path;
}

gsl_matrix *test_dense(const cb_sparse *A) {
  gsl_matrix *D = gsl_matrix_calloc((size_t)A->n, (size_t)A->n);
  for (int j = 0; j < A->n; j++)
    for (int p = A->colp[j]; p < A->colp[j + 1]; p++) gsl_matrix_set(D, (size_t)A->rowi[p], (size_t)j, A->val[p]);
  return D;
}
