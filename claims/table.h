/* A CSV file as written by clothbench: '#' provenance lines, one header row,
 * then rows of plain fields (no quoting; fields never contain commas). */
#ifndef CB_TABLE_H
#define CB_TABLE_H

typedef struct cb_table {
  int ncols, nrows;
  char **cols;  /* ncols header names */
  char **cells; /* nrows * ncols fields, row-major */
  char *meta;   /* the '#' lines, newline-separated */
} cb_table;

/* Returns CB_EIO if the file is missing, CB_EINVAL if malformed. */
int cb_table_read(const char *path, cb_table *t);
void cb_table_free(cb_table *t);

int cb_table_col(const cb_table *t, const char *name);         /* -1 if absent */
const char *cb_table_str(const cb_table *t, int row, int col); /* "" if out of range */
double cb_table_num(const cb_table *t, int row, int col);      /* NAN if empty or not a number */
/* A count or index from a CSV as an int: -1 unless the cell is a finite
 * number within +-CB_TABLE_INT_MAX (1e9, so that the sum or difference of two
 * fits an int), never an undefined conversion of nan, 1e20 or 3e9. */
enum { CB_TABLE_INT_MAX = 1000000000 };
int cb_table_int(const cb_table *t, int row, int col);
int cb_table_int_of(double v); /* the same rule on a number read otherwise */
/* Value of a "# key: value" provenance line, or NULL. Static buffer. */
const char *cb_table_meta(const cb_table *t, const char *key);

#endif
