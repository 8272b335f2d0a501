/* Progress of long runs on stderr: cells done out of the total, elapsed and
 * estimated remaining time. On a terminal the line is redrawn in place (at
 * most 5 times a second); otherwise a line is printed every 15 s. Data never
 * goes here: it goes to CSV. CB_QUIET=1 in the environment silences it.
 *
 * The estimate: with cost hints (cb_progress_start_cost, cb_progress_advance)
 * it is the measured time per unit of cost of the completed cells times the
 * cost still to run, minus the time already spent on the running cell; without
 * them, elapsed time per completed cell times the cells left. */
#ifndef CB_PROGRESS_H
#define CB_PROGRESS_H

typedef struct cb_progress {
  char label[64];
  long total, done;
  double t0, last;
  double cost_total, cost_done, t_done; /* cost hints; t_done: when the last cell completed */
  int tty, quiet, printed;
} cb_progress;

void cb_progress_start(cb_progress *p, const char *label, long total);
void cb_progress_update(cb_progress *p, long done);
void cb_progress_end(cb_progress *p);

/* total cells whose relative costs add up to cost_total (> 0) */
void cb_progress_start_cost(cb_progress *p, const char *label, long total, double cost_total);
/* one more cell done, of relative cost `cost` */
void cb_progress_advance(cb_progress *p, double cost);

#endif
