/* The scene declarations (lib/io/scene_decl.c) and the sweep runner with
 * --shard (lib/io/sweep.c): overrides in order, errors that name the scene,
 * rows in cell order, which cells a shard runs and its cell list. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_decl.h"
#include "support.h"
#include "sweep.h"

static cb_experiment begin(const char *out, const char *shard) {
  static char *argv[8];
  int argc = 0;
  argv[argc++] = "test_sweep";
  argv[argc++] = "--out";
  argv[argc++] = (char *)out;
  if (shard) {
    argv[argc++] = "--shard";
    argv[argc++] = (char *)shard;
  }
  cb_experiment e;
  cr_assert_eq(cb_experiment_begin(&e, "test_sweep", "", argc, argv), 0);
  return e;
}

Test(scene_decl, overrides_apply_in_order_then_the_cells_own) {
  cb_experiment e = begin("/tmp/unused.csv", NULL);
  cb_scene_decl d = {"soft", "hanging.ini", {"material.stretch_k=1e4", "material.stretch_k=2e4", NULL}, "map"};
  const char *more[] = {"integrator.dt=1/60", NULL};
  cb_config c;
  cr_assert_eq(cb_scene_decl_config(&e, &d, more, &c), CB_OK, "%s", cb_error_message());
  cr_assert_eq(c.stretch_k, 2e4); /* the later override wins */
  cr_assert_eq(c.dt, 1.0 / 60);
  cr_assert_str_eq(cb_scene_decl_override(&d, "material.stretch_k"), "2e4");
  cr_assert_null(cb_scene_decl_override(&d, "material.stretch"));
  cr_assert(cb_scene_decl_is(&d, "map") && !cb_scene_decl_is(&d, "ma"));
}

Test(scene_decl, errors_name_the_scene_and_the_key) {
  cb_experiment e = begin("/tmp/unused.csv", NULL);
  cb_scene_decl bad = {"wobbly", "hanging.ini", {"material.stretch_k=soft", NULL}, "map"};
  cb_config c;
  cr_assert_lt(cb_scene_decl_config(&e, &bad, NULL, &c), 0);
  cr_assert(strstr(cb_error_message(), "scene wobbly (hanging.ini)"), "%s", cb_error_message());
  cr_assert(strstr(cb_error_message(), "stretch_k"), "%s", cb_error_message());
  cb_scene_decl missing = {"ghost", "no_such.ini", {NULL}, "map"};
  cb_scene *s = (cb_scene *)&c;
  cr_assert_lt(cb_scene_decl_build(&e, &missing, NULL, NULL, &s), 0);
  cr_assert_null(s);
  cr_assert(strstr(cb_error_message(), "scene ghost (no_such.ini)"), "%s", cb_error_message());
}

/* cell i writes i rows "i,r" to the main table and, if i is even, one row to the side table */
static int cell(long i, void *ctx, FILE *const *out) {
  long *ran = ctx;
  ran[i]++;
  for (long r = 0; r < i; r++) fprintf(out[0], "%ld,%ld\n", i, r);
  if (i % 2 == 0) fprintf(out[1], "%ld\n", i);
  return i == 99 ? cb_fail("cell 99 fails") : CB_OK;
}

static char *slurp(const char *path) {
  FILE *f = fopen(path, "r");
  cr_assert_not_null(f, "%s", path);
  static char buf[1 << 20]; /* the provenance lines list every config's keys: tens of kB */
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  buf[n] = 0;
  cr_assert(feof(f), "%s: larger than the test's buffer", path);
  fclose(f);
  return buf;
}

static const char *data(const char *text) { /* after the header row (the first line not starting with '#') */
  const char *p = text;
  while (*p == '#') {
    p = strchr(p, '\n');
    cr_assert_not_null(p, "no header row");
    p++;
  }
  p = strchr(p, '\n');
  cr_assert_not_null(p, "no line after the header row");
  return p + 1;
}

Test(sweep, rows_in_cell_order_and_a_shard_runs_every_nth_cell) {
  char dir[] = "/tmp/cbsweepXXXXXX", out[128], side[160], cells[160];
  cr_assert_not_null(mkdtemp(dir));
  snprintf(out, sizeof out, "%s/s.csv", dir);
  snprintf(side, sizeof side, "%s/s_side.csv", dir);
  snprintf(cells, sizeof cells, "%s.cells", out);
  for (int sharded = 0; sharded < 2; sharded++) {
    cb_experiment e = begin(out, sharded ? "2/3" : NULL);
    cr_assert_eq(cb_experiment_table(&e, NULL, NULL, "i,r"), 0);
    cr_assert_eq(cb_experiment_table(&e, "side", NULL, "i"), 1);
    long ran[5] = {0}, ran2[3] = {0};
    cb_sweep sw[] = {{"first", 5, cell, NULL, ran}, {"second", 3, cell, NULL, ran2}};
    cr_assert_eq(cb_sweep_run(&e, sw, 2), CB_OK);
    cr_assert_eq(cb_experiment_end(&e, CB_OK), CB_OK);
    if (!sharded) {
      cr_assert_str_eq(data(slurp(out)), "1,0\n2,0\n2,1\n3,0\n3,1\n3,2\n4,0\n4,1\n4,2\n4,3\n1,0\n2,0\n2,1\n");
      cr_assert_str_eq(data(slurp(side)), "0\n2\n4\n0\n2\n");
      for (int i = 0; i < 5; i++) cr_assert_eq(ran[i], 1);
      continue;
    }
    /* global cells 0..7; shard 2 of 3 runs 1, 4 (first sweep) and 7 (the second sweep's cell 2) */
    cr_assert(ran[1] == 1 && ran[4] == 1 && ran2[2] == 1 && ran[0] + ran[2] + ran[3] + ran2[0] + ran2[1] == 0);
    cr_assert_str_eq(data(slurp(out)), "1,0\n4,0\n4,1\n4,2\n4,3\n2,0\n2,1\n");
    cr_assert_str_eq(data(slurp(side)), "4\n2\n");
    cr_assert_str_eq(slurp(cells), "shard 2 3 8\ntables - side\n1 1 0\n4 4 1\n7 2 1\n");
  }
  remove(out); remove(side); remove(cells); remove(dir);
}

Test(sweep, a_failing_cell_is_named_and_drops_the_tables) {
  char dir[] = "/tmp/cbsweepXXXXXX", out[128];
  cr_assert_not_null(mkdtemp(dir));
  snprintf(out, sizeof out, "%s/f.csv", dir);
  cb_experiment e = begin(out, NULL);
  cr_assert_eq(cb_experiment_table(&e, NULL, NULL, "i,r"), 0);
  cr_assert_eq(cb_experiment_table(&e, "side", NULL, "i"), 1);
  long ran[100] = {0};
  cb_sweep sw = {"failing", 100, cell, NULL, ran};
  cr_assert_eq(cb_sweep_run(&e, &sw, 1), CB_EINVAL);
  cr_assert(strstr(cb_error_message(), "failing cell 99: cell 99 fails"), "%s", cb_error_message());
  cr_assert_eq(cb_experiment_end(&e, CB_EINVAL), CB_EINVAL);
  cr_assert_null(fopen(out, "r")); /* nothing committed */
  remove(dir);
}

Test(sweep, bad_shard_options_are_refused) {
  const char *bad[] = {"0/3", "4/3", "2/x", "2/3x", "/3", "1/0"};
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    char *argv[] = {"test_sweep", "--shard", (char *)bad[i], NULL};
    cb_experiment e;
    cr_assert_lt(cb_experiment_begin(&e, "test_sweep", "", 3, argv), 0, "%s accepted", bad[i]);
  }
  char *argv[] = {"test_sweep", "--shard", "3/3", NULL};
  cb_experiment e;
  cr_assert_eq(cb_experiment_begin(&e, "test_sweep", "", 3, argv), 0);
  cr_assert_str_eq(e.out, "results/shard-3of3/test_sweep.csv");
}
