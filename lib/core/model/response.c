/* The post-step stage's mechanism (response.h): a response's state from its
 * type's size, its release, and the stage run in order. The scene owns the
 * list and fills the view; the responses themselves live with what they
 * respond to (collider.c, obstacle.c, contact_bridson.c). */
#include <clothbench/response.h>

#include <stdlib.h>

#include <clothbench/status.h>

int cb_response_alloc(cb_response *r, const cb_response_type *t) {
  r->type = t;
  r->state = NULL;
  if (!t || !t->apply) return cb_fail("scene: a post-step response has no type (or no apply)");
  if (t->size && !(r->state = cb_calloc(1, t->size))) return CB_ENOMEM;
  return CB_OK;
}

void cb_response_free(cb_response *r) {
  if (r->type && r->type->free) r->type->free(r);
  free(r->state);
  r->state = NULL;
}

int cb_response_apply_all(cb_response *rs, int n, const cb_response_view *view, const double *x_start, double *x,
                          double *v, double dt) {
  int st = CB_OK;
  for (int k = 0; k < n; k++) {
    int rs_k = rs[k].type->apply(&rs[k], view, x_start, x, v, dt);
    if (rs_k && !st) st = rs_k;
  }
  return st;
}
