/* tests/fuzz/fuzz_ply.c - libFuzzer target: ls_mesh_read on PLY files, ascii and binary
 * (see fuzz_mesh.h for the input layout and the invariants checked). */
#define FUZZ_MESH_FORMAT LS_MESH_FORMAT_PLY
#include "fuzz_mesh.h"
