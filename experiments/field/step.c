/* field's shared step helpers (field.h): the start state, whether a method accepts a scene, the
 * reference |grad F|, edge strain, and the sets a run uses. The cells' files (front.c, x1.c, x2.c,
 * tol.c, v1.c) and main.c call them; they call nothing of those. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "field.h"

int fd_state(const cb_experiment *e, const cb_scene_decl *d, int frames, cb_step_state *S) {
  static cb_config c; /* large: not on the stack */
  cb_scene *s = NULL;
  int st = cb_scene_decl_build(e, d, NULL, &c, &s);
  return st ? st : cb_step_state_init(S, d->label, &c, s, frames);
}

int fd_supported(cb_step_state *S, const char *const *sets, char *why, size_t nwhy) {
  static cb_config c;
  int st = cb_step_config(S, sets, &c);
  if (st) return st;
  cb_integrator *it = NULL;
  st = cb_integrator_from_config(&c, S->s, NULL, &it);
  cb_integrator_free(it);
  if (st == CB_EINVAL) { /* the method refuses the scene (e.g. xpbd and a penalty collider): say why */
    snprintf(why, nwhy, "%s", cb_error_message());
    cb_error_clear();
    return 0;
  }
  return st ? st : 1;
}

double fd_grad_hat(const cb_step_state *S) {
  cb_objective o;
  if (cb_objective_init(&o, S->s)) return NAN;
  int nf = 3 * S->s->model.nfree;
  double *g = malloc((size_t)(nf > 0 ? nf : 1) * sizeof(double)), gn = NAN;
  if (g) {
    cb_objective_begin(&o, S->x0, S->v0, S->c.dt);
    cb_objective_eval(&o, o.xhat, g, NULL);
    gn = 0;
    for (int k = 0; k < nf; k++) gn += g[k] * g[k];
    gn = sqrt(gn);
  }
  free(g);
  cb_objective_free(&o);
  return gn;
}

void fd_strain(const cb_scene *s, const double *x, double *max_strain, double *mean_abs) {
  *max_strain = NAN;
  *mean_abs = NAN;
  for (int t = 0; t < s->sys.nterms; t++) {
    int ns;
    const int *ends;
    const double *rest;
    double k;
    if (strcmp(s->sys.terms[t]->label, "stretch") || cb_spring_term_springs(s->sys.terms[t], &ns, &ends, &rest, &k))
      continue;
    double mx = -INFINITY, sum = 0;
    for (int c = 0; c < ns; c++) {
      const double *a = x + 3 * ends[2 * c], *b = x + 3 * ends[2 * c + 1];
      double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
      double e = sqrt(dx * dx + dy * dy + dz * dz) / rest[c] - 1.0; /* strain = |x_i - x_j| / L - 1 */
      mx = fmax(mx, e);
      sum += fabs(e);
    }
    *max_strain = mx;
    *mean_abs = ns ? sum / ns : NAN;
  }
}

void fd_with(const char *const *sets, const char *key, int K, char *buf, size_t nbuf, const char **out) {
  int k = 0;
  for (; sets[k] && k < 12; k++) out[k] = sets[k];
  snprintf(buf, nbuf, "%s=%d", key, K);
  out[k++] = buf;
  out[k] = NULL;
}

void fd_rho_cache_clear(fd_rho_cache *rc) { rc->n = 0; }

/* the cache's key of a method: its sets joined by newlines ("" when they do not fit) */
static void rho_key(const char *const *sets, char *key, size_t nkey) {
  size_t k = 0;
  key[0] = 0;
  for (int n = 0; sets[n] && n < 12; n++) {
    int w = snprintf(key + k, nkey - k, "%s\n", sets[n]);
    if (w < 0 || (size_t)w >= nkey - k) {
      key[0] = 0;
      return;
    }
    k += (size_t)w;
  }
}

int fd_fix_rho(cb_step_state *S, fd_rho_cache *rc, const char *const *sets, const char **out, char *buf, size_t nbuf,
               double *est_ms) {
  int n = 0, aut = -1;
  for (; sets[n] && n < 12; n++) {
    out[n] = sets[n];
    if (!strcmp(sets[n], "integrator.rho=auto")) aut = n;
  }
  out[n] = NULL;
  *est_ms = 0;
  if (aut < 0) return CB_OK;
  char key[sizeof rc->key[0]];
  rho_key(sets, key, sizeof key);
  for (int k = 0; rc && key[0] && k < rc->n; k++)
    if (!strcmp(rc->key[k], key)) { /* estimated before on this state: the same run would give the same rho */
      snprintf(buf, nbuf, "%s", rc->rho[k]);
      out[aut] = buf;
      *est_ms = rc->ms[k];
      return CB_OK;
    }
  const char *one[16];
  char b[64];
  fd_with(sets, "integrator.iters", 1, b, sizeof b, one);
  static cb_config c;
  cb_step_result r;
  double w;
  int st = cb_step_config(S, one, &c);
  if (st == CB_OK) st = cb_step_once(S, &c, NULL, NULL, &r, &w);
  if (st) return st;
  *est_ms = r.setup_ms;
  snprintf(buf, nbuf, "integrator.rho=%.17g", r.rho);
  out[aut] = buf;
  if (rc && key[0] && rc->n < FD_RHO_CACHE) {
    snprintf(rc->key[rc->n], sizeof rc->key[rc->n], "%s", key);
    snprintf(rc->rho[rc->n], sizeof rc->rho[rc->n], "%s", buf);
    rc->ms[rc->n++] = r.setup_ms;
  }
  return CB_OK;
}
