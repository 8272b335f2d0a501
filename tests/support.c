#define _DEFAULT_SOURCE /* mkstemps */
#include "support.h"

#include <criterion/criterion.h>
#include <math.h>
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
  if (cb_scene_from_config(&c, &s)) cr_assert_fail("scene: %s", cb_error_message());
  return s;
}

cb_integrator *test_integrator(const char *const *sets, cb_scene *s, cb_newton_hook hook, void *ctx) {
  cb_config c;
  test_config(&c, sets);
  cb_integrator_params p;
  cr_assert_eq(cb_integrator_params_from_config(&c, &p), CB_OK, "%s", cb_error_message());
  p.hook = hook;
  p.hook_ctx = ctx;
  cb_integrator *it = NULL;
  if (cb_integrator_from_config(&c, s, &p, &it)) cr_assert_fail("integrator: %s", cb_error_message());
  return it;
}

void test_count_rises(void *ctx, int event, const cb_newton_event *ev) {
  test_rise_trace *r = ctx;
  if (event != CB_NEWTON_GRADIENT) return;
  if (ev->iter == 0) r->first = ev->F;
  else if (ev->F > r->last + 1e-12 * fabs(r->last)) r->rises++;
  r->last = ev->F;
  r->n++;
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

void test_put(const char *dir, const char *name, const char *head, const char *text) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  cr_assert_not_null(f, "cannot write %s", path);
  if (head) fputs(head, f);
  fputs(text, f);
  cr_assert_eq(fclose(f), 0, "cannot write %s", path);
}

cb_verdict test_decide_check(cb_claim_check check, const char *path, const char *dir, cb_claim_result *res) {
  cb_table t;
  cr_assert_eq(cb_table_read(path, &t), CB_OK, "%s", cb_error_message());
  memset(res, 0, sizeof *res);
  check(&t, dir, res);
  cb_table_free(&t);
  return res->verdict;
}

cb_verdict test_decide_rows(cb_claim_check check, const char *head, const char *rows, cb_claim_result *res) {
  char path[] = "/tmp/cbclaimXXXXXX";
  int fd = mkstemp(path);
  cr_assert(fd >= 0, "mkstemp failed");
  FILE *f = fdopen(fd, "w");
  cr_assert_not_null(f);
  fputs(head, f);
  fputs(rows, f);
  cr_assert_eq(fclose(f), 0, "cannot write %s", path);
  cb_verdict v = test_decide_check(check, path, "/tmp", res);
  unlink(path);
  return v;
}

cb_verdict test_decide_claim(const char *id, const char *experiment, const char *dir, cb_claim_result *res) {
  for (int i = 0; i < cb_nclaims; i++)
    if (!strcmp(cb_claims[i].id, id)) {
      if (experiment) cr_assert_str_eq(cb_claims[i].experiment, experiment);
      cb_claim_decide(&cb_claims[i], dir, res);
      return res->verdict;
    }
  cr_assert_fail("claim %s not registered", id);
  return CB_NOT_RUN;
}

gsl_matrix *test_dense(const cb_sparse *A) {
  gsl_matrix *D = gsl_matrix_calloc((size_t)A->n, (size_t)A->n);
  for (int j = 0; j < A->n; j++)
    for (int p = A->colp[j]; p < A->colp[j + 1]; p++) gsl_matrix_set(D, (size_t)A->rowi[p], (size_t)j, A->val[p]);
  return D;
}

void test_lumped_masses(const cb_mesh *m, double density, double *mass) {
  memset(mass, 0, (size_t)m->nv * sizeof(double));
  for (int t = 0; t < m->nt; t++) {
    const int *v = m->tri + 3 * t;
    const double *a = m->x + 3 * v[0], *b = m->x + 3 * v[1], *c = m->x + 3 * v[2];
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double area = 0.5 * sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]); /* |e1 x e2| / 2 */
    for (int k = 0; k < 3; k++) mass[v[k]] += density * area / 3.0;
  }
}

void test_expect_config_error(const char *const *sets, const char *key) {
  cb_config c;
  cb_config_defaults(&c);
  for (int i = 0; sets[i]; i++)
    if (cb_config_set(&c, sets[i])) {
      cr_expect(strstr(cb_error_message(), key), "%s: the error does not name %s: %s", sets[i], key,
                cb_error_message());
      return;
    }
  cb_scene *s = NULL;
  int st = cb_scene_from_config(&c, &s);
  cr_expect_neq(st, CB_OK, "%s: accepted", sets[0]);
  if (st == CB_OK) {
    cb_scene_free(s);
    return;
  }
  cr_expect(strstr(cb_error_message(), key), "the error does not name %s: %s", key, cb_error_message());
}

long test_cross_intersections(const cb_scene *s, const double *x) {
  const cb_obstacle *o = cb_scene_obstacle(s);
  long n = 0;
  for (int a = 0; a < s->mesh.nt; a++)
    for (int b = 0; b < o->mesh.nt; b++) {
      const int *p = s->mesh.tri + 3 * a, *q = o->mesh.tri + 3 * b;
      n += cb_tri_tri_intersect(x + 3 * p[0], x + 3 * p[1], x + 3 * p[2], o->x + 3 * q[0], o->x + 3 * q[1],
                                o->x + 3 * q[2]);
    }
  return n;
}
