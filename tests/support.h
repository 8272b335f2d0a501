/* Helpers shared by the Criterion tests. */
#ifndef CB_TEST_SUPPORT_H
#define CB_TEST_SUPPORT_H

#include <gsl/gsl_matrix.h>

#include <clothbench/broadphase.h>
#include <clothbench/contact.h>
#include <clothbench/definiteness.h>
#include <clothbench/eigen.h>
#include <clothbench/energy.h>
#include <clothbench/integrator.h>
#include <clothbench/intersect.h>
#include <clothbench/material.h>
#include <clothbench/mesh.h>
#include <clothbench/objective.h>
#include <clothbench/projection.h>
#include <clothbench/run.h>
#include <clothbench/scene.h>
#include <clothbench/solver.h>
#include <clothbench/solver_shift.h>
#include <clothbench/sparse.h>
#include <clothbench/status.h>
#include <clothbench/stencil.h>
#include <clothbench/system.h>
#include <clothbench/timer.h>
#include <clothbench/topology.h>
#include "bind.h"
#include "claims.h"
#include "experiment.h"
#include "provenance.h"

/* Defaults, then each "section.key=value" of the NULL-terminated list.
 * Aborts the test with the library's message on error. */
void test_config(cb_config *c, const char *const *sets);
/* test_config + cb_scene_from_config. */
cb_scene *test_scene(const char *const *sets);
/* The integrator the same sets describe for s (cb_integrator_from_config),
 * with an optional Newton hook. Aborts the test on error. */
cb_integrator *test_integrator(const char *const *sets, cb_scene *s, cb_newton_hook hook, void *ctx);

/* A Newton hook (test_integrator's hook, ctx a test_rise_trace) that counts
 * the objective's rises: at each CB_NEWTON_GRADIENT event n grows, and an
 * iterate after a step's first (iter > 0) whose F exceeds the previous
 * iterate's by more than 1e-12 relative counts one rise. first and last are
 * the F of the step's first iterate and of the latest. Start from
 * {0}; zero n between steps to count each step's iterates. */
typedef struct {
  int n, rises;
  double first, last;
} test_rise_trace;
void test_count_rises(void *ctx, int event, const cb_newton_event *ev);

/* Writes text to a fresh temporary file; returns its path (static buffer). */
const char *test_tmpfile(const char *suffix, const char *text);

/* m_i = density * (sum of adjacent rest triangle areas) / 3, computed here
 * from the mesh alone (independently of the library's lumping). */
void test_lumped_masses(const cb_mesh *m, double density, double *mass);

/* ---- the claims tests: fixture CSVs and verdicts ---- */

/* Writes dir/name: head (unless NULL: a provenance line or the header row),
 * then text. Aborts the test when the file cannot be written. */
void test_put(const char *dir, const char *name, const char *head, const char *text);
/* Reads the CSV at path and runs check on it with results_dir dir; res
 * (cleared first) gets the result, whose verdict is returned. Aborts the
 * test when the CSV cannot be read. */
cb_verdict test_decide_check(cb_claim_check check, const char *path, const char *dir, cb_claim_result *res);
/* The same on a CSV of head followed by rows, written to a temporary file
 * (removed after), with /tmp as results_dir. */
cb_verdict test_decide_rows(cb_claim_check check, const char *head, const char *rows, cb_claim_result *res);
/* Decides the registered claim id on the CSVs in dir (cb_claim_decide);
 * aborts the test when id is not registered or, unless experiment is NULL,
 * belongs to another experiment. */
cb_verdict test_decide_claim(const char *id, const char *experiment, const char *dir, cb_claim_result *res);

/* Dense copy of a cb_sparse (caller frees with gsl_matrix_free). */
gsl_matrix *test_dense(const cb_sparse *A);

/* The config sets fail, at a set or when the scene is built, with a message naming key (a Criterion
 * expectation each). */
void test_expect_config_error(const char *const *sets, const char *key);
/* Intersecting (cloth triangle, obstacle triangle) pairs of s at x, every pair, exactly (cb_tri_tri_intersect). */
long test_cross_intersections(const cb_scene *s, const double *x);

#endif
