/* locking, L2 (results/locking_dofs.csv): DoFs per vertex by the rigidity
 * matrix, conforming against nonconforming (main.c describes the sweep). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <clothbench/mesh.h>
#include <clothbench/status.h>
#include <clothbench/topology.h>
#include "rng.h"
#include "csv.h"
#include "rigidity.h"

#include "locking.h"

/* ---- L2: DoFs per vertex, conforming against nonconforming ------------------------- */

static void jitter(double *x, int n3, double h, unsigned seed) {
  cb_rng rng = cb_rng_seed(seed);
  for (int i = 0; i < n3; i++) x[i] += h * (cb_rng_uniform(&rng) - 0.5);
}

static void l2_row(FILE *f, const char *name, cb_mesh *m, unsigned seed) {
  cb_topology tp;
  if (cb_topology_build(m, &tp)) {
    cb_csv_printf(f, "%s,%d,%d,,,,,,,,,bad_input\n", name, m->nv, m->nt);
    return;
  }
  double h = 0.3 * sqrt(cb_mesh_triangle_area(m, m->x, 0));
  double *x = malloc((size_t)3 * m->nv * sizeof(double)), *mid = malloc((size_t)3 * tp.ne * sizeof(double));
  memcpy(x, m->x, (size_t)3 * m->nv * sizeof(double));
  jitter(x, 3 * m->nv, h, seed);
  int conf = cb_rigidity_dofs(m->nv, x, tp.ne, tp.edge);
  int *bar = NULL, nbars = 0, nonc = -1;
  if (cb_nonconforming_bars(m, m->x, tp.ne, tp.edge, mid, &bar, &nbars) == CB_OK) {
    jitter(mid, 3 * tp.ne, h, seed + 1000); /* generic midpoint positions */
    nonc = cb_rigidity_dofs(tp.ne, mid, nbars, bar);
  }
  /* a count the SVD (or the bar construction) did not give (-1) is written empty */
  cb_csv_printf(f, "%s,%d,%d,%d,%d,%.17g,%d,%.17g,%d,%.17g,%d,%.17g,%s\n", name, m->nv, m->nt, tp.ne, tp.nb,
                conf < 0 ? cb_csv_na() : conf, 3 + tp.nb, conf < 0 ? cb_csv_na() : (double)conf / m->nv, tp.ne,
                nonc < 0 ? cb_csv_na() : nonc, 3 * m->nv - 3, nonc < 0 ? cb_csv_na() : (double)nonc / m->nv,
                conf < 0 || nonc < 0 ? "svd_failed" : "ok");
  free(bar);
  free(x);
  free(mid);
  cb_topology_free(&tp);
}

/* Cells: the grids (size k = i / 2, diagonal pattern i % 2), then the ring disks. */
int lk_l2_cell(long i, void *ctx, FILE *const *out) {
  static const int sizes[] = {3, 4, 6, 8, 10};
  int quick = *(const int *)ctx, ns = quick ? 4 : 5;
  FILE *f = out[T_DOFS];
  if (i < 2L * ns) {
    int k = (int)i / 2, d = (int)i % 2;
    {
      cb_grid_params g = cb_grid_params_default();
      g.n = g.m = sizes[k];
      g.diagonal = d ? CB_DIAG_ALTERNATING : CB_DIAG_REGULAR;
      cb_mesh m;
      char name[64];
      snprintf(name, sizeof name, "grid_%dx%d_%s", g.n, g.m, d ? "alternating" : "regular");
      if (cb_mesh_grid(&g, &m) == CB_OK) l2_row(f, name, &m, 7 + (unsigned)k);
      cb_mesh_free(&m);
    }
  } else {
    int rings = (int)(i - 2L * ns) + 1;
    cb_mesh m;
    char name[64];
    snprintf(name, sizeof name, "ring_disk_%d", rings);
    if (cb_ring_disk(rings, &m) == CB_OK) l2_row(f, name, &m, 100 + (unsigned)rings);
    cb_mesh_free(&m);
  }
  return CB_OK;
}
