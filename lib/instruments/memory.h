/* Peak resident memory of a stretch of code, for the tables that quote a
 * method's memory beside its time (J4: each solver's peak at each size).
 *
 * Linux only: cb_mem_probe_begin returns the C heap's free pages to the
 * system (malloc_trim), resets the process's peak resident set (VmHWM) to
 * its current size by writing 5 to /proc/self/clear_refs, and records the
 * resident set then (VmRSS); cb_mem_probe_end reads VmHWM again. Their
 * difference is the most memory the stretch held at once beyond what was
 * resident before it: its factor, hierarchy, Krylov vectors and scratch.
 * Pages it touched and freed count at their peak, as they should. Never
 * inside a timed region: the reset walks the process's page tables. */
#ifndef CB_MEMORY_H
#define CB_MEMORY_H

typedef struct {
  double base_bytes; /* VmRSS at begin; NaN when the probe is not available */
} cb_mem_probe;

/* 0 on success; -1 (and base_bytes NaN) where /proc/self/clear_refs or
 * /proc/self/status cannot be used. */
int cb_mem_probe_begin(cb_mem_probe *m);
/* The peak since begin beyond begin's resident set, in bytes (>= 0), or NaN
 * when the probe was not available. */
double cb_mem_probe_end(const cb_mem_probe *m);

#endif
