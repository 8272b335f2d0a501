/* blas-kernel: starts a program with the best safe OpenBLAS kernel.
 *
 *   blas-kernel [--cache FILE] [--] PROGRAM [ARG...]
 *   blas-kernel [--cache FILE] --show
 *   blas-kernel --self-test
 *
 * OpenBLAS reads OPENBLAS_CORETYPE when it is loaded, so the kernel must be
 * in the environment before the program starts: the Makefile puts this
 * program in front of every program make starts (EXP_ENV). With
 * OPENBLAS_CORETYPE already set it changes nothing. Otherwise, when the core
 * OpenBLAS detects is a fallback below what the CPU supports
 * (blas_kernel.h), it runs the self-test of the better core in a child
 * process started with OPENBLAS_CORETYPE=<core> (--self-test: dgemm, dsyrk,
 * dtrsm and dpotrf against straightforward loops, 1e-12 relative) and, if
 * it passes, executes PROGRAM with OPENBLAS_CORETYPE=<core>. Either way
 * CB_BLAS_CHOICE tells PROGRAM what was chosen or refused and why, for the
 * "# blas_kernel_choice:" line of its CSV's provenance.
 *
 * The self-test's verdict is cached in FILE (default build/blas-kernel.cache),
 * one line per CPU model name (with its AVX flags), OpenBLAS version and
 * core, so it runs once per
 * machine. --show prints the decision without running a program.
 * Exit status: PROGRAM's; 2 for a usage error; 127 when PROGRAM cannot run. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cblas.h>

#include "blas_kernel.h"
#include "provenance.h"

static int self_test(void) {
  const char *want = getenv("OPENBLAS_CORETYPE"), *got = openblas_get_corename();
  if (want && *want && strcasecmp(want, got)) {
    printf("failed: OpenBLAS runs %s, not the requested %s\n", got, want);
    return 1;
  }
  alarm(300); /* a kernel that hangs fails */
  char msg[200];
  double e = cb_blas_selftest(msg, sizeof msg);
  if (e < 0) {
    printf("failed: %s\n", msg);
    return 1;
  }
  int ok = e <= CB_BLAS_SELFTEST_TOL;
  printf("%s: dgemm, dsyrk, dtrsm, dpotrf on %s: max rel. error %.2g (%s) %s %.0e\n", ok ? "passed" : "failed", got, e,
         msg, ok ? "<=" : ">", CB_BLAS_SELFTEST_TOL);
  return !ok;
}

/* The self-test of core in a child process: its verdict line in out, and
 * whether it is definite (the child ran to a verdict or died of a signal;
 * a failed fork or exec is not cached). */
static int run_self_test(const char *core, char *out, size_t n, int *definite) {
  int fd[2];
  *definite = 0;
  if (pipe(fd)) {
    snprintf(out, n, "failed: no pipe for the self-test: %s", strerror(errno));
    return 1;
  }
  fflush(NULL);
  pid_t pid = fork();
  if (pid < 0) {
    snprintf(out, n, "failed: cannot fork the self-test: %s", strerror(errno));
    close(fd[0]);
    close(fd[1]);
    return 1;
  }
  if (pid == 0) {
    dup2(fd[1], STDOUT_FILENO);
    close(fd[0]);
    close(fd[1]);
    setenv("OPENBLAS_CORETYPE", core, 1);
    execl("/proc/self/exe", "blas-kernel", "--self-test", (char *)NULL);
    _exit(126);
  }
  close(fd[1]);
  char buf[512];
  size_t len = 0;
  for (ssize_t r;
       len + 1 < sizeof buf && ((r = read(fd[0], buf + len, sizeof buf - 1 - len)) > 0 || (r < 0 && errno == EINTR));)
    if (r > 0) len += (size_t)r;
  buf[len] = '\0';
  buf[strcspn(buf, "\n")] = '\0';
  close(fd[0]);
  int ws;
  while (waitpid(pid, &ws, 0) < 0 && errno == EINTR) {}
  if (WIFSIGNALED(ws)) {
    snprintf(out, n, "failed: the self-test of %s died of signal %d (%s)", core, WTERMSIG(ws), strsignal(WTERMSIG(ws)));
    *definite = 1;
    return 1;
  }
  int code = WIFEXITED(ws) ? WEXITSTATUS(ws) : -1;
  if ((code == 0 && !strncmp(buf, "passed", 6)) || (code == 1 && !strncmp(buf, "failed", 6))) {
    snprintf(out, n, "%s", buf);
    *definite = 1;
    return code;
  }
  snprintf(out, n, "failed: the self-test of %s exited with status %d", core, code);
  return 1;
}

static void cache_key(const char *core, char *key, size_t n) {
  char cpu[256], ver[64] = "OpenBLAS ?";
  cb_cpu_model(cpu, sizeof cpu);
  const char *cfg = openblas_get_config(); /* "OpenBLAS 0.3.21 ..." */
  const char *sp = strchr(cfg, ' ');
  if (sp) snprintf(ver, sizeof ver, "%.*s", (int)(strcspn(sp + 1, " ") + (size_t)(sp + 1 - cfg)), cfg);
  for (char *p = cpu; *p; p++)
    if (*p == '\t' || *p == '|') *p = ' ';
  char flags[256];
  cb_blas_cpu_flags(flags, sizeof flags);
  snprintf(key, n, "%s (%s) | %s | %s", cpu, flags, ver, core);
}

/* The cached verdict of key into out; 1 if found. */
static int cache_get(const char *path, const char *key, char *out, size_t n) {
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  char line[2048];
  size_t kl = strlen(key);
  int found = 0;
  while (fgets(line, sizeof line, f)) {
    line[strcspn(line, "\n")] = '\0';
    if (!strncmp(line, key, kl) && line[kl] == '\t' &&
        (!strncmp(line + kl + 1, "passed", 6) || !strncmp(line + kl + 1, "failed", 6))) {
      snprintf(out, n, "%s", line + kl + 1);
      found = 1;
    }
  }
  fclose(f);
  return found;
}

/* Replaces key's line (atomically: a temporary file renamed over the cache). */
static void cache_put(const char *path, const char *key, const char *verdict) {
  char tmp[4200], line[2048];
  snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
  FILE *out = fopen(tmp, "w");
  if (!out) {
    fprintf(stderr, "blas-kernel: cannot write the self-test cache %s: %s\n", tmp, strerror(errno));
    return;
  }
  FILE *in = fopen(path, "r");
  size_t kl = strlen(key);
  while (in && fgets(line, sizeof line, in))
    if (!(strncmp(line, key, kl) == 0 && line[kl] == '\t')) fputs(line, out);
  if (in) fclose(in);
  fprintf(out, "%s\t%s\n", key, verdict);
  if (fclose(out) || rename(tmp, path)) {
    fprintf(stderr, "blas-kernel: cannot write the self-test cache %s: %s\n", path, strerror(errno));
    remove(tmp);
  }
}

static void usage(FILE *f) {
  fputs("usage: blas-kernel [--cache FILE] [--] PROGRAM [ARG...]   run PROGRAM with the best safe OpenBLAS kernel\n"
        "       blas-kernel [--cache FILE] --show                  print the decision\n"
        "       blas-kernel --self-test                            test the running kernel\n",
        f);
}

int main(int argc, char **argv) {
  const char *cache = "build/blas-kernel.cache";
  int show = 0, i = 1;
  for (; i < argc; i++) {
    if (!strcmp(argv[i], "--self-test")) return self_test();
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
      usage(stdout);
      return 0;
    }
    if (!strcmp(argv[i], "--show")) show = 1;
    else if (!strcmp(argv[i], "--cache")) {
      if (++i == argc) {
        fputs("blas-kernel: --cache needs a file\n", stderr);
        return 2;
      }
      cache = argv[i];
    } else if (!strcmp(argv[i], "--")) {
      i++;
      break;
    } else if (argv[i][0] == '-') {
      fprintf(stderr, "blas-kernel: unknown option %s\n", argv[i]);
      usage(stderr);
      return 2;
    } else break;
  }
  if (!show && i == argc) {
    usage(stderr);
    return 2;
  }
  const char *env = getenv("OPENBLAS_CORETYPE");
  char flags[256], choice[1024] = "";
  cb_blas_cpu_flags(flags, sizeof flags);
  cb_blas_plan p;
  cb_blas_plan_make(env, cb_blas_detected_core(NULL), flags, &p);
  if (p.candidate) {
    char key[1024], verdict[600];
    cache_key(p.candidate, key, sizeof key);
    int failed, definite = 1;
    if (cache_get(cache, key, verdict, sizeof verdict)) failed = strncmp(verdict, "passed", 6) != 0;
    else {
      failed = run_self_test(p.candidate, verdict, sizeof verdict, &definite);
      if (definite) cache_put(cache, key, verdict);
    }
    snprintf(choice, sizeof choice, "%s %s; %s; self-test %s", failed ? "refused" : "chosen", p.candidate, p.why,
             verdict);
    if (!failed) setenv("OPENBLAS_CORETYPE", p.candidate, 1);
    setenv("CB_BLAS_CHOICE", choice, 1);
  } else unsetenv("CB_BLAS_CHOICE");
  if (show) {
    int inj = 0;
    const char *det = cb_blas_detected_core(&inj);
    if (p.candidate) printf("blas-kernel: %s\n", choice);
    else if (env && *env) printf("blas-kernel: %s (OpenBLAS runs %s)\n", p.why, openblas_get_corename());
    else printf("blas-kernel: %s detected%s; %s\n", det, inj ? " (CB_BLAS_TEST_CORENAME)" : "", p.why);
    return 0;
  }
  execvp(argv[i], argv + i);
  fprintf(stderr, "blas-kernel: cannot run %s: %s\n", argv[i], strerror(errno));
  return 127;
}
