/* Writing CSV rows by one convention (README.md, section "CSV convention";
 * the column names' unit suffixes are listed in docs/csv_columns.txt). It is
 * I/O, above the core and the instruments: the simulation does not depend on
 * how it is written. The convention:
 *   - a value that does not apply, or was not measured, is the empty field;
 *   - a value that was computed and is not finite is `nan`, `inf` or `-inf`,
 *     spelled exactly so (never `-nan`, whatever the NaN's sign bit);
 *   - every other number is written as its conversion asks (`%.17g` for
 *     doubles, the habit of every clothbench CSV).
 *
 * cb_csv_printf is fprintf for CSV rows: the same format strings (checked by
 * the compiler), except that a floating conversion (f F e E g G a A) of a
 * NaN writes `nan`, of an infinity `inf` or `-inf`, and of cb_csv_na()
 * nothing at all. So a writer marks a field "not applicable" by passing
 * cb_csv_na() for it (`measured ? x : cb_csv_na()`), and a computed NaN can
 * never come out as `-nan` or as an empty field.
 *
 * cb_csv_na() is a quiet NaN with a payload of its own (the trick of R's
 * NA_real_). Pass it straight to cb_csv_printf, or keep it in a variable
 * that is only copied; do not compute with it (whether arithmetic keeps a
 * NaN's payload depends on the machine). Integers have no NaN: write a count
 * that may not apply as a double, `n < 0 ? cb_csv_na() : (double)n` with
 * `%.17g` (exact below 2^53). */
#ifndef CB_CSV_H
#define CB_CSV_H

#include <stdarg.h>
#include <stdio.h>

#include <clothbench/run.h>

#include "stats.h"

/* The "not applicable / not measured" value: written as the empty field. */
double cb_csv_na(void);
/* Whether v is cb_csv_na() (of either sign). An ordinary NaN is not. */
int cb_csv_is_na(double v);
/* cb_csv_na() if v is NaN, else v: for a value whose NaN means "not
 * computed" by its own documented contract (e.g. spd_probe's witnesses that
 * did not run, a convergence rate of fewer than two iterations). */
double cb_csv_na_if_nan(double v);

/* fprintf with the convention above. Supports the conversions d i u o x X
 * c s p f F e E g G a A and %% with any flags, width, precision (also `*`)
 * and length modifier (hh h l ll j z t L); %n is refused. Returns the number
 * of bytes written, or a negative value on a write error or a refused
 * conversion. */
int cb_csv_printf(FILE *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
int cb_csv_vprintf(FILE *f, const char *fmt, va_list ap) __attribute__((format(printf, 2, 0)));

/* CSV fields "median,min,max" of the repeats times scale, each %.6f (three
 * empty fields when t has none; stats.h names the columns). */
void cb_timing_csv(FILE *f, const cb_timing *t, double scale);
/* The field "r1;r2;...": every repeat times scale, %.6f, in order
 * (cb_timing_parse reads it back). */
void cb_timing_csv_each(FILE *f, const cb_timing *t, double scale);
/* "median,min,max,each,repeats" of a timing (t NULL: not timed, every field empty). */
void cb_timing_csv_repeats(FILE *f, const cb_timing *t);

/* Per-step CSV: the header row and one row of the current state. Energy
 * columns: kinetic_j, elastic_j (the terms with a Hessian: springs,
 * bending), gravity_j (the gravity potential), total_j = their sum, and
 * pin_work_j (the driven pins' work so far; 0 without them). */
void cb_run_csv_header(FILE *f);
void cb_run_csv_row(FILE *f, const cb_run *r, int status);
/* The same with more columns at the end of each line: extra (NULL: none) is
 * the header's further names or the row's further cells, without a leading comma. */
void cb_run_csv_header_extra(FILE *f, const char *extra);
void cb_run_csv_row_extra(FILE *f, const cb_run *r, int status, const char *extra);

#endif
