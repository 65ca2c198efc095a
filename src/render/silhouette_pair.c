/* silhouette_pair.c - the pair mode: nvdiffrast-style antialiasing of neighbouring pixels, deterministic */
#include "silhouette_internal.h"

/* ---- the pair mode (nvdiffrast-style antialiasing, deterministic) ---- */

typedef struct pctx {
    const ls_vis *vis;
    const ls_edge_table *table;
    const uint32_t *indices;
    uint32_t triangle_count;
} pctx;

/* One pair of neighbouring pixels p0 -> p1 (right or down) whose triangle
 * ids differ: the silhouette edge of the owner crossing the segment between
 * their centres, at c (pixel units from the owner's centre, towards the
 * neighbour when ds = 1). */
typedef struct pitem {
    size_t p0, p1, q;
    uint32_t va, vb;    /* the edge's vertices */
    ls_real x1, y1, x2, y2, c, ds, alpha; /* frame: owner's centre, x along the pair */
    int vertical, clamped;
} pitem;

static int pair_item(const pctx *pc, size_t p0, size_t p1, int vertical, pitem *it)
{
    const ls_vis *vis = pc->vis;
    uint32_t id0 = vis->tri[p0], id1 = vis->tri[p1], own, k, best = 3u;
    size_t po;
    ls_real x[3], y[3], cx, cy, bc = (ls_real)0, dc, hw = (ls_real)vis->width * (ls_real)0.5;
    ls_real hh = (ls_real)vis->height * (ls_real)0.5;
    const uint32_t *f;
    if (id0 == id1) return 0;
    if (id0 > pc->triangle_count || id1 > pc->triangle_count) return 0;
    if (id0 == 0 || (id1 != 0 && vis->depth[p1] < vis->depth[p0])) {
        own = id1 - 1u;
        po = p1;
        it->ds = (ls_real)-1;
    } else {
        own = id0 - 1u;
        po = p0;
        it->ds = (ls_real)1;
    }
    f = pc->indices + 3 * (size_t)own;
    {
        size_t row = po / vis->width; /* the pixel's row and column */
        cx = (ls_real)(po - row * vis->width) + (ls_real)0.5;
        cy = (ls_real)row + (ls_real)0.5;
    }
    for (k = 0; k < 3; k++) {
        const ls_real *cl = vis->clip + 4 * (size_t)f[k];
        ls_real wx, wy;
        if (!(cl[2] + cl[3] >= (ls_real)0) || !(cl[3] > (ls_real)0)) return 0; /* near-clipped: skipped */
        wx = (cl[0] / cl[3] + (ls_real)1) * hw - cx;
        wy = ((ls_real)1 - cl[1] / cl[3]) * hh - cy;
        x[k] = vertical ? wy : wx;
        y[k] = vertical ? wx : wy;
    }
    for (k = 0; k < 3; k++) { /* the crossing farthest towards the neighbour */
        uint32_t k1 = (k + 1u) % 3u;
        ls_real d = y[k1] - y[k], cc;
        if ((y[k] >= (ls_real)0) == (y[k1] >= (ls_real)0) || d == (ls_real)0) continue;
        cc = (x[k] * y[k1] - x[k1] * y[k]) / d;
        if (best == 3u || it->ds * cc > it->ds * bc) {
            best = k;
            bc = cc;
        }
    }
    if (best == 3u) return 0;
    {
        uint32_t k1 = (best + 1u) % 3u, h = 3u * own + best, tw = pc->table->twin[h];
        ls_real dx = x[k1] - x[best], dy = y[k1] - y[best];
        const ls_real *A = vis->clip + 4 * (size_t)f[best], *B = vis->clip + 4 * (size_t)f[k1];
        if (r_abs(dy) < r_abs(dx)) return 0; /* flatter than 45 degrees to the pair */
        if (tw != LS_EDGE_NONE) {             /* the neighbour face folds behind: a silhouette */
            const uint32_t *g = pc->indices + 3 * (size_t)(tw / 3u);
            ls_real sc_ = hdet(A, B, vis->clip + 4 * (size_t)f[(best + 2u) % 3u]);
            ls_real sd_ = hdet(A, B, vis->clip + 4 * (size_t)g[(tw % 3u + 2u) % 3u]);
            if (!((sc_ > (ls_real)0 && sd_ > (ls_real)0) || (sc_ < (ls_real)0 && sd_ < (ls_real)0))) return 0;
        }
        it->va = f[best];
        it->vb = f[k1];
        it->x1 = x[best];
        it->y1 = y[best];
        it->x2 = x[k1];
        it->y2 = y[k1];
    }
    dc = it->ds * bc;
    if (!(dc > (ls_real)-0.0625 && dc < (ls_real)1.0625)) return 0;
    it->clamped = dc < (ls_real)0 || dc > (ls_real)1;
    dc = dc < (ls_real)0 ? (ls_real)0 : (dc > (ls_real)1 ? (ls_real)1 : dc);
    it->c = bc;
    it->alpha = it->ds * ((ls_real)0.5 - dc);
    it->p0 = p0;
    it->p1 = p1;
    it->vertical = vertical;
    return 1;
}

/* The next blending pair from cursor *k (2 pixel + direction, image
 * order); 0 when there is none left. it->q is the pixel it modifies. */
static int pair_next(const pctx *pc, size_t *k, pitem *it)
{
    const ls_vis *vis = pc->vis;
    size_t n = 2 * (size_t)vis->width * vis->height;
    if (vis->width == 0) return 0;
    while (*k < n) {
        size_t p0 = *k >> 1, row = p0 / vis->width, col = p0 - row * vis->width;
        int dir = (int)(*k & 1u);
        (*k)++;
        if (dir == 0 ? col + 1u >= vis->width : row + 1u >= vis->height) continue;
        if (pair_item(pc, p0, dir == 0 ? p0 + 1u : p0 + vis->width, dir, it)) {
            it->q = it->alpha > (ls_real)0 ? it->p0 : it->p1;
            return 1;
        }
    }
    return 0;
}

static ls_status pair_check(pctx *pc, const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                            uint32_t triangle_count, ls_diag *diag)
{
    if (vis == NULL) return ls_invalid_arg(diag, "view->vis is NULL");
    if (table == NULL) return ls_invalid_arg(diag, "view->table is NULL");
    if (triangle_count > 0 && indices == NULL)
        return ls_invalid_arg(diag, "view->indices is NULL with triangle_count > 0");
    if (vis->tri == NULL || vis->clip == NULL || table->magic != EDGE_TABLE_MAGIC) return LS_ERR_STATE;
    if (vis->ss != 1u) return ls_invalid_arg(diag, "view->vis->ss: allowed 1 (one sample per pixel)");
    if (vis->triangle_count != triangle_count)
        return ls_invalid_arg(diag, "view->triangle_count: allowed = view->vis->triangle_count");
    if (table->triangle_count != triangle_count || table->vertex_count != vis->vertex_count)
        return ls_invalid_arg(diag, "view->table: triangle_count and vertex_count allowed = view->vis's");
    pc->vis = vis;
    pc->table = table;
    pc->indices = indices;
    pc->triangle_count = triangle_count;
    return ls_check_triangle_indices(indices, triangle_count, vis->vertex_count, diag);
}

static ls_status pair_forward_impl(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                                   uint32_t triangle_count, const ls_real *image_in, ls_real *image_out, ls_diag *diag)
{
    ls_diag_clear(diag);
    pctx pc;
    size_t n, p, k = 0;
    pitem it;
    ls_status st = pair_check(&pc, vis, table, indices, triangle_count, diag);
    if (st != LS_OK) return st;
    if (image_in == NULL) return ls_invalid_arg(diag, "image_in is NULL");
    if (image_out == NULL) return ls_invalid_arg(diag, "image_out is NULL");
    if (image_in == image_out) return ls_invalid_arg(diag, "image_out: allowed != image_in (no in place)");
    n = 4 * (size_t)vis->width * vis->height;
    for (p = 0; p < n; p++) image_out[p] = image_in[p];
    while (pair_next(&pc, &k, &it)) {
        int c;
        for (c = 0; c < 4; c++)
            image_out[4 * it.q + (size_t)c] += it.alpha * (image_in[4 * it.p1 + (size_t)c] - image_in[4 * it.p0 + (size_t)c]);
    }
    return LS_OK;
}

ls_status ls_pair_forward(const ls_view *view, const ls_real *image_in, ls_real *image_out, ls_diag *diag)
{
    ls_diag_clear(diag);
    if (view == NULL) return ls_invalid_arg(diag, "view is NULL");
    return pair_forward_impl(view->vis, view->table, view->indices, view->triangle_count, image_in, image_out, diag);
}

static ls_status pair_backward_impl(const ls_vis *vis, const ls_edge_table *table, const uint32_t *indices,
                                    uint32_t triangle_count, const ls_real mvp[16], ls_real boost, const ls_real *image_in,
                                    const ls_real *grad_out, ls_real *grad_in, ls_real *grad_positions, ls_diag *diag)
{
    ls_diag_clear(diag);
    pctx pc;
    sctx sc;
    size_t k = 0;
    pitem it;
    ls_status st = pair_check(&pc, vis, table, indices, triangle_count, diag);
    if (st != LS_OK) return st;
    if (mvp == NULL) return ls_invalid_arg(diag, "view->mvp is NULL");
    if (image_in == NULL) return ls_invalid_arg(diag, "image_in is NULL");
    if (grad_out == NULL) return ls_invalid_arg(diag, "grad_out is NULL");
    if (grad_positions == NULL) return ls_invalid_arg(diag, "grad_positions is NULL");
    if (grad_in == grad_out) return ls_invalid_arg(diag, "grad_in: allowed != grad_out (no in place)");
    ls_sil_sctx_init(&sc, vis, indices, triangle_count);
    sc.m = mvp;
    if (grad_in != NULL) {
        size_t p, n = 4 * (size_t)vis->width * vis->height;
        for (p = 0; p < n; p++) grad_in[p] += grad_out[p];
    }
    while (pair_next(&pc, &k, &it)) {
        ls_real dd = (ls_real)0, gc, gx1, gy1, gx2, gy2, D, g4[4];
        int c;
        for (c = 0; c < 4; c++) {
            ls_real g = grad_out[4 * it.q + (size_t)c];
            dd += g * (image_in[4 * it.p1 + (size_t)c] - image_in[4 * it.p0 + (size_t)c]);
            if (grad_in != NULL) {
                grad_in[4 * it.p0 + (size_t)c] -= it.alpha * g;
                grad_in[4 * it.p1 + (size_t)c] += it.alpha * g;
            }
        }
        if (it.clamped) continue;
        /* alpha = ds / 2 - c: dL/dc = -dd; c = (x1 y2 - x2 y1) / (y2 - y1) */
        gc = -dd * boost;
        D = it.y2 - it.y1;
        gx1 = gc * it.y2 / D;
        gx2 = -(gc * it.y1 / D);
        gy1 = gc * (it.c - it.x2) / D;
        gy2 = gc * (it.x1 - it.c) / D;
        ls_sil_window_to_clip(&sc, vis->clip + 4 * (size_t)it.va, it.vertical ? gy1 : gx1, it.vertical ? gx1 : gy1, g4);
        ls_sil_clip_to_positions(&sc, it.va, g4, grad_positions);
        ls_sil_window_to_clip(&sc, vis->clip + 4 * (size_t)it.vb, it.vertical ? gy2 : gx2, it.vertical ? gx2 : gy2, g4);
        ls_sil_clip_to_positions(&sc, it.vb, g4, grad_positions);
    }
    return LS_OK;
}

ls_status ls_pair_backward(const ls_view *view, const ls_real *image_in, const ls_real *grad_out, ls_real *grad_in,
                           ls_real *grad_positions, ls_diag *diag)
{
    ls_diag_clear(diag);
    if (view == NULL) return ls_invalid_arg(diag, "view is NULL");
    return pair_backward_impl(view->vis, view->table, view->indices, view->triangle_count, view->mvp, view->boost, image_in,
                            grad_out, grad_in, grad_positions, diag);
}
