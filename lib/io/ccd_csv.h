/* Reading CCD query files in the format of Wang et al. 2021's CCD benchmark
 * (docs/geometry-ccd.md): 8 CSV rows a query, one per point,
 *   x_num,x_den,y_num,y_den,z_num,z_den,truth
 * integer numerators and denominators of any size (GMP), rows 1-4 the points
 * at t = 0 and rows 5-8 at t = 1, truth 0 or 1 (the same on the 8 rows).
 * Each rational becomes the interval between the two doubles around it (one
 * double when it is one exactly), so the CCD's guarantee holds for the exact
 * rational query. */
#ifndef CB_CCD_CSV_H
#define CB_CCD_CSV_H

#include <stdio.h>

#include <clothbench/ccd.h>

typedef struct cb_ccd_file {
  int n;           /* queries */
  cb_ccd_query *q; /* n queries */
  int *truth;      /* n truths (0/1) */
  long inexact;    /* coordinates that are no double (given as an interval of two neighbours) */
} cb_ccd_file;

/* Reads a file (name is used in messages). CB_EINVAL with "name:line:column: what" in cb_error_message() on
 * malformed input (not an integer, zero denominator, NaN/inf text, a value beyond 2^500, a row without 7
 * fields, a truth other than 0/1 or differing within a query, a file ending inside a query); CB_EIO when it
 * cannot be read; CB_ENOMEM. On error *out holds nothing to free. */
int cb_ccd_file_read(FILE *f, const char *name, cb_ccd_file *out);
int cb_ccd_file_load(const char *path, cb_ccd_file *out);
void cb_ccd_file_free(cb_ccd_file *file);

#endif
