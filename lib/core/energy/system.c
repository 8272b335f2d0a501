#include <clothbench/system.h>

#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

void cb_system_free(cb_system *s) {
  if (!s) return;
  for (int k = 0; k < s->nterms; k++) cb_term_free(s->terms[k]);
  cb_sparse_free(&s->A);
  free(s->diag);
  free(s->hconst);
  memset(s, 0, sizeof *s);
}

int cb_system_init(cb_system *s, const cb_model *m, cb_term **terms, int nterms) {
  memset(s, 0, sizeof *s);
  s->model = m;
  if (nterms > CB_MAX_TERMS) {
    for (int k = 0; k < nterms; k++) cb_term_free(terms[k]);
    return cb_fail("too many energy terms (%d > %d)", nterms, CB_MAX_TERMS);
  }
  for (int k = 0; k < nterms; k++) s->terms[s->nterms++] = terms[k];
  cb_pattern p;
  int st = cb_pattern_init(&p, m->nfree);
  for (int k = 0; st == CB_OK && k < s->nterms; k++)
    if (s->terms[k]->type->pattern) st = s->terms[k]->type->pattern(s->terms[k], &p);
  if (st == CB_OK) st = cb_sparse_from_pattern(&p, &s->A);
  cb_pattern_free(&p);
  for (int k = 0; st == CB_OK && k < s->nterms; k++)
    if (s->terms[k]->type->bind) st = s->terms[k]->type->bind(s->terms[k], &s->A);
  if (st == CB_OK) {
    s->diag = cb_malloc((size_t)s->A.n, sizeof(int));
    if (!s->diag) st = CB_ENOMEM;
    for (int i = 0; st == CB_OK && i < s->A.n; i++) s->diag[i] = cb_sparse_diag_index(&s->A, i);
  }
  for (int k = 0; st == CB_OK && k < s->nterms; k++) { /* constant Hessians: evaluated once, here */
    const cb_term_type *t = s->terms[k]->type;
    if (!(t->flags & CB_TERM_CONSTANT_HESSIAN) || !t->hessian) continue;
    if (!s->hconst && !(s->hconst = cb_calloc((size_t)s->A.nnz, sizeof(double)))) st = CB_ENOMEM;
    if (st == CB_OK) t->hessian(s->terms[k], m->mesh->x, CB_PROJ_NONE, s->hconst); /* any x: H does not depend on it */
  }
  if (st) cb_system_free(s);
  return st;
}

double cb_system_energy(const cb_system *s, const double *x, double *grad, double *per_term) {
  if (grad) memset(grad, 0, (size_t)3 * s->model->mesh->nv * sizeof(double));
  double E = 0.0;
  for (int k = 0; k < s->nterms; k++) {
    double e = s->terms[k]->type->energy(s->terms[k], x, grad);
    if (per_term) per_term[k] = e;
    E += e;
  }
  return E;
}

double cb_system_max_step(const cb_system *s, const double *x, const double *x1) {
  double alpha = 1.0;
  for (int k = 0; k < s->nterms; k++)
    if (s->terms[k]->type->max_step) {
      double a = s->terms[k]->type->max_step(s->terms[k], x, x1);
      if (!(a < alpha)) continue; /* NaN is no bound: the callback returns 0 on errors */
      alpha = a;
    }
  return alpha;
}

int cb_system_begin_step(const cb_system *s, const double *x, double dt) {
  for (int k = 0; k < s->nterms; k++)
    if (s->terms[k]->type->begin_step) {
      int st = s->terms[k]->type->begin_step(s->terms[k], x, dt);
      if (st) return st;
    }
  return CB_OK;
}

double cb_system_elastic_energy(const cb_system *s, const double *x) {
  double E = 0.0;
  for (int k = 0; k < s->nterms; k++)
    if (s->terms[k]->type->hessian) E += s->terms[k]->type->energy(s->terms[k], x, NULL);
  return E;
}

void cb_system_assemble(cb_system *s, const double *x, double mass_scale, cb_definiteness def, double shift) {
  cb_sparse *A = &s->A;
  if (s->hconst) memcpy(A->val, s->hconst, (size_t)A->nnz * sizeof(double)); /* A = H_const */
  else memset(A->val, 0, (size_t)A->nnz * sizeof(double));
  cb_projection proj = cb_definiteness_projection(def);
  const cb_model *m = s->model;
  for (int v = 0; v < m->mesh->nv; v++) { /* A += mass_scale M + shift bi on the diagonal */
    int bi = m->free_index[v];
    if (bi < 0) continue;
    for (int a = 0; a < 3; a++) A->val[s->diag[3 * bi + a]] += mass_scale * m->mass[v] + shift;
  }
  for (int k = 0; k < s->nterms; k++) { /* A += H_term(x), each element projected */
    const cb_term_type *t = s->terms[k]->type;
    if (t->hessian && !(t->flags & CB_TERM_CONSTANT_HESSIAN)) t->hessian(s->terms[k], x, proj, A->val);
  }
}
