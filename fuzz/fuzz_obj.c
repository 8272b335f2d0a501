/* libFuzzer harness: the OBJ reader (cb_mesh_read_obj on a file holding the
 * input) and, on success, the topology of the mesh it returns. */
#include <stdint.h>
#include <stdlib.h>

#include <clothbench/mesh.h>
#include <clothbench/status.h>
#include <clothbench/topology.h>

#include "fuzz_input.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = cb_fuzz_input_file("obj", data, size);
  if (!path) return 0;
  cb_mesh m;
  int st = cb_mesh_read_obj(path, &m);
  if (st != CB_OK) {
    if (cb_error_message()[0] == '\0') abort(); /* every failure says why */
    return 0;
  }
  cb_topology t;
  if (cb_topology_build(&m, &t) == CB_OK) cb_topology_free(&t);
  cb_mesh_free(&m);
  return 0;
}
