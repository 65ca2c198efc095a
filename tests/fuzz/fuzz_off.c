/* tests/fuzz/fuzz_off.c - libFuzzer target: ls_mesh_read on OFF files
 * (see fuzz_mesh.h for the input layout and the invariants checked). */
#define FUZZ_MESH_FORMAT LS_MESH_FORMAT_OFF
#include "fuzz_mesh.h"
