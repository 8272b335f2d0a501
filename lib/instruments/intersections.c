/* The exact intersection count (lib/instruments/intersections.h). */
#include "intersections.h"

#include <clothbench/intersect.h>
#include <clothbench/status.h>
#include <clothbench/timer.h>
#include <string.h>

int cb_intersections_init(cb_intersections *c, const cb_mesh *m) {
  memset(c, 0, sizeof *c);
  if (m->nt < 1) return cb_fail("intersections: the mesh has no triangles");
  cb_broadphase_params p = cb_broadphase_params_default(); /* thickness 0: closed boxes, touching counts */
  int rc = cb_broadphase_alloc(m->nv, m->nt, m->tri, &p, &c->bp);
  if (rc) return rc;
  c->nt = m->nt;
  c->tri = m->tri;
  return CB_OK;
}

void cb_intersections_free(cb_intersections *c) {
  if (!c) return;
  cb_broadphase_free(c->bp);
  memset(c, 0, sizeof *c);
}

typedef struct visit_ctx {
  const int *tri;
  const double *x;
  long pairs, count;
} visit_ctx;

static int visit(void *vctx, int i, int j) {
  visit_ctx *v = vctx;
  const int *a = v->tri + 3 * i, *b = v->tri + 3 * j;
  const double *x = v->x;
  v->pairs++;
  v->count += cb_tri_tri_intersect(x + 3 * a[0], x + 3 * a[1], x + 3 * a[2], x + 3 * b[0], x + 3 * b[1], x + 3 * b[2]);
  return 0;
}

int cb_intersections_count(cb_intersections *c, const double *x, long *count) {
  *count = -1;
  double t0 = cb_now_ms();
  int rc = cb_broadphase_update(c->bp, x, NULL);
  if (rc) return rc;
  long e0 = cb_orient_exact_calls();
  visit_ctx v = {c->tri, x, 0, 0};
  rc = cb_broadphase_self_pairs(c->bp, 1, visit, &v);
  if (rc) return rc;
  c->pairs = v.pairs;
  c->exact_calls = cb_orient_exact_calls() - e0;
  c->wall_ms = cb_now_ms() - t0;
  *count = v.count;
  return CB_OK;
}
