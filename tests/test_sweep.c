/* The scene declarations (lib/io/scene_decl.c) and the sweep runner with
 * --shard (lib/io/sweep.c): overrides in order, errors that name the scene,
 * rows in cell order, which cells a shard runs (modulo and balanced) and its
 * cell list, and the lock each cell holds. */
#include <criterion/criterion.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <unistd.h>

#include "scene_decl.h"
#include "support.h"
#include "sweep.h"

static cb_experiment begin_mode(const char *out, const char *shard, const char *mode) {
  static char *argv[8];
  int argc = 0;
  argv[argc++] = "test_sweep";
  argv[argc++] = "--out";
  argv[argc++] = (char *)out;
  if (shard) {
    argv[argc++] = "--shard";
    argv[argc++] = (char *)shard;
  }
  if (mode) {
    argv[argc++] = "--shard-mode";
    argv[argc++] = (char *)mode;
  }
  cb_experiment e;
  cr_assert_eq(cb_experiment_begin(&e, "test_sweep", "", argc, argv), 0);
  return e;
}

static cb_experiment begin(const char *out, const char *shard) { return begin_mode(out, shard, NULL); }

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
Test(sweep, scene_size_reads_the_declared_config) {
  cb_experiment e = begin("/tmp/unused.csv", NULL);
  cb_scene_decl d = {"big", "hanging.ini", {"mesh.n=42", "integrator.dt=1/60", NULL}, "w1"};
  cb_scene_size z;
  cr_assert_eq(cb_sweep_scene_size(&e, &d, &z), CB_OK, "%s", cb_error_message());
  cr_assert_eq(z.nv, 42 * 42);
  cr_assert_eq(z.mesh_n, 42);
  cr_assert_float_eq(z.rel, 4.0, 1e-12); /* 42^2 = 4 x 21^2 */
  cr_assert_eq(z.dt, 1.0 / 60);
  cb_scene_decl bad = {"wobbly", "hanging.ini", {"mesh.n=lots", NULL}, "w1"};
  cr_assert_lt(cb_sweep_scene_size(&e, &bad, &z), 0);
  cr_assert(strstr(cb_error_message(), "scene wobbly (hanging.ini)"), "%s", cb_error_message());
  cr_assert_eq(z.nv, 0);
}

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

/* the text with each line's last field (a cell's measured seconds) dropped */
static char *without_seconds(const char *text) {
  static char buf[1 << 16];
  size_t n = 0;
  for (const char *p = text; *p;) {
    const char *nl = strchr(p, '\n'), *end = nl ? nl : p + strlen(p), *sp = end;
    while (sp > p && sp[-1] != ' ') sp--;
    if (sp > p && strncmp(p, "shard ", 6) && strncmp(p, "tables", 6)) end = sp - 1; /* a cell line */
    cr_assert_lt(n + (size_t)(end - p) + 2, sizeof buf);
    memcpy(buf + n, p, (size_t)(end - p));
    n += (size_t)(end - p);
    buf[n++] = '\n';
    p = nl ? nl + 1 : end + strlen(end);
  }
  buf[n] = 0;
  return buf;
}

Test(sweep, rows_in_cell_order_and_a_shard_runs_every_nth_cell) {
  char dir[] = "/tmp/cbsweepXXXXXX", out[128], side[160], cells[160];
  cr_assert_not_null(mkdtemp(dir));
  snprintf(out, sizeof out, "%s/s.csv", dir);
  snprintf(side, sizeof side, "%s/s_side.csv", dir);
  snprintf(cells, sizeof cells, "%s.cells", out);
  for (int sharded = 0; sharded < 2; sharded++) {
    cb_experiment e = begin_mode(out, sharded ? "2/3" : NULL, sharded ? "modulo" : NULL);
    cr_assert_eq(cb_experiment_table(&e, NULL, NULL, "i,r"), 0);
    cr_assert_eq(cb_experiment_table(&e, "side", NULL, "i"), 1);
    long ran[5] = {0}, ran2[3] = {0};
    cb_sweep sw[] = {{"first", 5, cell, NULL, ran, NULL}, {"second", 3, cell, NULL, ran2, NULL}};
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
    /* per cell: index, rows per table, sweep group, sweep, index there, hint (then the seconds) */
    cr_assert_str_eq(without_seconds(slurp(cells)), "shard 2 3 8 modulo\ntables - side\n1 1 0 0 first 1 1\n4 4 1 0 "
                                                    "first 4 1\n7 2 1 0 second 2 1\n");
  }
  remove(out);
  remove(side);
  remove(cells);
  remove(dir);
}

static double hint(long i, void *ctx) {
  (void)ctx;
  static const double c[] = {1, 9, 2, 7, 3, 3, 5};
  return c[i];
}

static int quiet_cell(long i, void *ctx, FILE *const *out) {
  ((long *)ctx)[i]++;
  fprintf(out[0], "%ld\n", i);
  return CB_OK;
}

/* the longest-processing-time rule on hints 1 9 2 7 3 3 5 over 3 shards:
 * 9, 7, 5 open the shards; 3 (cell 4) to the 5, 3 (cell 5) to the 7, 2 to
 * the 8, 1 to the 9: every shard carries 10; each cell runs exactly once */
Test(sweep, balanced_shards_follow_the_longest_processing_time_rule) {
  char dir[] = "/tmp/cbsweepXXXXXX", out[128], cells[160];
  cr_assert_not_null(mkdtemp(dir));
  snprintf(out, sizeof out, "%s/b.csv", dir);
  snprintf(cells, sizeof cells, "%s.cells", out);
  const char *want[] = {"0 1", "3 5",
                        "2 4 6"}; /* shard I's cells; of the equal hints, cell 4 (the earlier) goes first */
  long ran[3][7] = {{0}};
  for (int k = 0; k < 3; k++) {
    char shard[16];
    snprintf(shard, sizeof shard, "%d/3", k + 1);
    cb_experiment e = begin(out, shard);
    cr_assert_eq(cb_experiment_table(&e, NULL, NULL, "i"), 0);
    cb_sweep sw = {"lpt", 7, quiet_cell, hint, ran[k], NULL};
    cr_assert_eq(cb_sweep_run(&e, &sw, 1), CB_OK);
    cr_assert_eq(cb_experiment_end(&e, CB_OK), CB_OK);
    char got[32] = "";
    for (int i = 0; i < 7; i++)
      if (ran[k][i]) snprintf(got + strlen(got), sizeof got - strlen(got), "%s%d", *got ? " " : "", i);
    cr_assert_str_eq(got, want[k], "shard %d ran cells %s", k + 1, got);
    cr_assert(!strncmp(slurp(cells), "shard ", 6) && strstr(slurp(cells), " balanced\n"), "%s", slurp(cells));
  }
  for (int i = 0; i < 7; i++)
    cr_assert_eq(ran[0][i] + ran[1][i] + ran[2][i], 1, "cell %d ran %ld times", i, ran[0][i] + ran[1][i] + ran[2][i]);
  remove(out);
  remove(cells);
  remove(dir);
}

Test(sweep, a_failing_cell_is_named_and_drops_the_tables) {
  char dir[] = "/tmp/cbsweepXXXXXX", out[128];
  cr_assert_not_null(mkdtemp(dir));
  snprintf(out, sizeof out, "%s/f.csv", dir);
  cb_experiment e = begin(out, NULL);
  cr_assert_eq(cb_experiment_table(&e, NULL, NULL, "i,r"), 0);
  cr_assert_eq(cb_experiment_table(&e, "side", NULL, "i"), 1);
  long ran[100] = {0};
  cb_sweep sw = {"failing", 100, cell, NULL, ran, NULL};
  cr_assert_eq(cb_sweep_run(&e, &sw, 1), CB_EINVAL);
  cr_assert(strstr(cb_error_message(), "failing cell 99: cell 99 fails"), "%s", cb_error_message());
  cr_assert_eq(cb_experiment_end(&e, CB_EINVAL), CB_EINVAL);
  cr_assert_null(fopen(out, "r")); /* nothing committed */
  remove(dir);
}

Test(sweep, bad_shard_options_are_refused) {
  const char *bad[] = {"0/3", "4/3", "2/x", "2/3x", "/3", "1/0"};
  char *badmode[] = {"test_sweep", "--shard", "1/2", "--shard-mode", "random", NULL};
  cb_experiment em;
  cr_assert_lt(cb_experiment_begin(&em, "test_sweep", "", 5, badmode), 0, "--shard-mode random accepted");
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

/* The per-cell lock (cb_experiment_timed_cells and cb_sweep.timed), seen from outside the runner: inside each
 * cell, a second open file description of the lock file asks for it without blocking. A timed cell holds it
 * exclusively, so even a shared request fails; an untimed cell holds it shared, so a shared request passes and
 * an exclusive one fails. Cell i's kind: the sweep's timed() when it has one (odd cells timed), else its name. */
typedef struct {
  const char *lock;
  int kind[8]; /* per cell: 2 held exclusively, 1 held shared, 0 neither (no lock held) */
} probe;

static int probe_cell(long i, void *ctx, FILE *const *out) {
  (void)out;
  probe *p = ctx;
  int fd = open(p->lock, O_RDWR);
  if (fd < 0) return CB_EIO;
  int sh = flock(fd, LOCK_SH | LOCK_NB) == 0;
  if (sh) flock(fd, LOCK_UN);
  int ex = flock(fd, LOCK_EX | LOCK_NB) == 0;
  close(fd);
  p->kind[i] = !sh ? 2 : !ex ? 1 : 0;
  return CB_OK;
}

static int odd_timed(long i, void *ctx) {
  (void)ctx;
  return (int)(i & 1);
}

Test(sweep, per_cell_lock_timed_cells_alone_untimed_shared) {
  char dir[] = "/tmp/cbsweepXXXXXX", out[128], lock[128], split[160];
  cr_assert_not_null(mkdtemp(dir));
  snprintf(out, sizeof out, "%s/p.csv", dir);
  snprintf(lock, sizeof lock, "%s/cpu.lock", dir);
  snprintf(split, sizeof split, "%s.split", out);
  setenv("CB_CPU_LOCK", lock, 1);
  cb_experiment e = begin(out, NULL);
  cb_experiment_timed_cells(&e, (const char *const[]){"named untimed", NULL});
  probe a = {lock, {0}}, b = {lock, {0}}, c = {lock, {0}};
  cb_sweep sw[] = {{"by cell", 4, probe_cell, NULL, &a, odd_timed},
                   {"named untimed", 2, probe_cell, NULL, &b, NULL},
                   {"timed by default", 2, probe_cell, NULL, &c, NULL}};
  cr_assert_eq(cb_sweep_run(&e, sw, 3), CB_OK, "%s", cb_error_message());
  cr_assert_eq(cb_experiment_end(&e, CB_OK), CB_OK, "%s", cb_error_message());
  unsetenv("CB_CPU_LOCK");
  for (int i = 0; i < 4; i++) cr_assert_eq(a.kind[i], i & 1 ? 2 : 1, "by cell %d: lock kind %d", i, a.kind[i]);
  for (int i = 0; i < 2; i++) {
    cr_assert_eq(b.kind[i], 1, "named untimed %d: lock kind %d", i, b.kind[i]);
    cr_assert_eq(c.kind[i], 2, "timed by default %d: lock kind %d", i, c.kind[i]);
  }
  /* the split counts the 4 timed cells' seconds as timed and the 4 others' as untimed: all non-negative */
  const char *s = slurp(split);
  cr_assert(strstr(s, "timed_cells_s: ") && strstr(s, "untimed_cells_s: ") && strstr(s, "cell_locks: 1\n"), "%s", s);
  /* and one line per cell: its global index, its kind (as above), its seconds and its sweep */
  static const int kind[8] = {0, 1, 0, 1, 0, 0, 1, 1};
  const char *line = s;
  for (int g = 0; g < 8; g++) {
    char want[32];
    snprintf(want, sizeof want, "cell %d %d ", g, kind[g]);
    line = strstr(line, want);
    cr_assert_not_null(line, "no line '%s' in order in %s", want, s);
    line += strlen(want);
  }
  cr_assert(strstr(s, " named_untimed\n") && strstr(s, " by_cell\n"), "%s", s);
  remove(split);
  remove(out);
  remove(lock);
  char turn[160];
  snprintf(turn, sizeof turn, "%s.turn", lock);
  remove(turn);
  remove(dir);
}
