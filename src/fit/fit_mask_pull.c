/* fit_mask_pull.c - config.mask_pull: every vertex is pulled into the
 * targets' masks.
 *
 * The silhouette gradient moves only the edges of a render's outline. A part
 * that covers pixels the target leaves empty inside its outline - the web
 * between two legs grown from one sphere, seen face-on - has no gradient in
 * its interior and recedes only from its border, a pixel at a time. Every
 * point of the target's surface projects into the target's mask in every
 * view, so a vertex that projects outside a mask is outside the target's
 * visual hull: the term pulls it back along the mask's distance field,
 *
 *     E = w / (B n) sum over the batch's B views and the n vertices of
 *         max(0, d(v, i) - margin)^2,
 *
 * d the distance in pixels from the vertex's projection to the nearest pixel
 * the target covers (alpha > 0), bilinear between pixel centres, margin one
 * pixel (a vertex on the true surface projects into a covered pixel, at most
 * half a pixel from a covered centre). Vertices behind the camera or outside
 * the image are not pulled. The distance fields are exact Euclidean distance
 * transforms of the targets' masks (mask.c), made when the fit is built. */
#include <largesteps/math.h>
#include "fit_internal.h"
#include "../base/parallel.h"
#include "../render/mask_internal.h"

void ls_fit_impl_mask_sizes(const ls_fit_config *c, uint32_t views, size_t *reals, size_t *indices)
{
    const size_t side = c->width > c->height ? c->width : c->height;
    *reals = *indices = 0;
    if (!(c->mask_pull > (ls_real)0)) return;
    *reals = (size_t)views * c->width * c->height + 3u * (side + 1u); /* the fields; a line's f, d, z */
    *indices = side + 1u;                                             /* a line's v */
}

void ls_fit_impl_mask_init(ls_fit *fit)
{
    const uint32_t w = fit->config.width, h = fit->config.height;
    uint32_t view;
    if (fit->mask_dist == NULL) return;
    for (view = 0; view < fit->views.count; view++) {
        const ls_real *t = fit->views.targets[view];
        ls_real *g = fit->mask_dist + (size_t)view * w * h;
        size_t covered = 0, i;
        for (i = 0; i < (size_t)w * h; i++) covered += t[4u * i + 3u] > (ls_real)0;
        if (covered == 0) { /* an empty mask says nothing about where the object is: no pull */
            memset(g, 0, (size_t)w * h * sizeof(ls_real));
            continue;
        }
        ls_mask_impl_distance(t, w, h, (ls_real)0, 0u, g, fit->mask_dist + (size_t)fit->views.count * w * h,
                              fit->mask_index);
    }
}

/* The term of one view on vertices [lo, hi): its value, and its gradient
 * added to gx. */
static ls_real pull_view(ls_fit *fit, uint32_t view, uint32_t lo, uint32_t hi, ls_real scale)
{
    const uint32_t w = fit->config.width, h = fit->config.height;
    const ls_real *m = fit->mvp + 16u * (size_t)view, *g = fit->mask_dist + (size_t)view * w * h;
    const ls_real margin = (ls_real)1, hw = (ls_real)0.5 * (ls_real)w, hh = (ls_real)0.5 * (ls_real)h;
    ls_real sum = (ls_real)0;
    uint32_t i, k;
    for (i = lo; i < hi; i++) {
        const ls_real *p = fit->xr + 3u * (size_t)i;
        const ls_real cx = ((m[0] * p[0] + m[1] * p[1]) + m[2] * p[2]) + m[3];
        const ls_real cy = ((m[4] * p[0] + m[5] * p[1]) + m[6] * p[2]) + m[7];
        const ls_real cw = ((m[12] * p[0] + m[13] * p[1]) + m[14] * p[2]) + m[15];
        ls_real fx, fy, tx, ty, d, e, gd, gfx, gfy, gX, gY, gW;
        uint32_t ix, iy;
        size_t at;
        if (!(cw > (ls_real)0)) continue;
        fx = (cx / cw + (ls_real)1) * hw - (ls_real)0.5; /* pixel centres at integers */
        fy = ((ls_real)1 - cy / cw) * hh - (ls_real)0.5;
        if (!(fx >= (ls_real)0 && fy >= (ls_real)0 && fx < (ls_real)(w - 1u) && fy < (ls_real)(h - 1u))) continue;
        ix = (uint32_t)fx;
        iy = (uint32_t)fy;
        tx = fx - (ls_real)ix;
        ty = fy - (ls_real)iy;
        at = (size_t)iy * w + ix;
        d = ((ls_real)1 - ty) * (((ls_real)1 - tx) * g[at] + tx * g[at + 1u]) +
            ty * (((ls_real)1 - tx) * g[at + w] + tx * g[at + w + 1u]);
        if (!(d > margin)) continue;
        e = d - margin;
        sum += e * e;
        gd = (ls_real)2 * e * scale;
        gfx = gd * (((ls_real)1 - ty) * (g[at + 1u] - g[at]) + ty * (g[at + w + 1u] - g[at + w]));
        gfy = gd * (((ls_real)1 - tx) * (g[at + w] - g[at]) + tx * (g[at + w + 1u] - g[at + 1u]));
        /* fx = (X / W + 1) w / 2 - 1/2, fy = (1 - Y / W) h / 2 - 1/2 */
        gX = gfx * hw / cw;
        gY = -gfy * hh / cw;
        gW = -(gX * cx + gY * cy) / cw;
        for (k = 0; k < 3; k++) fit->gx[3u * (size_t)i + k] += (gX * m[k] + gY * m[4 + k]) + gW * m[12 + k];
    }
    return sum;
}

/* A block of vertices for every view of the batch, in view order: each
 * vertex's gradient gathers its views' terms in the order one worker would. */
static void pull_task(void *arg, uint32_t part, uint32_t worker)
{
    struct ls_fit_pass *p = (struct ls_fit_pass *)arg;
    ls_fit *fit = p->fit;
    const ls_fit_config *c = &fit->config;
    const uint32_t count = fit->views.count, batch = fit_batch(c, count);
    const uint64_t n = fit->vertex_count;
    const uint32_t lo = (uint32_t)(n * part / LS_FIT_MASK_PARTS), hi = (uint32_t)(n * (part + 1u) / LS_FIT_MASK_PARTS);
    ls_real sum = (ls_real)0;
    uint32_t j;
    (void)worker;
    for (j = 0; j < batch; j++) sum += pull_view(fit, ls_fit_view_of(c, count, fit->iteration, j), lo, hi, p->mask_scale);
    p->mask_sums[part] = sum;
}

/* The vertices in LS_FIT_MASK_PARTS blocks whatever the worker count, the
 * blocks' values added in block order: the same bits for every W. */
void ls_fit_impl_mask_pull(ls_fit *fit)
{
    const ls_fit_config *c = &fit->config;
    struct ls_fit_pass *p = fit->pass;
    ls_real sum = (ls_real)0;
    uint32_t b;
    if (fit->mask_dist == NULL) return;
    p->fit = fit;
    p->mask_scale = c->mask_pull / ((ls_real)fit_batch(c, fit->views.count) * (ls_real)fit->vertex_count);
    ls_parallel_run(&c->parallel, fit_workers(c), LS_FIT_MASK_PARTS, pull_task, p);
    for (b = 0; b < LS_FIT_MASK_PARTS; b++) sum += p->mask_sums[b];
    fit->reg_loss += sum * p->mask_scale;
}
