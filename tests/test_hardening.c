/* Issue 35 (hardening, round 3): the defects of the library and the report
 * that a hostile user found, each with a check that failed before its fix.
 * The script-level items are in tests/hardening.sh. */
#define _XOPEN_SOURCE 700 /* mkdtemp, setrlimit */
#include <criterion/criterion.h>

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "report.h"
#include "support.h"
#include "table.h"

static char dir[64];

static void make_dir(void) {
  snprintf(dir, sizeof dir, "/tmp/cbharden.XXXXXX");
  cr_assert(mkdtemp(dir), "mkdtemp: %s", strerror(errno));
}

static void cleanup(void) {
  char c[128];
  if (!dir[0]) return;
  snprintf(c, sizeof c, "rm -rf '%s'", dir);
  if (system(c) != 0) fprintf(stderr, "could not remove %s\n", dir);
}

static void put(const char *name, const char *text) {
  char p[256];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  FILE *f = fopen(p, "w");
  cr_assert(f, "%s: %s", p, strerror(errno));
  fputs(text, f);
  cr_assert_eq(fclose(f), 0);
}

/* the whole file dir/name (static buffer; "" when missing) */
static const char *slurp(const char *name) {
  static char buf[1 << 16];
  char p[256];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  FILE *f = fopen(p, "r");
  if (!f) return "";
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  buf[n] = '\0';
  fclose(f);
  return buf;
}

/* the process's files may grow to limit bytes; a write past it fails with
 * EFBIG (SIGXFSZ ignored), as on a full disk or quota */
static void limit_file_size(rlim_t limit) {
  signal(SIGXFSZ, SIG_IGN);
  struct rlimit r = {limit, limit};
  cr_assert_eq(setrlimit(RLIMIT_FSIZE, &r), 0, "setrlimit: %s", strerror(errno));
}

/* item 19: a write error is reported with its cause, not "Success" */
Test(hardening, item19_write_error_keeps_its_cause, .fini = cleanup) {
  make_dir();
  char p[256];
  snprintf(p, sizeof p, "%s/big.csv", dir);
  limit_file_size(4096);
  cb_outfile o;
  cr_assert_eq(cb_outfile_open(&o, p), CB_OK);
  static char row[8192];
  memset(row, 'x', sizeof row - 1);
  for (int i = 0; i < 20; i++) fputs(row, o.f); /* the failing write happens here, in the run */
  errno = 0;                                    /* ... which goes on: other calls set errno before the commit */
  cr_assert_neq(cb_outfile_commit(&o), CB_OK, "160 kB committed under a 4 kB file-size limit");
  const char *m = cb_error_message();
  cr_expect(strstr(m, strerror(EFBIG)) != NULL, "the message does not name EFBIG: %s", m);
  cr_expect(strstr(m, "Success") == NULL, "the message says Success: %s", m);
  cr_expect(access(p, F_OK) != 0, "a failed commit left %s", p);
}

/* item 2: one table that cannot be written leaves the previous run whole */
Test(hardening, item2_tables_all_or_none, .fini = cleanup) {
  make_dir();
  put("r.csv", "old main\n");
  put("r_big.csv", "old big\n");
  put("r_small.csv", "old small\n");
  char out[256], lock[256], cfg[256];
  snprintf(out, sizeof out, "%s/r.csv", dir);
  snprintf(lock, sizeof lock, "%s/cpu.lock", dir);
  snprintf(cfg, sizeof cfg, "%s/noconfigs", dir);
  setenv("CB_CPU_LOCK", lock, 1);
  char *argv[] = {"hardening", "--out", out, "--configs", cfg, NULL};
  cb_experiment e;
  cr_assert_eq(cb_experiment_begin(&e, "hardening", "a test", 5, argv), 0);
  cr_assert_eq(cb_experiment_table(&e, NULL, NULL, "a,b"), 0);
  cr_assert_eq(cb_experiment_table(&e, "big", NULL, "a,b"), 1);
  cr_assert_eq(cb_experiment_table(&e, "small", NULL, "a,b"), 2);
  limit_file_size(32768);
  fputs("1,2\n", e.table[0].f);
  for (int i = 0; i < 4000; i++) fputs("1234567890,1234567890123456789012345678\n", e.table[1].f);
  fputs("3,4\n", e.table[2].f);
  cr_assert_neq(cb_experiment_end(&e, CB_OK), CB_OK, "160 kB written under a 32 kB limit");
  cr_expect_str_eq(slurp("r.csv"), "old main\n", "the main table was replaced though the run failed");
  cr_expect_str_eq(slurp("r_big.csv"), "old big\n");
  cr_expect_str_eq(slurp("r_small.csv"), "old small\n");
}

/* the report's text of fn on the results folder dir (static buffer) */
static const char *report_of(void (*fn)(FILE *, const char *)) {
  static char buf[1 << 16];
  FILE *f = fmemopen(buf, sizeof buf, "w");
  cr_assert(f);
  fn(f, dir);
  fclose(f);
  return buf;
}

/* item 7: the "# smoke:" line after a config line longer than any buffer */
Test(hardening, item7_smoke_after_a_long_config_line, .fini = cleanup) {
  make_dir();
  const char *e = cb_claims[0].experiment;
  cr_assert(e);
  static char text[70000];
  size_t n = (size_t)snprintf(text, sizeof text, "# program: %s\n# config configs/long.ini: ", e);
  for (int i = 0; i < 6000; i++) n += (size_t)snprintf(text + n, sizeof text - n, "k%d = 1, ", i);
  snprintf(text + n, sizeof text - n, "\n# experiment: %s\n# quick: 1\n# smoke: 1\na,b\n1,2\n", e);
  cr_assert_gt(strlen(text), 3 * 8192, "the config line is not longer than the buffers");
  char name[128];
  snprintf(name, sizeof name, "%s.csv", e);
  put(name, text);
  const char *r = report_of(cb_report_origin);
  cr_expect(strstr(r, "This is a **smoke** run") != NULL, "a smoke run not reported as one:\n%s", r);
  cr_expect(strstr(r, "**full**") == NULL, "a smoke run reported as full:\n%s", r);
}

/* item 10: a run time of nan, 1e20, 3e9 s or -5 s is not converted to minutes */
Test(hardening, item10_runtime_not_finite_or_out_of_range, .fini = cleanup) {
  make_dir();
  const char *e = cb_claims[0].experiment;
  char name[128];
  snprintf(name, sizeof name, "%s.csv", e);
  put(name, "# program: x\n# quick: 0\na,b\n1,2\n");
  snprintf(name, sizeof name, "%s.runtime", e);
  const char *bad[] = {"wall_s: nan\n", "wall_s: 1e20\n", "wall_s: 3e9\n", "wall_s: -inf\n", "wall_s: -5\n"};
  for (int i = 0; i < 5; i++) {
    put(name, bad[i]);
    const char *r = report_of(cb_report_runtimes);
    cr_expect(strstr(r, "-2147483648") == NULL && strstr(r, "nan") == NULL && strstr(r, "inf") == NULL,
              "'%s' printed as a time:\n%s", bad[i], r);
    cr_expect(strstr(r, "not a run time") != NULL, "'%s' not refused:\n%s", bad[i], r);
  }
  put(name, "wall_s: 125\n"); /* 2 min 05 s, and the total the same */
  const char *r = report_of(cb_report_runtimes);
  cr_expect(strstr(r, "| 2 min 05 s |") != NULL, "125 s not 2 min 05 s:\n%s", r);
}

/* item 10: a count read from a CSV becomes an int only when finite and in range */
Test(hardening, item10_table_int_refuses_nan_and_huge) {
  cr_expect_eq(cb_table_int_of(NAN), -1);
  cr_expect_eq(cb_table_int_of(1e20), -1);
  cr_expect_eq(cb_table_int_of(3e9), -1);
  cr_expect_eq(cb_table_int_of(-INFINITY), -1);
  cr_expect_eq(cb_table_int_of(42.0), 42);
  cr_expect_eq(cb_table_int_of(-7.0), -7);
}

/* item 9: a CSV cut in its last row is refused, not read as a short row */
Test(hardening, item9_csv_without_final_newline, .fini = cleanup) {
  make_dir();
  put("cut.csv", "# program: x\na,b\n1,2\n3,4");
  char p[256];
  snprintf(p, sizeof p, "%s/cut.csv", dir);
  cb_table t;
  cr_expect_neq(cb_table_read(p, &t), CB_OK, "a CSV cut in its last row was read");
  cr_expect(strstr(cb_error_message(), "does not end with a newline") != NULL, "%s", cb_error_message());
  put("whole.csv", "# program: x\na,b\n1,2\n3,4\n");
  snprintf(p, sizeof p, "%s/whole.csv", dir);
  cr_assert_eq(cb_table_read(p, &t), CB_OK, "%s", cb_error_message());
  cr_expect_eq(t.nrows, 2);
  cb_table_free(&t);
}

/* item 14: a FIFO as a config, a mesh or a CSV is refused at once (the
 * timeout turns the old wait for a writer into a failure) */
Test(hardening, item14_fifo_inputs_refused, .fini = cleanup, .timeout = 20) {
  make_dir();
  char p[256];
  snprintf(p, sizeof p, "%s/fifo", dir);
  cr_assert_eq(mkfifo(p, 0600), 0, "mkfifo: %s", strerror(errno));
  cb_config c;
  cr_expect_eq(cb_config_load(p, &c), CB_EIO);
  cr_expect(strstr(cb_error_message(), "not a regular file") != NULL, "%s", cb_error_message());
  cb_mesh m;
  cr_expect_eq(cb_mesh_read_obj(p, &m), CB_EIO);
  cr_expect(strstr(cb_error_message(), "not a regular file") != NULL, "%s", cb_error_message());
  cb_table t;
  cr_expect_eq(cb_table_read(p, &t), CB_EIO);
  cr_expect(strstr(cb_error_message(), "not a regular file") != NULL, "%s", cb_error_message());
}

/* item 8: report --fill marks the blocks it fills from a smoke or quick run */
Test(hardening, item8_fill_marks_smoke_verdicts, .fini = cleanup) {
  make_dir();
  const char *e = cb_claims[0].experiment, *id = cb_claims[0].id;
  char name[128], page[512], path[256];
  snprintf(name, sizeof name, "%s.csv", e);
  put(name, "# program: x\n# quick: 1\n# smoke: 1\na,b\n1,2\n");
  snprintf(page, sizeof page,
           "From the last full run:\n<!-- report:claim %s -->\n<!-- /report -->\n<!-- report:verdicts -->\n<!-- "
           "/report "
           "-->\n",
           id);
  put("page.md", page);
  cb_claim_result *res = calloc((size_t)cb_nclaims, sizeof *res);
  cr_assert(res);
  snprintf(path, sizeof path, "%s/page.md", dir);
  cr_assert_eq(cb_report_fill(path, res, dir), CB_OK, "%s", cb_error_message());
  const char *r = slurp("page.md");
  const char *claim = strstr(r, "<!-- report:claim"), *verdicts = strstr(r, "<!-- report:verdicts");
  cr_assert(claim && verdicts);
  const char *mark = strstr(claim, "Not a full run");
  cr_expect(mark && mark < verdicts, "the claim block filled from a smoke run is not marked:\n%s", r);
  cr_expect(strstr(verdicts, "Not a full run") != NULL, "the verdicts block is not marked:\n%s", r);
  cr_expect(strstr(r, "smoke") != NULL, "the kind of run is not named:\n%s", r);
  put(name, "# program: x\n# quick: 0\na,b\n1,2\n"); /* a full run: no mark */
  cr_assert_eq(cb_report_fill(path, res, dir), CB_OK, "%s", cb_error_message());
  cr_expect(strstr(slurp("page.md"), "Not a full run") == NULL, "a full run marked:\n%s", slurp("page.md"));
  free(res);
}

/* item 11: xpbd with stretch_k = bend_k = 0: infinite compliance, no
 * constraint; the cloth falls freely: x1 = x0 + dt^2 g for the free vertices
 * (v0 = 0, one substep), not NaN */
Test(hardening, item11_xpbd_zero_stiffness_falls) {
  const char *sets[] = {"integrator.method=xpbd", "material.stretch_k=0",   "material.bend_k=0",
                        "integrator.dt=0.01",     "scene.gravity=0 -9.8 0", NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof *x), *v = calloc((size_t)n3, sizeof *v);
  cr_assert(x && v);
  memcpy(x, s->x0, (size_t)n3 * sizeof *x);
  cb_step_stats st;
  int r = cb_integrator_step(it, x, v, &st);
  cr_expect_eq(r, CB_OK, "step 1: %s (%s)", cb_status_name(r), cb_error_message());
  double worst = 0;
  for (int i = 0; i < s->mesh.nv; i++) {
    double want_dy = s->free_index[i] >= 0 ? -9.8 * 0.01 * 0.01 : 0.0;
    double e = fabs(x[3 * i] - s->x0[3 * i]) + fabs(x[3 * i + 1] - s->x0[3 * i + 1] - want_dy) +
               fabs(x[3 * i + 2] - s->x0[3 * i + 2]);
    if (!(e <= worst)) worst = e; /* NaN makes worst NaN */
  }
  cr_expect(worst <= 1e-12, "the cloth does not fall freely: worst deviation from x0 + dt^2 g is %g", worst);
  free(x);
  free(v);
  cb_integrator_free(it);
  cb_scene_free(s);
}

/* item 12: a subnormal vertex_mass is refused with the key's name */
Test(hardening, item12_subnormal_vertex_mass_refused) {
  cb_config c;
  const char *sets[] = {"material.vertex_mass=5e-324", NULL};
  test_config(&c, sets);
  cb_scene *s = NULL;
  cr_expect_neq(cb_scene_from_config(&c, &s), CB_OK, "a vertex mass of 5e-324 kg was accepted");
  cr_expect(strstr(cb_error_message(), "material.vertex_mass") != NULL, "%s", cb_error_message());
  cb_scene_free(s);
}

/* item 13: pcg and cg with solver.tol = 0 on the hanging cloth reach
 * round-off and stop as not converged, never as "A is not positive definite" */
Test(hardening, item13_cg_tol_zero_stops_at_roundoff) {
  const char *solvers[] = {"pcg", "cg"};
  for (int k = 0; k < 2; k++) {
    cb_config c;
    cr_assert_eq(cb_config_load("configs/hanging.ini", &c), CB_OK, "%s", cb_error_message());
    char m[64];
    snprintf(m, sizeof m, "solver.method=%s", solvers[k]);
    cr_assert_eq(cb_config_set(&c, m), CB_OK);
    cr_assert_eq(cb_config_set(&c, "solver.tol=0"), CB_OK);
    cb_scene *s = NULL;
    cb_integrator *it = NULL;
    cr_assert_eq(cb_scene_from_config(&c, &s), CB_OK, "%s", cb_error_message());
    cr_assert_eq(cb_integrator_from_config(&c, s, NULL, &it), CB_OK, "%s", cb_error_message());
    int n3 = 3 * s->mesh.nv;
    double *x = malloc((size_t)n3 * sizeof *x), *v = calloc((size_t)n3, sizeof *v);
    memcpy(x, s->x0, (size_t)n3 * sizeof *x);
    cb_step_stats st;
    int r = cb_integrator_step(it, x, v, &st);
    cr_expect(r == CB_OK || r == CB_NOT_CONVERGED, "%s, tol 0, step 1: %s: %s", solvers[k], cb_status_name(r),
              cb_error_message());
    cr_expect(strstr(cb_error_message(), "not positive definite") == NULL, "%s", cb_error_message());
    free(x);
    free(v);
    cb_integrator_free(it);
    cb_scene_free(s);
  }
}

/* Also: pbd/xpbd's sweeps per step, iters x substeps, must fit an int */
Test(hardening, also_pbd_iters_times_substeps_fits_an_int) {
  const char *methods[] = {"pbd", "xpbd"};
  for (int k = 0; k < 2; k++) {
    char m[64];
    snprintf(m, sizeof m, "integrator.method=%s", methods[k]);
    const char *sets[] = {m, "integrator.iters=100000000", "integrator.substeps=1000000", NULL};
    cb_config c;
    test_config(&c, sets);
    cb_scene *s = test_scene(sets);
    cb_integrator *it = NULL;
    cr_expect_neq(cb_integrator_from_config(&c, s, NULL, &it), CB_OK, "%s: 1e14 sweeps per step accepted", m);
    cr_expect(strstr(cb_error_message(), "iters x substeps") != NULL, "%s", cb_error_message());
    cb_integrator_free(it);
    cb_scene_free(s);
  }
}

/* Also: lbfgs with a vertex exactly on the penalty sphere's centre takes its
 * step (the energy counted 0 there, a false minimum the line search could
 * not leave) */
Test(hardening, also_lbfgs_vertex_on_penalty_centre) {
  const char *base[] = {"integrator.method=lbfgs", NULL};
  cb_scene *s0 = test_scene(base);
  int i = s0->free_vertex[s0->model.nfree / 2];
  char c[256];
  snprintf(c, sizeof c, "collider.centre=%.17g %.17g %.17g", s0->x0[3 * i], s0->x0[3 * i + 1], s0->x0[3 * i + 2]);
  cb_scene_free(s0);
  const char *sets[] = {"integrator.method=lbfgs", "collider.type=penalty", "collider.radius=0.05", c, NULL};
  cb_scene *s = test_scene(sets);
  cb_integrator *it = test_integrator(sets, s, NULL, NULL);
  int n3 = 3 * s->mesh.nv;
  double *x = malloc((size_t)n3 * sizeof *x), *v = calloc((size_t)n3, sizeof *v);
  memcpy(x, s->x0, (size_t)n3 * sizeof *x);
  cb_step_stats st;
  int r = cb_integrator_step(it, x, v, &st);
  cr_expect(r == CB_OK || r == CB_NOT_CONVERGED, "step 1 with vertex %d on the centre: %s: %s", i, cb_status_name(r),
            cb_error_message());
  free(x);
  free(v);
  cb_integrator_free(it);
  cb_scene_free(s);
}
