/* tests/fuzz/fuzz_obj.c - libFuzzer target: ls_mesh_read on OBJ files
 * (see fuzz_mesh.h for the input layout and the invariants checked). */
#define FUZZ_MESH_FORMAT LS_MESH_FORMAT_OBJ
#include "fuzz_mesh.h"
