/* locking, L1 (results/locking.csv): the fold angle at rest against in-plane
 * stiffness, per mesh, fold line and model (main.c describes the sweep). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/energy.h>
#include <clothbench/mesh.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include "csv.h"
#include "stability.h"

#include "locking.h"

static int degenerate(const cb_scene *s, const double *x) {
  int c = 0, nt;
  for (int k = 0; k < s->sys.nterms; k++) c += cb_fem_term_degenerate(s->sys.terms[k], x, &nt);
  return c;
}

/* ---- L1: fold angle at rest against in-plane stiffness ------------------------------ */

typedef struct {
  const char *name;
  double deg;
} fold_line;
static const fold_line folds[NFOLD] = {{"edges", 90}, {"diagonal", 45}, {"cross", 135}, {"angle30", 30}};

/* Cell ci: mesh kind ci / NFOLD, fold line ci % NFOLD, both models, every k. */
int lk_l1_cell(long ci, void *ctx, FILE *const *out) {
  static const char *const models[2] = {"spring", "fem"};
  int quick = *(const int *)ctx;
  FILE *f = out[T_MAIN];
  int nk = E.smoke ? 2 : quick ? 4 : 7, n = E.smoke ? 5 : quick ? 9 : 13;
  double ks[7];
  for (int j = 0; j < nk; j++) ks[j] = pow(10.0, 1.0 + 6.0 * j / (nk - 1));
  cb_equilibrium_params ep = cb_equilibrium_params_default();
  ep.tol = 1e-5;
  ep.max_steps = quick ? 300 : 400;
  int mk = (int)(ci / NFOLD), fl = E.smoke ? 2 : (int)(ci % NFOLD); /* smoke: the one cell is regular, cross */
  {
    cb_mesh rest;
    if (lk_rest_mesh((mesh_kind)mk, n, 0, &rest)) return CB_EIO;
    {
      /* fold line through the centre with direction (cos, sin) in (x, z); pinned: side s <= 0 */
      double th = folds[fl].deg * PI / 180, nrm[2] = {sin(th), -cos(th)}; /* normal of the direction (cos, sin) */
      double tol = 1e-9;
      char *pins = malloc(16 * (size_t)rest.nv + 16), *p = pins, *end = pins + 16 * (size_t)rest.nv + 16;
      double *sd = malloc((size_t)rest.nv * sizeof(double));
      if (!pins || !sd) return CB_ENOMEM;
      *p = 0;
      int npin = 0;
      for (int i = 0; i < rest.nv; i++) {
        sd[i] = nrm[0] * rest.x[3 * i] + nrm[1] * rest.x[3 * i + 2];
        if (sd[i] <= tol) {
          int w = snprintf(p, (size_t)(end - p), npin ? " %d" : "%d", i);
          p += w;
          npin++;
        }
      }
      int on_edges = 1;
      for (int t = 0; t < rest.nt; t++) {
        int neg = 0, pos = 0;
        for (int a = 0; a < 3; a++) {
          neg |= sd[rest.tri[3 * t + a]] < -tol;
          pos |= sd[rest.tri[3 * t + a]] > tol;
        }
        if (neg && pos) on_edges = 0;
      }
      for (int md = 0; md < 2; md++)
        for (int ki = 0; ki < nk; ki++) {
          char sk[64];
          snprintf(sk, sizeof sk, "material.stretch_k=%.17g", ks[ki]);
          const char *sets[] = {md ? "material.stretch=fem" : "material.stretch=spring", sk, NULL};
          cb_scene *s = NULL;
          int bs = lk_build(lk_scene_of("fold"), sets, (mesh_kind)mk, n, mk == MESH_DISK ? disk_xz : NULL, pins, &s);
          if (bs) {
            free(pins);
            free(sd);
            cb_mesh_free(&rest);
            return bs;
          }
          size_t n3 = 3 * (size_t)s->mesh.nv;
          double *x = malloc(n3 * sizeof(double));
          memcpy(x, s->x0, n3 * sizeof(double));
          cb_equilibrium_stats es;
          int rc = cb_stability_equilibrium(s, x, &ep, &es);
          /* the free part's centroid against the fold line (through the origin, at y = 0) */
          double cm[3] = {0, 0, 0}, M = 0;
          for (int i = 0; i < s->mesh.nv; i++) {
            if (s->free_index[i] < 0) continue;
            for (int a = 0; a < 3; a++) cm[a] += s->mass[i] * x[3 * i + a];
            M += s->mass[i];
          }
          for (int a = 0; a < 3; a++) cm[a] /= M;
          double offset = nrm[0] * cm[0] + nrm[1] * cm[2], drop = -cm[1];
          double angle = atan2(drop, offset) * 180 / PI;
          double smax, srms;
          lk_edge_strain(s, x, &smax, &srms);
          int st = rc ? rc : es.status;
          cb_csv_printf(f, "%s,%s,%s,%.0f,%d,%.17g,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%ld,%.6g,%d,%.3f,%s\n",
                        models[md], mesh_names[mk], folds[fl].name, folds[fl].deg, on_edges, ks[ki], s->mesh.nv, npin,
                        angle, offset, drop, smax, srms, es.steps, es.newton_iters, es.residual, degenerate(s, x),
                        es.ms, cb_status_name(st));
          free(x);
          cb_scene_free(s);
        }
      free(pins);
      free(sd);
    }
    cb_mesh_free(&rest);
  }
  return 0;
}
