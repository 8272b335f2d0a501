/* Peak resident memory of a stretch of code (memory.h). */
#include "memory.h"

#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* The value of "<key>:" in /proc/self/status, in bytes (the file gives kB), or NaN. */
static double status_bytes(const char *key) {
  FILE *f = fopen("/proc/self/status", "r");
  if (!f) return NAN;
  char line[256];
  size_t n = strlen(key);
  double v = NAN;
  while (fgets(line, sizeof line, f))
    if (strncmp(line, key, n) == 0 && line[n] == ':') {
      double kb;
      if (sscanf(line + n + 1, "%lf", &kb) == 1) v = kb * 1024.0;
      break;
    }
  fclose(f);
  return v;
}

int cb_mem_probe_begin(cb_mem_probe *m) {
  m->base_bytes = NAN;
  malloc_trim(0);
  FILE *f = fopen("/proc/self/clear_refs", "w");
  if (!f) return -1;
  int ok = fputs("5", f) >= 0;
  if (fclose(f) != 0 || !ok) return -1;
  m->base_bytes = status_bytes("VmRSS");
  return isnan(m->base_bytes) ? -1 : 0;
}

double cb_mem_probe_end(const cb_mem_probe *m) {
  if (isnan(m->base_bytes)) return NAN;
  double hwm = status_bytes("VmHWM");
  return isnan(hwm) ? NAN : fmax(hwm - m->base_bytes, 0.0);
}
