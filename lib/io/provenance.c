#include "provenance.h"

#include <cblas.h>
#include <cholmod.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_version.h>
#include <stdlib.h>
#include <time.h>

/* OpenBLAS extensions (declared in its cblas.h) */
void cb_runtime_init(void) {
  gsl_set_error_handler_off();
  const char *env = getenv("OPENBLAS_NUM_THREADS");
  if (!env || !*env) openblas_set_num_threads(1);
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
  fprintf(f, "# omp_num_threads: %s\n", omp && *omp ? omp : "unset");
  fputs("# command:", f);
  for (int i = 0; i < argc; i++) fprintf(f, " %s", argv[i]);
  fputc('\n', f);
  if (cfg) {
    fprintf(f, "# config: %s\n", cfg->path[0] ? cfg->path : "(defaults)");
    fprintf(f, "# overrides: %s\n", cfg->overrides[0] ? cfg->overrides : "(none)");
    fputs("# config_effective: ", f);
    cb_config_write(cfg, f, " ");
    fputc('\n', f);
  }
  fprintf(f, "# date: %s\n", date);
}
