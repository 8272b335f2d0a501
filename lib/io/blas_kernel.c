#include "blas_kernel.h"

#include <cblas.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "rng.h"

/* LAPACK's Cholesky factorisation (OpenBLAS's own, libopenblas exports it). */
extern void dpotrf_(const char *uplo, const int *n, double *a, const int *lda, int *info);

/* ---- core names ---- */

/* OpenBLAS's x86-64 DYNAMIC_ARCH core names (driver/others/dynamic.c) by the
 * instruction set their kernels use. */
static const struct {
  const char *name;
  int level;
} cores[] = {
    {"Katmai", 0},         {"Coppermine", 0},  {"Northwood", 0},    {"Prescott", 0},   {"Banias", 0},
    {"Atom", 0},           {"Core2", 0},       {"Penryn", 0},       {"Dunnington", 0}, {"Nehalem", 0},
    {"Athlon", 0},         {"Opteron", 0},     {"Opteron_SSE3", 0}, {"Barcelona", 0},  {"Nano", 0},
    {"Bobcat", 0},         {"Sandybridge", 1}, {"Bulldozer", 1},    {"Piledriver", 1}, {"Steamroller", 1},
    {"Excavator", 1},      {"Haswell", 2},     {"Zen", 2},          {"SkylakeX", 3},   {"Cooperlake", 3},
    {"SapphireRapids", 3},
};

int cb_blas_core_level(const char *core) {
  if (!core) return -1;
  for (size_t i = 0; i < sizeof cores / sizeof cores[0]; i++)
    if (!strcasecmp(core, cores[i].name)) return cores[i].level;
  return -1;
}

static int has_flag(const char *flags, const char *want) {
  size_t w = strlen(want);
  for (const char *p = flags; *p;) {
    p += strspn(p, " ,\t");
    size_t len = strcspn(p, " ,\t");
    if (len == w && !strncmp(p, want, w)) return 1;
    p += len;
  }
  return 0;
}

const char *cb_blas_best_core(const char *flags) {
  if (!flags) return NULL;
  if (has_flag(flags, "avx512f") && has_flag(flags, "avx512bw") && has_flag(flags, "avx512vl") &&
      has_flag(flags, "avx512dq"))
    return "SkylakeX";
  if (has_flag(flags, "avx2") && has_flag(flags, "fma")) return "Haswell";
  return NULL;
}

void cb_blas_cpu_flags(char *out, size_t n) {
  const char *inj = getenv("CB_BLAS_TEST_CPUFLAGS");
  if (inj) {
    snprintf(out, n, "%s", inj);
    return;
  }
  out[0] = '\0';
  __builtin_cpu_init();
  size_t used = 0;
#define CB_FLAG(name) \
  if (__builtin_cpu_supports(name) && used < n) \
    used += (size_t)snprintf(out + used, n - used, "%s%s", used ? " " : "", name);
  CB_FLAG("avx")
  CB_FLAG("avx2") CB_FLAG("fma") CB_FLAG("avx512f") CB_FLAG("avx512bw") CB_FLAG("avx512vl") CB_FLAG("avx512dq")
#undef CB_FLAG
}

const char *cb_blas_detected_core(int *injected) {
  const char *inj = getenv("CB_BLAS_TEST_CORENAME");
  if (injected) *injected = inj != NULL;
  return inj ? inj : openblas_get_corename();
}

void cb_blas_plan_make(const char *env_coretype, const char *detected, const char *flags, cb_blas_plan *p) {
  p->candidate = NULL;
  const char *best = cb_blas_best_core(flags);
  int have = cb_blas_core_level(detected);
  if (env_coretype && *env_coretype)
    snprintf(p->why, sizeof p->why, "OPENBLAS_CORETYPE=%s is set: left as it is", env_coretype);
  else if (!best)
    snprintf(p->why, sizeof p->why, "the CPU has neither AVX-512 F/BW/VL/DQ nor AVX2+FMA: no better kernel");
  else if (have < 0)
    snprintf(p->why, sizeof p->why, "core '%s' is not one clothbench ranks: left as it is",
             detected ? detected : "(none)");
  else if (have >= cb_blas_core_level(best))
    snprintf(p->why, sizeof p->why, "the detected %s is at least the CPU's best safe %s", detected, best);
  else {
    p->candidate = best;
    snprintf(p->why, sizeof p->why, "the detected %s is a fallback below the CPU's %s", detected, best);
  }
}

/* ---- the self-test ---- */

double cb_blas_rel_error(const double *x, const double *ref, size_t n) {
  double num = 0, den = 0;
  for (size_t i = 0; i < n; i++) {
    double d = fabs(x[i] - ref[i]);
    if (isnan(d)) return INFINITY;
    if (d > num) num = d;
    if (fabs(ref[i]) > den) den = fabs(ref[i]);
  }
  if (den == 0) return num == 0 ? 0 : 1;
  return num / den;
}

static cb_rng rng; /* the project's generator (rng.h), seeded by cb_blas_selftest */
static double urand(void) { return 2.0 * cb_rng_uniform(&rng) - 1.0; } /* uniform in [-1, 1) */
static void fill(double *a, size_t n) {
  for (size_t i = 0; i < n; i++) a[i] = urand();
}

/* column-major element (i, j) of a matrix with leading dimension ld */
#define AT(a, ld, i, j) (a)[(size_t)(j) * (size_t)(ld) + (size_t)(i)]

typedef struct {
  double worst;
  char msg[160];
} tally;

static void record(tally *t, const char *what, double err) {
  if (!(err <= t->worst)) {
    t->worst = err;
    snprintf(t->msg, sizeof t->msg, "%s: %.2g", what, err);
  }
}

/* C = alpha op(A) op(B) + beta C, m x n, inner dimension k */
static void test_gemm(tally *t, int ta, int tb, int m, int n, int k, double *buf) {
  int lda = ta ? k : m, ldb = tb ? n : k;
  double *a = buf, *b = a + (size_t)m * k, *c = b + (size_t)k * n, *r = c + (size_t)m * n;
  fill(a, (size_t)m * k);
  fill(b, (size_t)k * n);
  fill(c, (size_t)m * n);
  const double al = 0.7, be = -0.3;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < m; i++) {
      double s = 0;
      for (int l = 0; l < k; l++)
        s += (ta ? AT(a, lda, l, i) : AT(a, lda, i, l)) * (tb ? AT(b, ldb, j, l) : AT(b, ldb, l, j));
      AT(r, m, i, j) = al * s + be * AT(c, m, i, j);
    }
  cblas_dgemm(CblasColMajor, ta ? CblasTrans : CblasNoTrans, tb ? CblasTrans : CblasNoTrans, m, n, k, al, a, lda, b,
              ldb, be, c, m);
  char what[32];
  snprintf(what, sizeof what, "dgemm %c%c", ta ? 'T' : 'N', tb ? 'T' : 'N');
  record(t, what, cb_blas_rel_error(c, r, (size_t)m * n));
}

/* lower triangle of C = A A^T + C (A n x k); the upper triangle must stay */
static void test_syrk(tally *t, int n, int k, double *buf) {
  double *a = buf, *c = a + (size_t)n * k, *r = c + (size_t)n * n;
  fill(a, (size_t)n * k);
  fill(c, (size_t)n * n);
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double s = 0;
      if (i >= j)
        for (int l = 0; l < k; l++) s += AT(a, n, i, l) * AT(a, n, j, l);
      AT(r, n, i, j) = AT(c, n, i, j) + s;
    }
  cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, n, k, 1.0, a, n, 1.0, c, n);
  record(t, "dsyrk", cb_blas_rel_error(c, r, (size_t)n * n));
}

/* a well-conditioned lower-triangular n x n L (unit-ish diagonal, small off-diagonal) */
static void lower(double *l, int n) {
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) AT(l, n, i, j) = i > j ? urand() / n : i == j ? 1.5 + 0.5 * urand() : 0.0;
}

/* left: L X = B (B m x n, L m x m); right: X L^T = B (L n x n), CHOLMOD's call */
static void test_trsm(tally *t, int left, int m, int n, double *buf) {
  int nl = left ? m : n;
  double *l = buf, *b = l + (size_t)nl * nl, *r = b + (size_t)m * n;
  lower(l, nl);
  fill(b, (size_t)m * n);
  memcpy(r, b, (size_t)m * n * sizeof *r);
  if (left) {
    for (int j = 0; j < n; j++)
      for (int i = 0; i < m; i++) {
        double s = AT(r, m, i, j);
        for (int q = 0; q < i; q++) s -= AT(l, m, i, q) * AT(r, m, q, j);
        AT(r, m, i, j) = s / AT(l, m, i, i);
      }
  } else { /* X L^T = B: column j of X from columns < j */
    for (int j = 0; j < n; j++)
      for (int i = 0; i < m; i++) {
        double s = AT(r, m, i, j);
        for (int q = 0; q < j; q++) s -= AT(r, m, i, q) * AT(l, n, j, q);
        AT(r, m, i, j) = s / AT(l, n, j, j);
      }
  }
  if (left) cblas_dtrsm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasNonUnit, m, n, 1.0, l, m, b, m);
  else cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasNonUnit, m, n, 1.0, l, n, b, m);
  record(t, left ? "dtrsm left" : "dtrsm right", cb_blas_rel_error(b, r, (size_t)m * n));
}

/* lower Cholesky factor of A = G G^T + n I */
static void test_potrf(tally *t, int n, double *buf) {
  double *g = buf, *a = g + (size_t)n * n, *r = a + (size_t)n * n;
  fill(g, (size_t)n * n);
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double s = i == j ? n : 0.0;
      for (int q = 0; q < n; q++) s += AT(g, n, i, q) * AT(g, n, j, q);
      AT(a, n, i, j) = s;
    }
  memcpy(r, a, (size_t)n * n * sizeof *r);
  for (int j = 0; j < n; j++) { /* column by column (left-looking) */
    double d = AT(r, n, j, j);
    for (int q = 0; q < j; q++) d -= AT(r, n, j, q) * AT(r, n, j, q);
    d = sqrt(d);
    AT(r, n, j, j) = d;
    for (int i = j + 1; i < n; i++) {
      double s = AT(r, n, i, j);
      for (int q = 0; q < j; q++) s -= AT(r, n, i, q) * AT(r, n, j, q);
      AT(r, n, i, j) = s / d;
    }
  }
  int info = 0;
  dpotrf_("L", &n, a, &n, &info);
  if (info) {
    record(t, "dpotrf (info != 0)", INFINITY);
    return;
  }
  for (int j = 0; j < n; j++) /* compare the lower triangles */
    for (int i = 0; i < j; i++) AT(a, n, i, j) = AT(r, n, i, j);
  record(t, "dpotrf", cb_blas_rel_error(a, r, (size_t)n * n));
}

double cb_blas_selftest(char *msg, size_t n) {
  enum { SZ = 4 * 420 * 420 };
  double *buf = malloc(SZ * sizeof *buf);
  if (!buf) {
    snprintf(msg, n, "out of memory for the self-test");
    return -1;
  }
  rng = cb_rng_seed(1);
  tally t = {0, "none"};
  /* odd sizes: the edge kernels; k and n beyond the blocking of every core */
  test_gemm(&t, 0, 0, 197, 213, 417, buf);
  test_gemm(&t, 1, 0, 131, 77, 401, buf);
  test_gemm(&t, 0, 1, 61, 259, 133, buf);
  test_gemm(&t, 0, 0, 7, 5, 3, buf);
  test_syrk(&t, 203, 389, buf);
  test_trsm(&t, 1, 257, 101, buf);
  test_trsm(&t, 0, 301, 167, buf);
  test_potrf(&t, 333, buf);
  test_potrf(&t, 45, buf);
  free(buf);
  snprintf(msg, n, "%s", t.msg);
  return t.worst;
}

/* ---- what runs, for the provenance ---- */

/* CB_BLAS_CHOICE as build/blas-kernel sets it: "chosen <core>; ..." or
 * "refused <core>; ...". Returns 'c', 'r' or 0 (unset or malformed), with the
 * core in core[64]. */
static int choice(char core[64], const char **text) {
  const char *s = getenv("CB_BLAS_CHOICE");
  *text = s;
  char verb[16];
  if (!s || sscanf(s, "%15s %63[^;]", verb, core) != 2) return 0;
  if (!strcmp(verb, "chosen")) return 'c';
  if (!strcmp(verb, "refused")) return 'r';
  return 0;
}

/* The running core and one sentence on how it came to run. Returns 1 when
 * it is a detected fallback below a better core with no refusal recorded
 * (the case to warn about), with that core in *best. */
static int describe(const char **core, char *how, size_t n, const char **best) {
  const char *env = getenv("OPENBLAS_CORETYPE"), *text;
  char ch[64];
  int injected = 0, kind = choice(ch, &text);
  const char *running = openblas_get_corename();
  *best = NULL;
  if (env && *env) {
    *core = running;
    if (kind == 'c' && !strcasecmp(ch, env) && !strcasecmp(ch, running)) snprintf(how, n, "%s", text);
    else snprintf(how, n, "set by the environment (OPENBLAS_CORETYPE=%s)", env);
    return 0;
  }
  const char *det = cb_blas_detected_core(&injected);
  *core = det;
  char flags[256];
  cb_blas_cpu_flags(flags, sizeof flags);
  cb_blas_plan p;
  cb_blas_plan_make(NULL, det, flags, &p);
  const char *inj = injected ? " (CB_BLAS_TEST_CORENAME)" : "";
  if (!p.candidate) {
    snprintf(how, n, "detected%s; %s", inj, p.why);
    return 0;
  }
  if (kind == 'r' && !strcasecmp(ch, p.candidate)) {
    snprintf(how, n, "detected%s; %s; %s", inj, p.why, text);
    return 0;
  }
  *best = p.candidate;
  snprintf(how, n, "detected%s; %s (not started by make: OPENBLAS_CORETYPE=%s would select it)", inj, p.why,
           p.candidate);
  return 1;
}

void cb_blas_kernel_describe(const char **core, char *how, size_t n) {
  const char *best;
  describe(core, how, n, &best);
}

int cb_blas_kernel_warning(FILE *f, const char *program) {
  const char *core, *best;
  char how[1024];
  if (!describe(&core, how, sizeof how, &best)) return 0;
  fprintf(f,
          "%s: warning: OpenBLAS runs its fallback %s kernels on this CPU, which supports %s: "
          "set OPENBLAS_CORETYPE=%s (make's runs select it after a self-test: build/blas-kernel --show)\n",
          program, core, best, best);
  return 1;
}
