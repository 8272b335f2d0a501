/* How many threads actually ran: a measurement, beside the thread knob of
 * lib/io/threads.h that sets how many may.
 *
 * cb_threads_count_during() runs a function and counts this process's
 * threads whose CPU time grew meanwhile (per-thread CPU clocks of every task
 * in /proc/self/task). The two probes time a fixed workload of each library
 * that starts threads (OpenBLAS's pool, CHOLMOD's OpenMP regions) and count
 * the threads that ran in it, the fewest of 3 repetitions after a warm-up. */
#ifndef CB_THREAD_PROBE_H
#define CB_THREAD_PROBE_H

/* Runs fn(ctx) and returns how many threads of this process consumed CPU
 * time while it ran (the caller included), or a negative status when
 * /proc/self/task cannot be read. */
int cb_threads_count_during(void (*fn)(void *), void *ctx);

/* Threads that ran during a CHOLMOD supernodal factorisation of a 2D
 * Laplacian on a 96 x 96 grid (its Map clear and supernode loops open OpenMP
 * regions), and during a 384 x 384 dgemm; < 0 when it could not be
 * measured. A few ms each. */
int cb_thread_probe_cholmod(void);
int cb_thread_probe_dgemm(void);

#endif
