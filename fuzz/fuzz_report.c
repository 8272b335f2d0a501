/* libFuzzer harness: the report and the claim checkers on crafted CSVs
 * (issue 35: nan, 1e20 and 3e9 in a CSV or a .runtime file were converted to
 * int with undefined behaviour, which UBSan in this build aborts on).
 * The input is a CSV. Its first line, "# file: NAME.csv", names the file it
 * becomes in a scratch results folder (NAME: letters, digits and '_' only;
 * without that line, the first claim's experiment's main CSV); the same bytes
 * are also written as the main CSV of the experiment whose name NAME starts
 * with (so that a side table's checker runs at all), and the input's last
 * line, as "wall_s: <it>", is that experiment's .runtime. Then every claim
 * of that experiment is decided and the report's origin and run-time tables
 * are written (to /dev/null). Any input must give verdicts and reasons,
 * never a crash, a sanitizer report or a hang. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "claims.h"
#include "report.h"

static char dir[256];
static FILE *devnull;

static void remove_dir(void) {
  char cmd[300];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd) != 0) fprintf(stderr, "fuzz_report: could not remove %s\n", dir);
}

static int put(const char *name, const uint8_t *data, size_t size) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "wb");
  if (!f) return -1;
  size_t w = fwrite(data, 1, size, f);
  return fclose(f) != 0 || w != size ? -1 : 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (!dir[0]) {
    const char *t = getenv("TMPDIR");
    snprintf(dir, sizeof dir, "%s/cbfuzzreport.%ld", t && t[0] ? t : "/tmp", (long)getpid());
    if (mkdir(dir, 0700) != 0 && access(dir, W_OK) != 0) abort();
    atexit(remove_dir);
    devnull = fopen("/dev/null", "w");
    if (!devnull) abort();
  }
  static char written[3][128]; /* the previous input's files */
  for (int k = 0; k < 3; k++)
    if (written[k][0]) {
      char p[512];
      snprintf(p, sizeof p, "%s/%s", dir, written[k]);
      unlink(p);
      written[k][0] = '\0';
    }
  /* the file name */
  char name[64] = "";
  static const char tag[] = "# file: ";
  if (size > sizeof tag && !memcmp(data, tag, sizeof tag - 1)) {
    size_t i = sizeof tag - 1, n = 0;
    while (i < size && n + 1 < sizeof name && data[i] != '\n') {
      char ch = (char)data[i++];
      if (!((ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_' || ch == '.')) return 0;
      name[n++] = ch;
    }
    name[n] = '\0';
    if (n < 5 || strcmp(name + n - 4, ".csv") != 0 || strstr(name, "..")) return 0;
  }
  const char *exp = NULL;
  for (int i = 0; i < cb_nclaims && !exp; i++) {
    const char *e = cb_claims[i].experiment;
    if (e && (!name[0] || !strncmp(name, e, strlen(e)))) exp = e;
  }
  if (!exp) return 0;
  char main_csv[128];
  snprintf(main_csv, sizeof main_csv, "%s.csv", exp);
  snprintf(written[0], sizeof written[0], "%s", main_csv);
  snprintf(written[1], sizeof written[1], "%s", name);
  if (put(main_csv, data, size) || (name[0] && put(name, data, size))) return 0;
  /* the last line as the run time */
  size_t last = size;
  while (last > 0 && data[last - 1] == '\n') last--;
  size_t from = last;
  while (from > 0 && data[from - 1] != '\n') from--;
  char rt[160];
  int n = snprintf(rt, sizeof rt, "wall_s: %.*s\n", (int)(last - from > 100 ? 100 : last - from),
                   (const char *)data + from);
  char rtname[128];
  snprintf(rtname, sizeof rtname, "%s.runtime", exp);
  snprintf(written[2], sizeof written[2], "%s", rtname);
  if (n > 0 && put(rtname, (const uint8_t *)rt, strlen(rt))) return 0;
  for (int i = 0; i < cb_nclaims; i++) {
    if (!cb_claims[i].experiment || strcmp(cb_claims[i].experiment, exp) != 0) continue;
    cb_claim_result *res = calloc(1, sizeof *res);
    if (!res) abort();
    cb_claim_decide(&cb_claims[i], dir, res);
    (void)cb_verdict_name(res->verdict);
    free(res);
  }
  cb_report_origin(devnull, dir);
  cb_report_runtimes(devnull, dir);
  return 0;
}
