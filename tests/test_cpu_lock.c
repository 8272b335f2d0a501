/* The CPU lock's turnstile (lib/io/experiment.c) under a conversion: an
 * experiment holding the lock shared (from cb_experiment_begin) converts it
 * to exclusive (cb_experiment_timed) while another process holds the
 * turnstile and waits for the lock exclusively, as a second timed
 * experiment that started at the same moment does. Before the fix the first
 * waited at the turnstile with its shared lock still held, and the two waited
 * for each other for ever. */
#include <criterion/criterion.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "experiment.h"

static char dir[] = "/tmp/cbcpulockXXXXXX";
static char lock[256], turn[256], out[256];

static void setup(void) {
  cr_assert_not_null(mkdtemp(dir));
  snprintf(lock, sizeof lock, "%s/cpu.lock", dir);
  snprintf(turn, sizeof turn, "%s/cpu.lock.turn", dir);
  snprintf(out, sizeof out, "%s/x.csv", dir);
  setenv("CB_CPU_LOCK", lock, 1);
  setenv("CB_QUIET", "1", 1);
}

static void teardown(void) {
  char cmd[300];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
}

TestSuite(cpu_lock, .init = setup, .fini = teardown, .timeout = 60);

Test(cpu_lock, converting_while_another_waits_in_the_turnstile_does_not_deadlock) {
  char *argv[] = {"test_cpu_lock", "--out", out, NULL};
  cb_experiment e;
  cr_assert_eq(cb_experiment_begin(&e, "test_cpu_lock", "", 3, argv), 0); /* holds the lock shared */
  int ready[2];
  cr_assert_eq(pipe(ready), 0);
  pid_t child = fork();
  cr_assert(child >= 0);
  if (child == 0) {   /* the second timed experiment: the turnstile, then the lock exclusively */
    close(e.lock_fd); /* the parent's lock lives on in an inherited descriptor: not this process's */
    if (e.turn_fd >= 0) close(e.turn_fd);
    int t = open(turn, O_RDWR | O_CREAT, 0666), l = open(lock, O_RDWR | O_CREAT, 0666);
    if (t < 0 || l < 0 || flock(t, LOCK_EX) != 0) _exit(2);
    if (write(ready[1], "x", 1) != 1) _exit(3);
    if (flock(l, LOCK_EX) != 0) _exit(4); /* waits for the parent's shared lock */
    flock(t, LOCK_UN);
    flock(l, LOCK_UN);
    _exit(0);
  }
  char c;
  cr_assert_eq(read(ready[0], &c, 1), 1);
  nanosleep(&(struct timespec){0, 100000000}, NULL); /* the child is (about to be) blocked on the lock */
  alarm(20);                                         /* a deadlock ends the test with SIGALRM: a crash, a failure */
  cb_experiment_timed(&e);
  alarm(0);
  int status = 0;
  cr_assert_eq(waitpid(child, &status, 0), child);
  cr_expect(WIFEXITED(status) && WEXITSTATUS(status) == 0, "the other process ended with %d", status);
  close(ready[0]);
  close(ready[1]);
}
