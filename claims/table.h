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
/* Value of a "# key: value" provenance line, or NULL. Static buffer. */
const char *cb_table_meta(const cb_table *t, const char *key);

#endif
