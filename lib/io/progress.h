/* Progress of long runs on stderr: cells done out of the total, elapsed and
 * estimated remaining time. On a terminal the line is redrawn in place (at
 * most 5 times a second); otherwise a line is printed every 15 s. Data never
 * goes here: it goes to CSV. CB_QUIET=1 in the environment silences it. */
#ifndef CB_PROGRESS_H
#define CB_PROGRESS_H

typedef struct cb_progress {
  char label[64];
  long total, done;
  double t0, last;
  int tty, quiet, printed;
} cb_progress;

void cb_progress_start(cb_progress *p, const char *label, long total);
void cb_progress_update(cb_progress *p, long done);
void cb_progress_end(cb_progress *p);

#endif
