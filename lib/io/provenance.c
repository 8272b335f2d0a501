#include "provenance.h"

#include <cblas.h>
#include <cholmod.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_version.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "blas_kernel.h"
#include "threads.h"

int cb_runtime_init(void) {
  gsl_set_error_handler_off();
  return cb_threads_init();
}

void cb_provenance_escaped(FILE *f, const char *s) {
  for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
    if (*p == '\\') fputs("\\\\", f);
    else if (*p == '\n') fputs("\\n", f);
    else if (*p == '\r') fputs("\\r", f);
    else if (*p == '\t') fputs("\\t", f);
    else if (*p < 0x20 || *p == 0x7f) fprintf(f, "\\x%02x", *p);
    else fputc(*p, f);
  }
}

void cb_provenance_config(FILE *f, const cb_config *cfg) {
  char *buf = NULL;
  size_t len = 0;
  FILE *m = open_memstream(&buf, &len);
  if (!m) {
    fputs("(out of memory)", f);
    return;
  }
  cb_config_write(cfg, m, " ");
  if (fclose(m) == 0 && buf) cb_provenance_escaped(f, buf);
  else fputs("(out of memory)", f);
  free(buf);
}

void cb_cpu_model(char *out, size_t n) {
  snprintf(out, n, "unknown");
  FILE *f = fopen("/proc/cpuinfo", "r");
  if (!f) return;
  char line[512];
  while (fgets(line, sizeof line, f)) {
    if (strncmp(line, "model name", 10) != 0) continue;
    const char *colon = strchr(line, ':');
    if (!colon) break;
    colon++;
    while (*colon == ' ' || *colon == '\t') colon++;
    snprintf(out, n, "%.*s", (int)strcspn(colon, "\n"), colon);
    break;
  }
  fclose(f);
}

void cb_provenance_write(FILE *f, const char *program, int argc, char **argv, const cb_config *cfg) {
  int cv[3] = {0, 0, 0};
  cholmod_version(cv);
  time_t now = time(NULL);
  struct tm tmv;
  char date[64];
  gmtime_r(&now, &tmv);
  strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &tmv);
  const char *omp = getenv("OMP_NUM_THREADS");
  fprintf(f, "# program: %s\n", program);
  fprintf(f, "# git_revision: %s (%s)\n", cb_build_git, cb_build_dirty);
  fprintf(f, "# compiler: gcc %s\n", __VERSION__);
  fprintf(f, "# cflags: %s\n", cb_build_cflags);
  fprintf(f, "# cholmod: %d.%d.%d\n", cv[0], cv[1], cv[2]);
  fprintf(f, "# gsl: %s\n", gsl_version);
  fprintf(f, "# openblas: %s\n", openblas_get_config());
  fprintf(f, "# blas_threads: %d\n", openblas_get_num_threads());
  const char *core;
  char how[1024];
  cb_blas_kernel_describe(&core, how, sizeof how);
  fputs("# blas_kernel: ", f);
  cb_provenance_escaped(f, core);
  fputs("\n# blas_kernel_choice: ", f);
  cb_provenance_escaped(f, how);
  fputc('\n', f);
  fputs("# omp_num_threads: ", f);
  cb_provenance_escaped(f, omp && *omp ? omp : "unset");
  fputc('\n', f);
  const cb_threads_info *th = cb_threads_info_get();
  fprintf(f, "# threads_requested: openblas %d, openmp %d (dynamic on: caps CHOLMOD's num_threads(4) regions)\n",
          th->blas_requested, th->omp_requested);
  fprintf(f,
          "# threads_observed: cholmod_factorize %d, dgemm %d (threads whose CPU time grew during a probe: "
          "supernodal factorisation of a 96^2-grid Laplacian, 384^3 dgemm)\n",
          th->cholmod_observed, th->dgemm_observed);
  char cpu[256];
  cb_cpu_model(cpu, sizeof cpu);
  fputs("# cpu: ", f);
  cb_provenance_escaped(f, cpu);
  fprintf(f, "\n# cores: %ld\n", sysconf(_SC_NPROCESSORS_ONLN));
  fputs("# command:", f);
  for (int i = 0; i < argc; i++) {
    fputc(' ', f);
    cb_provenance_escaped(f, argv[i]);
  }
  fputc('\n', f);
  if (cfg) {
    fputs("# config: ", f);
    cb_provenance_escaped(f, cfg->path[0] ? cfg->path : "(defaults)");
    fputs("\n# overrides: ", f);
    cb_provenance_escaped(f, cfg->overrides[0] ? cfg->overrides : "(none)");
    fputs("\n# config_effective: ", f);
    cb_provenance_config(f, cfg);
    fputc('\n', f);
  }
  fprintf(f, "# date: %s\n", date);
}
