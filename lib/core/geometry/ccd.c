/* CCD registry and the shared wrapper: input checks (docs/geometry-ccd.md). */
#include <clothbench/ccd.h>

#include <math.h>
#include <string.h>

#include <clothbench/status.h>

/* The registry. Each plug-in file lib/core/geometry/ccd_<name>.c defines
 * `const cb_ccd_type cb_ccd_<name>`; its one X(name) line below declares and
 * lists it. The first is the default. */
#define CB_CCD_REGISTRY(X) \
  X(inclusion) \
  /* one X(name) line per CCD method, above this line */
#define CB_CCD_DECLARE(name) extern const cb_ccd_type cb_ccd_##name;
#define CB_CCD_ENTRY(name) &cb_ccd_##name,
CB_CCD_REGISTRY(CB_CCD_DECLARE)
const cb_ccd_type *const cb_ccd_types[] = {CB_CCD_REGISTRY(CB_CCD_ENTRY) NULL};

const cb_ccd_type *cb_ccd_type_find(const char *name) {
  if (!name) return cb_ccd_types[0];
  for (int i = 0; cb_ccd_types[i]; i++)
    if (!strcmp(cb_ccd_types[i]->name, name)) return cb_ccd_types[i];
  return NULL;
}

cb_ccd_params cb_ccd_params_default(void) {
  cb_ccd_params p = {.eta = 0.0, .tol = 1e-6, .max_boxes = 1000000};
  return p;
}

/* 2^500: a coordinate beyond it could overflow the methods' sums of a few products (DBL_MAX ~ 2^1024) */
#define CB_CCD_MAX_COORD 0x1p500

static int fail(cb_ccd_result *r, int status) {
  r->hit = 1; /* a caller that ignores the status still stops */
  r->toi = 0.0;
  return status;
}

int cb_ccd_run(const cb_ccd_type *type, int kind, const cb_ccd_query *q, const cb_ccd_params *p, cb_ccd_result *r) {
  r->boxes = 0;
  if (!type) type = cb_ccd_types[0];
  if (!q || !p) return fail(r, cb_fail("ccd: NULL query or parameters"));
  if (kind != CB_CCD_VF && kind != CB_CCD_EE) return fail(r, cb_fail("ccd: unknown kind %d (0 vf, 1 ee)", kind));
  if (!(p->eta >= 0.0) || !isfinite(p->eta)) return fail(r, cb_fail("ccd: eta = %g must be finite and >= 0", p->eta));
  if (!(p->tol > 0.0) || !isfinite(p->tol)) return fail(r, cb_fail("ccd: tol = %g must be finite and > 0", p->tol));
  if (p->max_boxes < 1) return fail(r, cb_fail("ccd: max_boxes = %ld must be >= 1", p->max_boxes));
  for (int k = 0; k < 8; k++)
    for (int j = 0; j < 3; j++) {
      double lo = q->lo[k][j], hi = q->hi[k][j];
      if (!isfinite(lo) || !isfinite(hi))
        return fail(r, cb_fail("ccd: point %d coordinate %d is not finite (%g, %g)", k, j, lo, hi));
      if (!(lo <= hi)) return fail(r, cb_fail("ccd: point %d coordinate %d: lo %g > hi %g", k, j, lo, hi));
      if (fabs(lo) > CB_CCD_MAX_COORD || fabs(hi) > CB_CCD_MAX_COORD)
        return fail(r, cb_fail("ccd: point %d coordinate %d: |x| = %g exceeds 2^500", k, j, fmax(fabs(lo), fabs(hi))));
    }
  int s = kind == CB_CCD_VF ? type->vf(q, p, r) : type->ee(q, p, r);
  if (s < 0) return fail(r, s);
  return s;
}

static int plain(const cb_ccd_type *type, int kind, const double x0[12], const double x1[12], const cb_ccd_params *p,
                 cb_ccd_result *r) {
  cb_ccd_query q;
  for (int k = 0; k < 4; k++)
    for (int j = 0; j < 3; j++) {
      q.lo[k][j] = q.hi[k][j] = x0[3 * k + j];
      q.lo[k + 4][j] = q.hi[k + 4][j] = x1[3 * k + j];
    }
  return cb_ccd_run(type, kind, &q, p, r);
}

int cb_ccd_vf(const cb_ccd_type *type, const double x0[12], const double x1[12], const cb_ccd_params *p,
              cb_ccd_result *r) {
  return plain(type, CB_CCD_VF, x0, x1, p, r);
}

int cb_ccd_ee(const cb_ccd_type *type, const double x0[12], const double x1[12], const cb_ccd_params *p,
              cb_ccd_result *r) {
  return plain(type, CB_CCD_EE, x0, x1, p, r);
}
