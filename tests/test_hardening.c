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
#include <unistd.h>

#include "support.h"

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
  errno = 0; /* ... which goes on: other calls set errno before the commit */
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
