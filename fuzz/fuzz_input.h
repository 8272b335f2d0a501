/* The fuzz harnesses' input file: the library reads configs and meshes from
 * paths, so each input is written to one file per process (and kind) and
 * read back from there. */
#ifndef CB_FUZZ_INPUT_H
#define CB_FUZZ_INPUT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static char cb_fuzz_path[512];
static inline void cb_fuzz_remove_input(void) { remove(cb_fuzz_path); }

/* Writes data to ${TMPDIR:-/tmp}/cbfuzz.<pid>.<ext> and returns that path
 * (static storage, removed at exit), or NULL if it cannot be written. */
static inline const char *cb_fuzz_input_file(const char *ext, const uint8_t *data, size_t size) {
  char *path = cb_fuzz_path;
  if (!path[0]) {
    const char *dir = getenv("TMPDIR");
    snprintf(path, sizeof cb_fuzz_path, "%s/cbfuzz.%ld.%s", dir && dir[0] ? dir : "/tmp", (long)getpid(), ext);
    atexit(cb_fuzz_remove_input);
  }
  FILE *f = fopen(path, "wb");
  if (!f) return NULL;
  size_t w = fwrite(data, 1, size, f);
  if (fclose(f) != 0 || w != size) return NULL;
  return path;
}

#endif
