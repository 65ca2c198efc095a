/* fit_normals.c - the vertex normals and their backward on the caller's
 * workers (W > 1): the faces' terms by blocks of faces, then each vertex's
 * sum of its faces' terms in face order by blocks of vertices, from the
 * mesh's vertex-to-corner incidence. A vertex receives the same terms in the
 * same order as in ls_shade_vertex_normals and ls_vertex_normals_backward
 * (which one worker calls), so the bits are theirs. */
#include "fit_internal.h"
#include "../render/render_internal.h"
#include "../base/parallel.h"
#include <stddef.h>

void ls_fit_impl_incidence(const ls_fit *fit)
{
    const struct ls_fit_pass *p = fit->pass;
    const uint32_t n = fit->vertex_count, corners = 3u * fit->face_count;
    uint32_t *start = p->vf_start, i, v;
    if (start == NULL) return; /* one worker: the serial calls need none */
    memset(start, 0, ((size_t)n + 1u) * sizeof(uint32_t));
    for (i = 0; i < corners; i++) start[fit->triangles[i] + 1u]++;
    for (v = 0; v < n; v++) start[v + 1u] += start[v];
    /* each vertex's corners in corner (so face) order; start[v] ends at v's end */
    for (i = 0; i < corners; i++) p->vf_corner[start[fit->triangles[i]]++] = i;
    for (v = n; v > 0u; v--) start[v] = start[v - 1u];
    start[0] = 0;
}

/* A task's pass and its part [lo, hi) of the faces (faces 1) or vertices. */
static const struct ls_fit_pass *task_part(const void *arg, uint32_t part, int faces, uint32_t *lo, uint32_t *hi)
{
    const struct ls_fit_pass *p = (const struct ls_fit_pass *)arg;
    const uint64_t count = faces ? p->fit->face_count : p->fit->vertex_count;
    *lo = (uint32_t)(count * part / p->parts);
    *hi = (uint32_t)(count * (part + 1u) / p->parts);
    return p;
}

static void normal_face_task(void *arg, uint32_t part, uint32_t worker)
{
    uint32_t t, lo, hi;
    const struct ls_fit_pass *p = task_part(arg, part, 1, &lo, &hi);
    const ls_fit *fit = p->fit;
    (void)worker;
    for (t = lo; t < hi; t++)
        p->face_ok[t] = (unsigned char)ls_face_unit_normal(fit->xr, fit->triangles + 3u * (size_t)t, p->face_buf + 3u * (size_t)t);
}

static void normal_vertex_task(void *arg, uint32_t part, uint32_t worker)
{
    uint32_t v, e, q, lo, hi;
    const struct ls_fit_pass *p = task_part(arg, part, 0, &lo, &hi);
    (void)worker;
    for (v = lo; v < hi; v++) {
        ls_real *m = p->nsum + 3u * (size_t)v;
        m[0] = m[1] = m[2] = (ls_real)0;
        for (e = p->vf_start[v]; e < p->vf_start[v + 1u]; e++) {
            const uint32_t t = p->vf_corner[e] / 3u;
            if (!p->face_ok[t]) continue;
            for (q = 0; q < 3u; q++) m[q] += p->face_buf[3u * (size_t)t + q];
        }
        ls_vertex_normal_unit(m, p->fit->normals + 3u * (size_t)v);
    }
}

ls_status ls_fit_impl_normals(ls_fit *fit, ls_diag *diag)
{
    const ls_fit_config *c = &fit->config;
    struct ls_fit_pass *p = fit->pass;
    if (p->vf_start == NULL)
        return ls_shade_vertex_normals(fit->xr, fit->vertex_count, fit->triangles, fit->face_count, fit->normals, diag);
    p->fit = fit;
    p->parts = fit_workers(c);
    ls_parallel_run(&c->parallel, fit_workers(c), p->parts, normal_face_task, p);
    ls_parallel_run(&c->parallel, fit_workers(c), p->parts, normal_vertex_task, p);
    return LS_OK;
}

static void grad_vertex_task(void *arg, uint32_t part, uint32_t worker)
{
    uint32_t v, lo, hi;
    const struct ls_fit_pass *p = task_part(arg, part, 0, &lo, &hi);
    (void)worker;
    for (v = lo; v < hi; v++) ls_vertex_normal_sum_grad(p->nsum + 3u * (size_t)v, p->fit->gnormals + 3u * (size_t)v);
}

static void grad_face_task(void *arg, uint32_t part, uint32_t worker)
{
    uint32_t t, lo, hi;
    const struct ls_fit_pass *p = task_part(arg, part, 1, &lo, &hi);
    const ls_fit *fit = p->fit;
    (void)worker;
    for (t = lo; t < hi; t++)
        p->face_ok[t] = (unsigned char)ls_face_normal_backward(fit->xr, fit->triangles + 3u * (size_t)t, p->nsum,
                                                               p->face_buf + 9u * (size_t)t);
}

static void grad_gather_task(void *arg, uint32_t part, uint32_t worker)
{
    uint32_t v, e, q, lo, hi;
    const struct ls_fit_pass *p = task_part(arg, part, 0, &lo, &hi);
    (void)worker;
    for (v = lo; v < hi; v++) {
        ls_real *d = p->fit->gx + 3u * (size_t)v;
        for (e = p->vf_start[v]; e < p->vf_start[v + 1u]; e++) {
            const uint32_t t = p->vf_corner[e] / 3u, k = p->vf_corner[e] % 3u;
            const ls_real *g = p->face_buf + 9u * (size_t)t;
            if (!p->face_ok[t]) continue;
            if (k == 0u)
                for (q = 0; q < 3u; q++) d[q] -= g[q];
            else
                for (q = 0; q < 3u; q++) d[q] += g[3u * k + q];
        }
    }
}

ls_status ls_fit_impl_normals_backward(ls_fit *fit, ls_diag *diag)
{
    const ls_fit_config *c = &fit->config;
    struct ls_fit_pass *p = fit->pass;
    if (p->vf_start == NULL)
        return ls_vertex_normals_backward(fit->xr, fit->vertex_count, fit->triangles, fit->face_count, fit->gnormals,
                                          fit->gx, &fit->block, diag);
    p->fit = fit;
    p->parts = fit_workers(c);
    /* nsum holds this iteration's sums (ls_fit_impl_normals, same positions) */
    ls_parallel_run(&c->parallel, fit_workers(c), p->parts, grad_vertex_task, p);
    ls_parallel_run(&c->parallel, fit_workers(c), p->parts, grad_face_task, p);
    ls_parallel_run(&c->parallel, fit_workers(c), p->parts, grad_gather_task, p);
    return LS_OK;
}
