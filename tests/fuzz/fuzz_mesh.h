/* tests/fuzz/fuzz_mesh.h - the mesh-reader harness, included by fuzz_obj.c,
 * fuzz_ply.c and fuzz_off.c with FUZZ_MESH_FORMAT set to their format.
 *
 * Input: one selector byte (fuzz_common.h), then the file. Checks, besides
 * the common invariants: ls_mesh_read fails with the same status as
 * ls_mesh_read_info when that fails; with an arena of the answer of
 * ls_mesh_read_bytes it does not fail with LS_ERR_NOMEM and takes exactly
 * that many bytes; with less it does not succeed. On success the counts are
 * those of the first pass, every index is below the vertex count and every
 * coordinate is finite.
 */
#ifndef LS_FUZZ_MESH_H
#define LS_FUZZ_MESH_H

#include "fuzz_common.h"

/* The mesh read, split at its creases (the angle from the selector): within
 * its sizing answer it succeeds and stays there; in less it succeeds within
 * the arena or runs out and leaves it as it was; the result has the input's
 * faces, each corner where the input's was, and its indices in range. */
static void fuzz_split_creases(const ls_mesh *mesh, uint8_t selector)
{
    fuzz_arena fs;
    ls_mesh out, before;
    ls_diag diag;
    ls_status st;
    size_t need = 0, c;
    const ls_real crease_cos = (ls_real)((double)(selector % 65u) / 32.0 - 1.0);
    if (ls_mesh_split_creases_bytes(mesh->vertex_count, mesh->face_count, &need) != LS_OK) return;
    fuzz_arena_open(&fs, selector, need);
    memset(&out, 0x5A, sizeof out);
    before = out;
    ls_diag_clear(&diag);
    st = ls_mesh_split_creases(mesh, crease_cos, &fs.arena, &out, &diag);
    FUZZ_ASSERT(st == LS_OK || (st == LS_ERR_NOMEM && !fs.enough));
    if (st != LS_OK) {
        fuzz_check_failure(st, &diag, &fs, &out, &before, sizeof out);
    } else {
        FUZZ_ASSERT(fuzz_arena_peak(&fs) <= need);
        FUZZ_ASSERT(out.face_count == mesh->face_count);
        FUZZ_ASSERT(out.vertex_count >= mesh->vertex_count);
        FUZZ_ASSERT((size_t)out.vertex_count <= (size_t)mesh->vertex_count + 3u * (size_t)mesh->face_count);
        for (c = 0; c < 3u * (size_t)out.face_count; c++) {
            FUZZ_ASSERT(out.triangles[c] < out.vertex_count);
            FUZZ_ASSERT(memcmp(out.positions + 3u * (size_t)out.triangles[c], mesh->positions + 3u * (size_t)mesh->triangles[c],
                               3u * sizeof(ls_real)) == 0);
        }
    }
    fuzz_arena_close(&fs);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    ls_mesh_file_info info;
    ls_mesh mesh, before;
    ls_diag diag, info_diag;
    ls_status info_st, st;
    fuzz_arena fa;
    size_t need = 0, i;
    uint8_t selector;
    if (size < 1) return 0;
    selector = data[0];
    data++;
    size--;
    (void)ls_mesh_format_guess(data, size);
    ls_diag_clear(&info_diag);
    memset(&info, 0x5A, sizeof info);
    info_st = ls_mesh_read_info(data, size, FUZZ_MESH_FORMAT, &info, &info_diag);
    FUZZ_ASSERT(info_st >= LS_OK && info_st < LS_STATUS_COUNT);
    FUZZ_ASSERT(info_st != LS_ERR_NOMEM);
    if (info_st == LS_OK) {
        FUZZ_ASSERT(info.format == FUZZ_MESH_FORMAT);
        FUZZ_ASSERT(info.vertex_count > 0 && info.face_count > 0);
        FUZZ_ASSERT(info.polygon_count > 0 && info.polygon_count <= info.face_count);
        if (ls_mesh_read_bytes(&info, &need) != LS_OK) need = FUZZ_ARENA_CAP + 1u;
    } else {
        FUZZ_ASSERT(info_diag.what != NULL && info_diag.what[0] != '\0' && info_diag.status == info_st);
    }
    fuzz_arena_open(&fa, selector, need);
    memset(&mesh, 0x5A, sizeof mesh);
    before = mesh;
    ls_diag_clear(&diag);
    st = ls_mesh_read(data, size, FUZZ_MESH_FORMAT, &fa.arena, &mesh, &diag);
    fuzz_check_status(info_st, st, &fa, 1);
    if (st != LS_OK) {
        fuzz_check_failure(st, &diag, &fa, &mesh, &before, sizeof mesh);
    } else {
        FUZZ_ASSERT(fuzz_arena_peak(&fa) == need);
        FUZZ_ASSERT(mesh.vertex_count == info.vertex_count && mesh.face_count == info.face_count);
        for (i = 0; i < (size_t)mesh.face_count * 3u; i++) FUZZ_ASSERT(mesh.triangles[i] < mesh.vertex_count);
        for (i = 0; i < (size_t)mesh.vertex_count * 3u; i++) FUZZ_ASSERT(fuzz_finite_real(mesh.positions[i]));
        fuzz_split_creases(&mesh, selector);
    }
    fuzz_arena_close(&fa);
    return 0;
}

#endif /* LS_FUZZ_MESH_H */
