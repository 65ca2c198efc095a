/* fit_job.c - fitting problems and measured runs (see fit_job.h). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include "ls_posix.h"
#include "fit_job.h"
#include "report.h"

extern const unsigned char ls_embedded_bunny_obj[];
extern const size_t ls_embedded_bunny_obj_size;

/* The SH lighting of mesh targets: a soft sky from above plus a key light
 * from the front right (9 coefficients per channel, shade.h's order). */
const ls_real ls_job_default_sh[27] = {
    (ls_real)1.70, (ls_real)0.55, (ls_real)0.35, (ls_real)-0.25, (ls_real)0.05, (ls_real)0.04, (ls_real)-0.06, (ls_real)0.02, (ls_real)-0.05,
    (ls_real)1.65, (ls_real)0.55, (ls_real)0.35, (ls_real)-0.25, (ls_real)0.05, (ls_real)0.04, (ls_real)-0.06, (ls_real)0.02, (ls_real)-0.05,
    (ls_real)1.55, (ls_real)0.60, (ls_real)0.35, (ls_real)-0.25, (ls_real)0.05, (ls_real)0.04, (ls_real)-0.06, (ls_real)0.02, (ls_real)-0.05,
};

double ls_job_smallest_mode(const ls_mesh *m, ls_arena *arena)
{
    const double w = 1e3;
    ls_arena_mark mark = ls_arena_save(arena);
    const uint32_t n = m->vertex_count;
    ls_param_config c;
    ls_param p;
    ls_real *x, *u;
    double mu = 0;
    uint32_t i, it;
    ls_param_config_default(&c);
    c.form = LS_SYSTEM_LAMBDA;
    c.weight = (ls_real)w;
    c.k = 1;
    x = (ls_real *)ls_arena_alloc(arena, n, sizeof(ls_real));
    u = (ls_real *)ls_arena_alloc(arena, n, sizeof(ls_real));
    if (n < 4 || x == NULL || u == NULL || ls_param_init_mesh(&p, m, &c, arena, NULL) != LS_OK) {
        ls_arena_restore(arena, mark);
        return 0;
    }
    for (i = 0; i < n; i++) x[i] = (ls_real)((double)((i * 2654435761u) % 1000u) / 1000.0 - 0.5);
    for (it = 0; it < 100; it++) {
        double mean = 0, norm = 0, num = 0;
        if (ls_param_from_differential(&p, x, u) != LS_OK) break;
        for (i = 0; i < n; i++) mean += (double)u[i];
        mean /= n;
        for (i = 0; i < n; i++) norm += ((double)u[i] - mean) * ((double)u[i] - mean);
        if (!(norm > 0)) break;
        for (i = 0; i < n; i++) x[i] = (ls_real)(((double)u[i] - mean) / sqrt(norm));
        if (ls_param_to_differential(&p, x, u) != LS_OK) break;
        for (i = 0; i < n; i++) num += (double)x[i] * ((double)u[i] - (double)x[i]) / w;
        if (it > 0 && fabs(num - mu) <= 1e-6 * mu) {
            mu = num;
            break;
        }
        mu = num;
    }
    ls_arena_restore(arena, mark);
    return mu;
}

int ls_job_parse_remesh(const char *text, uint32_t *at, uint32_t *count)
{
    const char *p = text;
    int ok = 1;
    *count = 0;
    if (strcmp(text, "none") == 0) return 1;
    while (ok && *p != '\0') {
        char *end;
        unsigned long it = *p >= '0' && *p <= '9' ? strtoul(p, &end, 10) : (end = (char *)(uintptr_t)p, 0ul);
        ok = end != p && *count < LS_JOB_MAX_REMESH && it < 1000000ul && (*count == 0 || it > at[*count - 1u]);
        if (ok) at[(*count)++] = (uint32_t)it;
        p = *end == ',' ? end + 1 : end;
        if (*end != ',' && *end != '\0') ok = 0;
    }
    return ok && *count > 0;
}

double ls_job_now_ms(void) { return (double)ls_posix_clock_ns(NULL) * 1e-6; }

int ls_job_fail(const char *what, ls_status st, const ls_diag *d)
{
    /* a file that could not be read: its reason alone (ls_posix_read_error) */
    int unread = (st == LS_ERR_IO || st == LS_ERR_TOO_LARGE) && d != NULL && d->what == ls_posix_read_error();
    fprintf(stderr, "largesteps: %s%s: %s%s%s\n", unread ? "cannot read " : "", what, unread ? "" : ls_status_str(st),
            !unread && d != NULL && d->what != NULL && d->what[0] ? ": " : "", d != NULL && d->what != NULL ? d->what : "");
    return 0;
}

/* dir of `file` + rel (rel unchanged when absolute or when file has no dir). */
static void join_path(const char *file, const char *rel, char *out, size_t cap)
{
    const char *slash = strrchr(file, '/');
    size_t n = slash != NULL && rel[0] != '/' ? (size_t)(slash - file) + 1u : 0u;
    if (n >= cap) n = 0;
    memcpy(out, file, n);
    out[n] = '\0';
    strncat(out, rel, cap - n - 1u);
}

static int has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

static ls_status load_image(const char *path, ls_arena *arena, ls_image *img, ls_diag *d)
{
    unsigned char *data = NULL;
    size_t bytes = 0;
    ls_status st = ls_posix_read_file(path, &data, &bytes);
    if (st != LS_OK && d != NULL) {
        ls_diag_clear(d);
        d->what = ls_posix_read_error();
    }
    if (st == LS_OK) st = ls_image_decode(data, bytes, img, arena, d);
    free(data);
    return st;
}

/* The scene's cameras, lighting and background. */
static int apply_scene(ls_job_problem *p, const ls_scene *sc, const char *scene_path, ls_arena *arena)
{
    char path[4096];
    ls_diag d;
    uint32_t v, i, k;
    ls_status st = LS_OK;
    ls_diag_clear(&d);
    p->views = sc->camera_count;
    p->width = sc->width;
    p->height = sc->height;
    p->mvps = (ls_real *)ls_arena_alloc(arena, 16u * p->views, sizeof(ls_real));
    if (p->mvps == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL);
    for (v = 0; v < p->views && st == LS_OK; v++) {
        ls_real proj[16];
        st = ls_scene_projection(sc, v, proj);
        if (st == LS_OK) ls_mat4_mul(proj, sc->cameras[v].view, p->mvps + 16u * v);
    }
    if (st != LS_OK) return ls_job_fail("scene camera", st, NULL);
    for (k = 0; k < 3; k++) p->shading.background[k] = sc->background[k];
    if (sc->lighting == LS_SCENE_LIGHT_UNKNOWN && p->shading.mode != LS_SHADE_MASK) {
        fprintf(stderr, "largesteps: %s does not record its lighting: estimating it (9 RGB spherical-harmonics "
                        "coefficients; the albedo uniform, or per vertex with --albedo vertex) from the images with the geometry (--shading mask fits the "
                        "alpha masks alone)\n", scene_path);
        p->shading.mode = LS_SHADE_SH;
        p->light = LS_FIT_LIGHT_ESTIMATE;
        memset(p->sh, 0, sizeof p->sh);
    } else if (sc->lighting == LS_SCENE_LIGHT_MASK || sc->lighting == LS_SCENE_LIGHT_UNKNOWN) {
        p->shading.mode = LS_SHADE_MASK;
    } else if (sc->lighting == LS_SCENE_LIGHT_SH) {
        memcpy(p->sh, sc->sh, sizeof p->sh);
    } else {
        ls_arena_mark mark = ls_arena_save(arena);
        ls_image env;
        ls_real *rgb;
        join_path(scene_path, sc->envmap, path, sizeof path);
        st = load_image(path, arena, &env, &d);
        if (st != LS_OK) return ls_job_fail(path, st, &d);
        rgb = (ls_real *)ls_arena_alloc(arena, 3u * (size_t)env.width * env.height, sizeof(ls_real));
        if (rgb == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL);
        for (i = 0; i < env.width * env.height; i++)
            for (k = 0; k < 3; k++) rgb[3u * i + k] = (ls_real)env.pixels[4u * i + k];
        st = ls_sh_from_equirect(rgb, env.width, env.height, p->sh);
        if (st != LS_OK) return ls_job_fail("projecting the environment map", st, NULL);
        for (i = 0; i < 27; i++) p->sh[i] *= sc->envmap_scale;
        ls_arena_restore(arena, mark);
    }
    return 1;
}

/* A dataset without w, h: the resolution of its first image. */
static int size_from_image(ls_scene *sc, const char *scene_path, ls_arena *arena)
{
    char path[4096];
    ls_arena_mark mark = ls_arena_save(arena);
    ls_image img;
    ls_diag d;
    ls_status st;
    join_path(scene_path, sc->cameras[0].image, path, sizeof path);
    ls_diag_clear(&d);
    st = load_image(path, arena, &img, &d);
    ls_arena_restore(arena, mark);
    if (st != LS_OK) return ls_job_fail(path, st, &d);
    sc->width = img.width;
    sc->height = img.height;
    return 1;
}

/* Where the cameras look, for a start without a mesh: the point nearest to
 * every camera's axis (least squares), and the radius whose sphere covers
 * the largest of the masks' extents, as a mesh target's bounding sphere does
 * (a sphere inside every mask, half as large, ended at 17 % of the diagonal
 * instead of 2.4 % on the bunny's 16-view dataset: growing is slower than
 * shrinking). */
static void start_from_cameras(ls_job_problem *p, const ls_scene *sc)
{
    double a[9] = {0}, b[3] = {0}, c[3], det, r = 0;
    uint32_t v, i, k;
    for (v = 0; v < sc->camera_count; v++) {
        const ls_real *m = sc->cameras[v].view;
        double d[3], o[3];
        for (k = 0; k < 3; k++) {
            d[k] = -(double)m[8 + k]; /* the view's -z axis in world space */
            o[k] = -((double)m[k] * m[3] + (double)m[4 + k] * m[7] + (double)m[8 + k] * m[11]);
        }
        for (i = 0; i < 3; i++)
            for (k = 0; k < 3; k++) {
                double q = (i == k ? 1.0 : 0.0) - d[i] * d[k];
                a[3 * i + k] += q;
                b[i] += q * o[k];
            }
    }
    det = a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) + a[2] * (a[3] * a[7] - a[4] * a[6]);
    if (!(det > 1e-9 || det < -1e-9)) return; /* parallel axes: keep the origin */
    c[0] = (b[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (b[1] * a[8] - a[5] * b[2]) + a[2] * (b[1] * a[7] - a[4] * b[2])) / det;
    c[1] = (a[0] * (b[1] * a[8] - a[5] * b[2]) - b[0] * (a[3] * a[8] - a[5] * a[6]) + a[2] * (a[3] * b[2] - b[1] * a[6])) / det;
    c[2] = (a[0] * (a[4] * b[2] - b[1] * a[7]) - a[1] * (a[3] * b[2] - b[1] * a[6]) + b[0] * (a[3] * a[7] - a[4] * a[6])) / det;
    /* per view: the mask's half extent in NDC times the distance over the
     * projection's scale is the radius that fills it; the largest */
    for (v = 0; v < sc->camera_count; v++) {
        const ls_real *t = p->targets[v], *m = sc->cameras[v].view, *mvp = p->mvps + 16u * v;
        uint32_t x0 = sc->width, x1 = 0, y0 = sc->height, y1 = 0, x, y;
        double z = 0, sx = (double)mvp[0] * mvp[0] + (double)mvp[1] * mvp[1] + (double)mvp[2] * mvp[2];
        double sy = (double)mvp[4] * mvp[4] + (double)mvp[5] * mvp[5] + (double)mvp[6] * mvp[6], ext;
        for (y = 0; y < sc->height; y++)
            for (x = 0; x < sc->width; x++)
                if (t[4u * ((size_t)y * sc->width + x) + 3u] > (ls_real)0.5) {
                    if (x < x0) x0 = x;
                    if (x > x1) x1 = x;
                    if (y < y0) y0 = y;
                    if (y > y1) y1 = y;
                }
        if (x1 < x0) return; /* an empty mask: load_targets' checks report masks; keep the default */
        for (k = 0; k < 3; k++) z += (double)m[8 + k] * c[k];
        z = -(z + (double)m[11]); /* the centre's depth */
        ext = (double)(x1 - x0 + 1) / sc->width / sqrt(sx);
        if ((double)(y1 - y0 + 1) / sc->height / sqrt(sy) > ext) ext = (double)(y1 - y0 + 1) / sc->height / sqrt(sy);
        if (z > 0 && z * ext > r) r = z * ext;
    }
    if (!(r > 0)) return;
    for (k = 0; k < 3; k++) p->framing.center[k] = (ls_real)c[k];
    p->framing.radius = (ls_real)r;
}

/* Decodes every camera's target image into p->targets[v]. A camera
 * dataset's images carry the mask in alpha: fitting masks, every channel
 * is the alpha. */
static int load_targets(ls_job_problem *p, const ls_scene *sc, const char *scene_path, int dataset, ls_arena *arena)
{
    char path[4096];
    ls_diag d;
    uint32_t v, i, k;
    for (v = 0; v < p->views; v++) {
        ls_arena_mark mark = ls_arena_save(arena);
        ls_image img;
        ls_status st;
        join_path(scene_path, sc->cameras[v].image, path, sizeof path);
        ls_diag_clear(&d);
        st = load_image(path, arena, &img, &d);
        if (st != LS_OK) return ls_job_fail(path, st, &d);
        if (img.width != sc->width || img.height != sc->height) {
            fprintf(stderr, "largesteps: %s is %ux%u, the scene's resolution is %ux%u\n", path, (unsigned)img.width,
                    (unsigned)img.height, (unsigned)sc->width, (unsigned)sc->height);
            return 0;
        }
        if (dataset && (p->shading.mode == LS_SHADE_MASK || p->light == LS_FIT_LIGHT_ESTIMATE)) {
            int masked = 0;
            for (i = 0; i < img.width * img.height; i++) {
                ls_real a = (ls_real)img.pixels[4u * i + 3u];
                if (p->light == LS_FIT_LIGHT_ESTIMATE) { /* the colours, as the images give them */
                    for (k = 0; k < 3; k++) p->targets[v][4u * i + k] = (ls_real)img.pixels[4u * i + k];
                } else {
                    p->targets[v][4u * i] = p->targets[v][4u * i + 1u] = p->targets[v][4u * i + 2u] = a;
                }
                p->targets[v][4u * i + 3u] = a;
                masked |= a < (ls_real)1;
            }
            if (!masked) {
                fprintf(stderr, "largesteps: %s has no mask: a dataset's images need the object's mask in their "
                                "alpha channel (RGBA PNG)\n", path);
                return 0;
            }
        } else {
            for (i = 0; i < 4u * img.width * img.height; i++) p->targets[v][i] = (ls_real)img.pixels[i];
        }
        ls_arena_restore(arena, mark);
    }
    return 1;
}

/* The views of ls_job_render, a task each: worker w rasterizes into its own
 * visibility buffer and scratch (each worker's share of the arena's free
 * bytes); a view's status and diagnosis are its own. */
typedef struct render_job {
    const ls_job_problem *p;
    const ls_view *view; /* all but vis and mvp */
    ls_real **rgba;
    ls_vis *vis;         /* [workers] */
    ls_arena *scratch;   /* [workers] */
    ls_status *st;       /* [views] */
    ls_diag *d;          /* [views] */
} render_job;

static void render_task(void *arg, uint32_t v, uint32_t w)
{
    const render_job *j = (const render_job *)arg;
    ls_arena_mark mark = ls_arena_save(&j->scratch[w]);
    ls_view view = *j->view;
    view.vis = &j->vis[w];
    view.mvp = j->p->mvps + 16u * v;
    ls_diag_clear(&j->d[v]);
    j->st[v] = ls_raster(&j->vis[w], &view, &j->scratch[w], &j->d[v]);
    if (j->st[v] == LS_OK) j->st[v] = ls_shade(&view, j->rgba[v], &j->d[v]);
    ls_arena_restore(&j->scratch[w], mark);
}

/* The views on `workers` workers (1: here, in view order), the arena's free
 * bytes split among them: LS_OK, or the first failing view's status (in
 * view order); LS_ERR_NOMEM also when a share is too small. */
static ls_status render_views(const ls_job_problem *p, const ls_view *view, uint32_t ss, ls_real **rgba,
                              uint32_t workers, ls_arena *arena, ls_diag *d)
{
    ls_arena_mark mark = ls_arena_save(arena);
    render_job j;
    size_t share;
    uint32_t w, v;
    ls_status st = LS_OK;
    j.p = p;
    j.view = view;
    j.rgba = rgba;
    j.vis = (ls_vis *)ls_arena_alloc(arena, workers, sizeof(ls_vis));
    j.scratch = (ls_arena *)ls_arena_alloc(arena, workers, sizeof(ls_arena));
    j.st = (ls_status *)ls_arena_alloc(arena, p->views, sizeof(ls_status));
    j.d = (ls_diag *)ls_arena_alloc(arena, p->views, sizeof(ls_diag));
    if (j.d == NULL) st = LS_ERR_NOMEM;
    share = ls_arena_available(arena) / workers / LS_ARENA_ALIGN * LS_ARENA_ALIGN;
    for (w = 0; w < workers && st == LS_OK; w++) {
        void *mem = ls_arena_alloc(arena, share, 1);
        st = mem == NULL ? LS_ERR_NOMEM : ls_arena_init(&j.scratch[w], mem, share);
        if (st == LS_OK) st = ls_vis_init(&j.vis[w], &j.scratch[w], p->width, p->height, ss, view->vertex_count);
    }
    if (st == LS_OK && workers > 1u)
        p->parallel.run(p->parallel.ctx, p->views, render_task, &j);
    else if (st == LS_OK)
        for (v = 0; v < p->views; v++) render_task(&j, v, 0);
    for (v = 0; v < p->views && st == LS_OK; v++) {
        st = j.st[v];
        if (st != LS_OK && d != NULL) *d = j.d[v];
    }
    ls_arena_restore(arena, mark);
    return st;
}

ls_status ls_job_render(const ls_job_problem *p, const ls_mesh *m, uint32_t ss, ls_real **rgba, ls_arena *arena,
                        ls_diag *d)
{
    ls_arena_mark mark = ls_arena_save(arena);
    const uint32_t workers = p->parallel.run != NULL && p->views > 1u ? ls_job_workers(p) : 1u;
    ls_view view;
    ls_real *normals = (ls_real *)ls_arena_alloc(arena, 3u * (size_t)m->vertex_count, sizeof(ls_real));
    ls_status st = normals == NULL ? LS_ERR_NOMEM : LS_OK;
    if (st == LS_OK) st = ls_shade_vertex_normals(m->positions, m->vertex_count, m->triangles, m->face_count, normals, d);
    memset(&view, 0, sizeof view);
    view.positions = m->positions;
    view.indices = m->triangles;
    view.triangle_count = m->face_count;
    view.vertex_count = m->vertex_count;
    view.normals = normals;
    view.opts = &p->shading;
    if (st == LS_OK) st = render_views(p, &view, ss, rgba, workers, arena, d);
    if (st == LS_ERR_NOMEM && workers > 1u) /* a worker's share too small: all of the memory, here */
        st = render_views(p, &view, ss, rgba, 1u, arena, d);
    ls_arena_restore(arena, mark);
    return st;
}

/* Taubin's smoothing, n steps of x += lambda (avg of the neighbours - x)
 * then the same with mu: a low-pass filter that does not shrink the mesh
 * (plain averaging would). lap: the uniform Laplacian D - A (full storage),
 * so (avg - x)_i = -(L x)_i / L_ii; y: 3 V scratch. */
static void taubin(const ls_csc *lap, ls_real *x, ls_real *y, uint32_t n)
{
    static const ls_real steps[2] = {(ls_real)0.5, (ls_real)-0.53};
    uint32_t it, i, s, c, k;
    for (it = 0; it < n; it++)
        for (s = 0; s < 2; s++) {
            (void)ls_csc_matvec(lap, 3, x, y);
            for (i = 0; i < lap->ncols; i++) {
                ls_real deg = 0;
                for (k = lap->colptr[i]; k < lap->colptr[i + 1u]; k++)
                    if (lap->rowidx[k] == i) deg = lap->values[k];
                if (deg > 0)
                    for (c = 0; c < 3; c++) x[3u * i + c] -= steps[s] * y[3u * i + c] / deg;
            }
        }
}

/* 1 when face t (the same three vertices as t0) goes round them as t0 does. */
static int same_turn(const uint32_t *t, const uint32_t *t0)
{
    const uint32_t at = t[0] == t0[0] ? 0u : t[1] == t0[0] ? 1u : 2u;
    return t[(at + 1u) % 3u] == t0[1];
}

/* `src` without its fins into *out (its positions shared, its triangles in
 * the arena's scratch): faces on the same three vertices cancel in pairs of
 * opposite orientation (a zero-thickness fin, whose edges are non-manifold:
 * Suzanne has one where two quads share a diagonal), and of what is left of
 * such a group one face is kept. The remesher refuses a non-manifold edge;
 * the surface is the same without them. *out is src itself when it has none. */
static int without_fins(const ls_mesh *src, ls_arena *arena, ls_mesh *out)
{
    const uint32_t nf = src->face_count;
    uint32_t *tri, *high, *idx, *keep, f, g, h, kept = 0;
    uint64_t *low;
    *out = *src;
    tri = (uint32_t *)ls_arena_scratch(arena, 3u * (size_t)nf, sizeof(uint32_t));
    high = (uint32_t *)ls_arena_scratch(arena, nf, sizeof(uint32_t));
    low = (uint64_t *)ls_arena_scratch(arena, nf, sizeof(uint64_t));
    idx = (uint32_t *)ls_arena_scratch(arena, nf, sizeof(uint32_t));
    keep = (uint32_t *)ls_arena_scratch(arena, nf, sizeof(uint32_t));
    if (keep == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL);
    for (f = 0; f < nf; f++) { /* the corners sorted: the two smaller in low, the largest in high */
        const uint32_t *t = src->triangles + 3u * (size_t)f;
        uint32_t a = t[0], b = t[1], c = t[2], x;
        if (a > b) x = a, a = b, b = x;
        if (b > c) x = b, b = c, c = x;
        if (a > b) x = a, a = b, b = x;
        low[f] = (uint64_t)a << 32 | b;
        high[f] = c;
        idx[f] = f;
    }
    /* by the largest corner, then (stably) by the two others: equal faces side by side
       (keep is the sorts' scratch until it holds the verdicts) */
    (void)ls_sort_u32(high, idx, nf, keep);
    (void)ls_sort_u64(low, idx, nf, keep);
    for (f = 0; f < nf; f++) keep[f] = 1u;
    for (g = 0; g < nf; g = h) {
        const uint32_t *t0 = src->triangles + 3u * (size_t)idx[g];
        int turn = 0; /* faces turning as the group's first, minus those turning the other way */
        for (h = g; h < nf && low[idx[h]] == low[idx[g]] && high[idx[h]] == high[idx[g]]; h++)
            turn += same_turn(src->triangles + 3u * (size_t)idx[h], t0) ? 1 : -1;
        if (h - g == 1u) continue;
        for (f = g; f < h; f++) keep[idx[f]] = 0u;
        for (f = g; f < h && turn != 0; f++) /* one face of the orientation left over */
            if (same_turn(src->triangles + 3u * (size_t)idx[f], t0) == (turn > 0)) {
                keep[idx[f]] = 1u;
                break;
            }
    }
    for (f = 0; f < nf; f++)
        if (keep[f]) memcpy(tri + 3u * (size_t)kept++, src->triangles + 3u * (size_t)f, 3u * sizeof(uint32_t));
    if (kept < nf) {
        out->triangles = tri;
        out->face_count = kept;
    }
    return 1;
}

/* `clean` remeshed to edge h into p->initial; long needle faces (a CAD
 * part's) outgrow the remesher's bound (remesh.h): then 4 x the room. */
static ls_status remesh_start(ls_job_problem *p, const ls_mesh *clean, ls_real h, ls_arena *arena, ls_diag *d)
{
    ls_remesh_params rp;
    ls_status st;
    ls_remesh_params_default(&rp, h);
    ls_diag_clear(d);
    st = ls_remesh(clean, &rp, arena, &p->initial, NULL, d);
    if (st == LS_ERR_NOMEM) {
        ls_arena_mark m2 = ls_arena_save(arena);
        ls_mesh_report rep;
        uint32_t cap = 0;
        if (ls_mesh_validate(clean, arena, &rep) != LS_OK || ls_remesh_capacity(clean, &rep, rp.h, &cap) != LS_OK) cap = 0;
        ls_arena_restore(arena, m2);
        if (cap > 0 && cap <= UINT32_MAX / 4u) {
            rp.vertex_cap = 4u * cap;
            ls_diag_clear(d);
            st = ls_remesh(clean, &rp, arena, &p->initial, NULL, d);
        }
    }
    return st;
}

/* The initial mesh from `source` (the target, or its visual hull): remeshed
 * to edge `edge` x the source's bounding-box diagonal (projected onto it:
 * same genus), then `smooth` Taubin steps take its detail away. For targets
 * a sphere cannot reach (the elephant has genus 3). A remesh that
 * self-intersects (a part thinner than the edge, where the remesher's
 * relaxation folds it: the femur at 0.012 of its diagonal has 4 pairs, at
 * 0.0132 none) is made again at LS_JOB_START_RETRY times the edge, twice at
 * most; when every one does, the first is kept. The mesh stays at the
 * arena's bottom. */
static int coarse_initial(ls_job_problem *p, const ls_mesh *source, double edge, uint32_t smooth, int required,
                          ls_arena *arena)
{
    ls_real lo[3], hi[3], diag2 = 0, h, *y, *keep;
    ls_arena_mark mark, start;
    ls_tangle_report t;
    ls_mesh clean;
    ls_csc lap;
    ls_diag d;
    size_t top;
    uint32_t i, c, k, pairs = 0, attempt;
    ls_status st = LS_OK;
    ls_diag_clear(&d);
    for (c = 0; c < 3; c++) lo[c] = hi[c] = source->positions[c];
    for (i = 0; i < source->vertex_count; i++)
        for (c = 0; c < 3; c++) {
            ls_real v = source->positions[3u * i + c];
            if (v < lo[c]) lo[c] = v;
            if (v > hi[c]) hi[c] = v;
        }
    for (c = 0; c < 3; c++) diag2 += (hi[c] - lo[c]) * (hi[c] - lo[c]);
    h = (ls_real)edge * LS_RSQRT(diag2);
    mark = ls_arena_save(arena);
    if (!without_fins(source, arena, &clean)) return 0;
    start = ls_arena_save(arena);
    for (attempt = 0;; attempt++) {
        const int again = attempt > LS_JOB_START_RETRIES; /* every edge tried self-intersects: the first */
        ls_real ha = h;
        for (k = 0; !again && k < attempt; k++) ha *= (ls_real)LS_JOB_START_RETRY;
        ls_arena_restore(arena, start);
        st = remesh_start(p, &clean, ha, arena, &d);
        if (st == LS_OK) st = ls_tangle(&p->initial, NULL, arena, &t, &d);
        if (st != LS_OK) break;
        pairs = t.intersecting_pairs;
        p->start_edge_asked = edge;
        p->start_edge = edge * (double)(ha / h);
        p->start_tries = attempt + 1u;
        p->start_pairs = pairs;
        if (pairs == 0 || again) break;
    }
    if (st != LS_OK && !required) { /* the caller's other start; why, for its warning */
        ls_arena_restore(arena, mark);
        p->coarse_failure = d.what != NULL ? d.what : ls_status_str(st);
        return -1;
    }
    if (st != LS_OK) return ls_job_fail("remeshing into the initial mesh", st, &d);
    top = mark.top; /* the fins' scratch released, the remeshed mesh kept */
    mark = ls_arena_save(arena);
    mark.top = top;
    ls_arena_restore(arena, mark);
    if (smooth == 0) return 1;
    st = ls_laplacian_uniform(&p->initial, LS_LAP_FULL, arena, &lap, &d);
    y = st == LS_OK ? (ls_real *)ls_arena_alloc(arena, 3u * (size_t)p->initial.vertex_count, sizeof(ls_real)) : NULL;
    keep = y != NULL ? (ls_real *)ls_arena_alloc(arena, 3u * (size_t)p->initial.vertex_count, sizeof(ls_real)) : NULL;
    if (keep == NULL || st != LS_OK) {
        ls_arena_restore(arena, mark);
        return ls_job_fail("smoothing the initial mesh", st != LS_OK ? st : LS_ERR_NOMEM, &d);
    }
    /* One Taubin step at a time: a step after which the mesh self-intersects
     * more than the remeshed one did is undone and the smoothing stops (the
     * genus-2 femur at 0.03 of its diagonal has 11 pairs after its first step,
     * 24 after ten, and a tangled start ends tangled). */
    for (k = 0; k < smooth; k++) {
        memcpy(keep, p->initial.positions, 3u * (size_t)p->initial.vertex_count * sizeof(ls_real));
        taubin(&lap, p->initial.positions, y, 1);
        st = ls_tangle(&p->initial, NULL, arena, &t, &d);
        if (st != LS_OK || t.intersecting_pairs > pairs) {
            memcpy(p->initial.positions, keep, 3u * (size_t)p->initial.vertex_count * sizeof(ls_real));
            break;
        }
    }
    ls_arena_restore(arena, mark);
    return 1;
}

/* The initial mesh from the targets' masks: their visual hull in the cube
 * around the framing's sphere (a mesh target's bounding sphere; a dataset's
 * sphere guessed from its masks, so half as large again), remeshed coarse
 * (and smoothed when asked). */
static int hull_initial(ls_job_problem *p, uint32_t resolution, double edge, uint32_t smooth, ls_arena *arena)
{
    ls_hull_views hv;
    ls_hull_params hp;
    ls_real lo[3], hi[3];
    ls_mesh hull;
    ls_diag d;
    uint32_t c;
    ls_status st;
    ls_diag_clear(&d);
    for (c = 0; c < 3; c++) {
        ls_real r = p->have_mesh ? p->framing.radius : (ls_real)1.5 * p->framing.radius;
        lo[c] = p->framing.center[c] - r;
        hi[c] = p->framing.center[c] + r;
    }
    ls_hull_params_default(&hp, lo, hi);
    hp.resolution = resolution;
    hv.images = (const ls_real *const *)p->targets;
    hv.mvps = p->mvps;
    hv.count = p->views;
    hv.width = p->width;
    hv.height = p->height;
    st = ls_visual_hull(&hv, &hp, arena, &hull, &d);
    if (st != LS_OK) return ls_job_fail("the visual hull of the targets", st, &d);
    return coarse_initial(p, &hull, edge, smooth, 1, arena);
}

int ls_job_parse_normals(const char *v, uint32_t *normals, double *crease_deg)
{
    double deg = 0;
    if (strcmp(v, "smooth") == 0) *normals = LS_JOB_NORMALS_SMOOTH;
    else if (strcmp(v, "flat") == 0) *normals = LS_JOB_NORMALS_FLAT;
    else if (strcmp(v, "auto") == 0) *normals = LS_JOB_NORMALS_AUTO;
    else if (ls_parse_double(v, strlen(v), &deg) == LS_OK && deg > 0 && deg < 180) *normals = LS_JOB_NORMALS_CREASES;
    else return 0;
    *crease_deg = deg;
    return 1;
}

ls_status ls_job_shown_mesh(const ls_mesh *mesh, uint32_t normals, double crease_deg, ls_arena *arena, ls_mesh *shown,
                            int *creased, double *flat_share, ls_diag *d)
{
    const double rad = 3.14159265358979323846 / 180.0;
    ls_status st = LS_OK;
    *shown = *mesh;
    *creased = 0;
    *flat_share = 0;
    if (normals == LS_JOB_NORMALS_FLAT) return ls_mesh_unweld(mesh, arena, shown, d);
    if (normals == LS_JOB_NORMALS_AUTO) { /* split only a mesh made of flat pieces */
        uint32_t creases = 0, edges = 0;
        st = ls_mesh_count_creases(mesh, (ls_real)ls_cos(LS_JOB_COPLANAR_DEG * rad), arena, &creases, &edges, d);
        *flat_share = edges > 0 ? (double)(edges - creases) / (double)edges : 0;
        *creased = st == LS_OK && *flat_share >= LS_JOB_FLAT_SHARE;
        crease_deg = LS_JOB_CREASE_DEG;
    }
    if (st == LS_OK && (normals == LS_JOB_NORMALS_CREASES || *creased))
        st = ls_mesh_split_creases(mesh, (ls_real)ls_cos(crease_deg * rad), arena, shown, d);
    return st;
}

/* The problem's target images, width x height each. */
static int alloc_targets(ls_job_problem *p, ls_arena *arena)
{
    const size_t px = 4u * (size_t)p->width * p->height;
    uint32_t v;
    p->targets = (ls_real **)ls_arena_alloc(arena, p->views, sizeof(ls_real *));
    if (p->targets == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL);
    for (v = 0; v < p->views; v++) {
        p->targets[v] = (ls_real *)ls_arena_alloc(arena, px, sizeof(ls_real));
        if (p->targets[v] == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL);
    }
    return 1;
}

/* A mesh target's images: the mesh as --target-normals shows it; with auto,
 * flat when the fit starts from the target itself (p->target_flat_start). */
static int render_target(ls_job_problem *p, const ls_job_options *o, ls_arena *arena)
{
    ls_arena_mark mark = ls_arena_save(arena);
    const uint32_t normals = p->target_flat_start ? LS_JOB_NORMALS_FLAT : o->target_normals;
    ls_mesh shown = p->target;
    ls_diag d;
    ls_status st;
    ls_diag_clear(&d);
    st = ls_job_shown_mesh(&p->target, normals, o->target_crease_deg, arena, &shown, &p->target_creased,
                           &p->target_flat_share, &d);
    if (st == LS_OK) st = ls_job_render(p, &shown, o->target_ss, p->targets, arena, &d);
    ls_arena_restore(arena, mark);
    return st == LS_OK ? 1 : ls_job_fail("rendering the target", st, &d);
}

/* p->thickness: the median over the views of each target's inscribed radius. */
static int measure_thickness(ls_job_problem *p, ls_arena *arena)
{
    ls_arena_mark mark = ls_arena_save(arena);
    ls_real *r = (ls_real *)ls_arena_alloc(arena, p->views, sizeof(ls_real));
    ls_diag d;
    uint32_t v, k;
    ls_status st = r != NULL ? LS_OK : LS_ERR_NOMEM;
    ls_diag_clear(&d);
    for (v = 0; v < p->views && st == LS_OK; v++) {
        ls_real x;
        st = ls_mask_inscribed_radius(p->targets[v], p->width, p->height, arena, &x, &d);
        for (k = v; k > 0 && r[k - 1u] > x; k--) r[k] = r[k - 1u]; /* kept sorted */
        if (st == LS_OK) r[k] = x;
    }
    if (st == LS_OK)
        p->thickness = p->views % 2u ? (double)r[p->views / 2u] : 0.5 * ((double)r[p->views / 2u - 1u] + (double)r[p->views / 2u]);
    ls_arena_restore(arena, mark);
    return st == LS_OK ? 1 : ls_job_fail("measuring the targets' thickness", st, &d);
}

int ls_job_load(ls_job_problem *p, const ls_job_options *o, ls_arena *arena)
{
    ls_scene scene;
    ls_arena_mark targets_mark;
    ls_diag d;
    uint32_t v, i;
    int is_scene, own_auto; /* own_auto: the automatic start from the target, for a genus or components */
    ls_status st;
    memset(p, 0, sizeof *p);
    memset(&scene, 0, sizeof scene);
    ls_diag_clear(&d);
    memcpy(p->sh, ls_job_default_sh, sizeof p->sh);
    ls_shade_opts_init(&p->shading);
    p->shading.mode = o->shading;
    p->views = o->views;
    p->width = o->width;
    p->height = o->height;
    p->have_mesh = 1;
    p->name = o->target != NULL ? o->target : "embedded bunny";
    p->parallel = o->parallel;
    p->workers = o->workers;
    is_scene = o->target != NULL && (has_suffix(o->target, ".txt") || has_suffix(o->target, ".scene") ||
                                     has_suffix(o->target, ".xml") || has_suffix(o->target, ".json"));
    if (is_scene) {
        unsigned char *text = NULL;
        size_t bytes = 0;
        char path[4096];
        st = ls_posix_read_file(o->target, &text, &bytes);
        if (st != LS_OK) {
            fprintf(stderr, "largesteps: cannot read %s: %s\n", o->target, ls_posix_read_error());
            return 0;
        }
        if (has_suffix(o->target, ".xml"))
            st = ls_scene_parse_mitsuba((const char *)text, bytes, arena, &scene, &d);
        else if (has_suffix(o->target, ".json"))
            st = ls_scene_parse_transforms((const char *)text, bytes, arena, &scene, &d);
        else
            st = ls_scene_parse((const char *)text, bytes, arena, &scene, &d);
        free(text);
        if (st != LS_OK) {
            fprintf(stderr, "largesteps: %s:%u:%u: %s\n", o->target, (unsigned)d.line, (unsigned)d.column, d.what);
            return 0;
        }
        if (scene.width == 0 && !size_from_image(&scene, o->target, arena)) return 0;
        if (!apply_scene(p, &scene, o->target, arena)) return 0;
        p->have_mesh = scene.target == LS_SCENE_TARGET_MESH;
        if (p->have_mesh) {
            join_path(o->target, scene.target_mesh, path, sizeof path);
            st = ls_posix_load_mesh(path, arena, &p->target, &d);
            if (st != LS_OK) return ls_job_fail(path, st, &d);
        }
    } else if (o->target != NULL) {
        st = ls_posix_load_mesh(o->target, arena, &p->target, &d);
        if (st != LS_OK) return ls_job_fail(o->target, st, &d);
    } else {
        st = ls_mesh_read(ls_embedded_bunny_obj, ls_embedded_bunny_obj_size, LS_MESH_FORMAT_AUTO, arena, &p->target, &d);
        if (st != LS_OK) return ls_job_fail("the embedded bunny", st, &d);
    }
    p->shading.sh = p->sh;
    if (p->have_mesh) {
        st = ls_camera_frame(p->target.positions, p->target.vertex_count,
                             (ls_real)(LS_JOB_FOV_DEG * 3.14159265358979323846 / 180.0), LS_FOV_X,
                             (ls_real)p->width / (ls_real)p->height, (ls_real)LS_JOB_MARGIN, &p->framing, &d);
        if (st != LS_OK) return ls_job_fail("framing the target", st, &d);
    } else {
        p->framing.radius = 1;
    }
    if (p->mvps == NULL) { /* views on a Fibonacci sphere framing the target */
        ls_real *dirs = (ls_real *)ls_arena_alloc(arena, 3u * p->views, sizeof(ls_real));
        p->mvps = (ls_real *)ls_arena_alloc(arena, 16u * p->views, sizeof(ls_real));
        if (p->mvps == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL);
        (void)ls_camera_fibonacci_dirs(p->views, dirs);
        for (v = 0; v < p->views; v++) (void)ls_camera_framed_view(&p->framing, dirs + 3u * v, NULL, p->mvps + 16u * v);
    }
    if (p->have_mesh) { /* what a sphere can reach */
        ls_arena_mark mark = ls_arena_save(arena);
        ls_mesh_report rep;
        if (ls_mesh_validate(&p->target, arena, &rep) == LS_OK) {
            p->target_genus = rep.has_genus ? rep.genus : -1;
            p->target_components = rep.components;
        }
        ls_arena_restore(arena, mark);
    }
    /* a start from the target itself, not smoothed (the automatic one for a genus or components a sphere
       cannot reach, or --init-coarse): its faces are where the fit begins, and renders that show them flat keep
       it there, where smooth renders of a coarse mesh show another surface (docs/fit-suite.md) */
    own_auto = o->init_auto && p->have_mesh && !is_scene && (p->target_genus > 0 || p->target_components > 1);
    p->target_flat_start = p->have_mesh && o->target_normals == LS_JOB_NORMALS_AUTO && o->init_smooth == 0 &&
                           o->init_hull == 0 && !(is_scene && scene.initial == LS_SCENE_INITIAL_MESH) &&
                           (o->init_edge > 0 || own_auto);
    targets_mark = ls_arena_save(arena);
    if (!alloc_targets(p, arena)) return 0;
    if (p->have_mesh) {
        if (!render_target(p, o, arena)) return 0;
    } else if (!load_targets(p, &scene, o->target, has_suffix(o->target, ".json"), arena)) {
        return 0;
    } else if (has_suffix(o->target, ".json") && scene.initial == LS_SCENE_INITIAL_ICOSPHERE) {
        start_from_cameras(p, &scene);
    }
    if (!measure_thickness(p, arena)) return 0;
    if (p->have_mesh && o->auto_res && !is_scene && p->width == p->height && p->thickness > 0 &&
        p->thickness < LS_JOB_MIN_THICKNESS) { /* too thin to grow into: rendered larger */
        const double want = ceil((double)p->width * LS_JOB_MIN_THICKNESS / p->thickness / LS_JOB_AUTO_RES_STEP);
        const uint32_t res = want * LS_JOB_AUTO_RES_STEP < LS_JOB_AUTO_RES_MAX ? (uint32_t)want * LS_JOB_AUTO_RES_STEP
                                                                              : LS_JOB_AUTO_RES_MAX;
        if (res > p->width) {
            p->res_asked = p->width;
            p->thickness_asked = p->thickness;
            ls_arena_restore(arena, targets_mark);
            p->width = p->height = res;
            if (!alloc_targets(p, arena) || !render_target(p, o, arena) || !measure_thickness(p, arena)) return 0;
        }
    }
    if (is_scene && scene.initial == LS_SCENE_INITIAL_MESH) {
        char path[4096];
        join_path(o->target, scene.initial_mesh, path, sizeof path);
        st = ls_posix_load_mesh(path, arena, &p->initial, &d);
        if (st != LS_OK) return ls_job_fail(path, st, &d);
    } else if (o->init_hull > 0) {
        if (!hull_initial(p, o->init_hull, o->init_edge > 0 ? o->init_edge : LS_JOB_HULL_EDGE, o->init_smooth, arena))
            return 0;
    } else if (o->init_edge > 0 && p->have_mesh) {
        if (!coarse_initial(p, &p->target, o->init_edge, o->init_smooth, 1, arena)) return 0;
        p->from_target = 1;
    } else {
        int got = -1;
        if (own_auto) {
            got = coarse_initial(p, &p->target, LS_JOB_AUTO_EDGE, o->init_smooth, 0, arena);
            if (got == 0) return 0;
            p->auto_coarse = got > 0 ? 1 : -1;
            p->from_target = got > 0;
        }
        if (got < 0 && p->target_flat_start) { /* no start from the target after all: its renders as for a sphere */
            p->target_flat_start = 0;
            if (!render_target(p, o, arena)) return 0;
        }
        if (got < 0) { /* an icosphere on the target's bounding sphere */
            st = ls_icosphere(is_scene ? scene.initial_level : o->level, arena, &p->initial);
            if (st != LS_OK) return ls_job_fail("initial icosphere", st, NULL);
            for (i = 0; i < p->initial.vertex_count; i++)
                for (v = 0; v < 3; v++)
                    p->initial.positions[3u * i + v] =
                        p->framing.center[v] + p->framing.radius * p->initial.positions[3u * i + v];
        }
    }
    return 1;
}

/* One distance sample of the fit's current mesh, in memory released after
 * it (the fit stays the last allocation at the bottom, as ls_fit_remesh
 * needs). */
uint32_t ls_job_workers(const ls_job_problem *p) { return p->workers > 1u ? p->workers : 1u; }

/* The distances between m and the target, on the problem's workers. */
static ls_status job_distance(const ls_job_problem *p, const ls_mesh *m, ls_arena *arena, ls_distance_report *dist,
                              ls_diag *d)
{
    const uint32_t samples[2] = {ls_distance_default_samples(m), ls_distance_default_samples(&p->target)};
    return ls_mesh_distance_parallel(m, &p->target, samples, &p->parallel, ls_job_workers(p), arena, dist, d);
}

static int track(const ls_job_problem *p, ls_fit *fit, uint32_t it, double elapsed_ms, ls_arena *arena, ls_job_run *r)
{
    ls_arena_mark mark = ls_arena_save(arena);
    ls_real *pos = (ls_real *)ls_arena_alloc(arena, 3u * (size_t)fit->vertex_count, sizeof(ls_real));
    ls_distance_report dist;
    ls_mesh m;
    ls_diag d;
    ls_status st = pos != NULL ? LS_OK : LS_ERR_NOMEM;
    ls_diag_clear(&d);
    if (st == LS_OK) st = ls_fit_mesh(fit, pos, &m);
    if (st == LS_OK)
        st = job_distance(p, &m, arena, &dist, &d);
    ls_arena_restore(arena, mark);
    if (st != LS_OK) return ls_job_fail("distances during the fit", st, &d);
    r->track_it[r->tracked] = it;
    r->track_ms[r->tracked] = elapsed_ms;
    r->track_h_rel[r->tracked] = dist.hausdorff_rel;
    r->track_rms_rel[r->tracked] = dist.rms_rel;
    r->tracked++;
    return 1;
}

int ls_job_capacity(const ls_job_problem *p, const ls_job_schedule *s, const ls_fit_capacity *given, ls_arena *arena,
                    ls_fit_capacity *cap)
{
    const uint32_t remeshes = s->remesh_count;
    const double growth = 1.0 / ((double)s->remesh_h * (double)s->remesh_h);
    ls_arena_mark mark = ls_arena_save(arena);
    ls_mesh_report rep;
    uint64_t n = (uint64_t)p->initial.vertex_count + 64u, f, z;
    uint32_t r, bits;
    ls_status st = ls_mesh_validate(&p->initial, arena, &rep);
    ls_arena_restore(arena, mark);
    if (st != LS_OK) return ls_job_fail("validating the initial mesh", st, NULL);
    for (r = 0; r < remeshes && n < ((uint64_t)1 << 31); r++) n = (uint64_t)((double)n * growth) + 1u;
    n *= 2u;
    if (n > ((uint64_t)1 << 31)) n = (uint64_t)1 << 31;
    f = (int64_t)(2u * n) > 2 * rep.euler ? (uint64_t)((int64_t)(2u * n) - 2 * rep.euler) : 0u; /* F = 2 V - 2 chi - B */
    if (f < p->initial.face_count) f = p->initial.face_count;
    for (bits = 0; (n >> bits) != 0; bits++) {}
    z = n * 6u * bits;
    cap->max_vertices = given != NULL && given->max_vertices != 0 ? given->max_vertices : (uint32_t)n;
    cap->max_faces = given != NULL && given->max_faces != 0 ? given->max_faces : f > UINT32_MAX ? UINT32_MAX : (uint32_t)f;
    cap->max_factor_nnz = given != NULL && given->max_factor_nnz != 0 ? given->max_factor_nnz
                          : z > UINT32_MAX ? UINT32_MAX : (uint32_t)z;
    return 1;
}

/* ls_job_fail, and for a capacity error which option raises it. */
static int capacity_fail(const char *what, ls_status st, const ls_diag *d)
{
    (void)ls_job_fail(what, st, d);
    if (st == LS_ERR_TOO_LARGE && d->has_value)
        fprintf(stderr, "largesteps: needed %llu, capacity %.0f: raise it with --max-vertices, --max-faces or "
                        "--max-factor-nnz (largesteps fit --help)\n", (unsigned long long)d->index, (double)d->value);
    return 0;
}

/* ls_fit_remesh at h, and where the guard refuses the result for new
 * self-intersections (LS_ERR_MESH), once more at another h (5/4 h, or 3/4 h
 * from h = 0.8 up). *done: 1 remeshed; 0 refused for self-intersections (the
 * second try refused too, or beyond the job's capacity: a fallback, not
 * worth a word); -1 the asked h beyond the capacity (said on stderr); either
 * way the mesh stays as it is and the call succeeds. */
static ls_status guarded_remesh(ls_fit *fit, ls_arena *arena, ls_real h, ls_real lr_factor, ls_remesh_info *ri,
                                int *done, ls_diag *d)
{
    ls_status st = ls_fit_remesh(fit, arena, h, lr_factor, ri, d);
    if (st == LS_ERR_MESH && fit->config.guard) {
        st = ls_fit_remesh(fit, arena, h < (ls_real)0.8 ? h * (ls_real)1.25 : h * (ls_real)0.75, lr_factor, ri, d);
        if (st == LS_ERR_TOO_LARGE) st = LS_ERR_MESH;
    }
    *done = st == LS_OK ? 1 : 0;
    if (st == LS_ERR_TOO_LARGE && fit->config.guard) { /* the fit is as before: go on without this remesh */
        fprintf(stderr, "largesteps: a remesh before iteration %u would exceed the job's capacity (%s); the fit goes "
                        "on with its mesh (--max-vertices raises it)\n", (unsigned)fit->iteration, d->what);
        *done = -1;
        return LS_OK;
    }
    return st == LS_ERR_MESH && fit->config.guard ? LS_OK : st;
}

/* 1 when every value is 0 (a gradient that moves nothing). */
static int all_zero(const ls_real *v, size_t count)
{
    size_t i;
    for (i = 0; i < count; i++)
        if (v[i] != (ls_real)0) return 0;
    return 1;
}

/* Self-intersecting pairs of the fit's current mesh (ls_fit_tangle_pairs). */
static int fit_pairs(ls_fit *fit, uint32_t *pairs)
{
    ls_tangle_report t;
    ls_diag d;
    ls_status st;
    ls_diag_clear(&d);
    st = ls_fit_tangle_pairs(fit, &t, &d);
    if (st != LS_OK) return ls_job_fail("self-intersection check", st, &d);
    *pairs = t.intersecting_pairs;
    return 1;
}

void ls_job_schedule_default(ls_job_schedule *s)
{
    memset(s, 0, sizeof *s);
    s->iterations = 800; /* 400 and 100, 250 twice as long: a lower spread of H over perturbed runs */
    s->remesh_count = 2;
    s->remesh_at[0] = 200;
    s->remesh_at[1] = 500;
    s->remesh_h = (ls_real)0.5;
    s->remesh_lr = (ls_real)0.8;
    /* the guard: checks every 25 iterations (about 1 % of the time of a step each);
     * a roll-back remeshes at the mean edge and steps on at 0.7 x the learning rate */
    s->guard_every = 25;
    s->guard_lr = (ls_real)0.7;
    s->guard_remesh = (ls_real)1;
    /* the last eighth at half the learning rate: a lower H on 7 of 8 suite targets
       (docs/fit-suite.md) for no time */
    s->settle = (ls_real)0.125;
    s->settle_lr = (ls_real)0.5;
    s->boost_final = (ls_real)-1; /* the fit's config.boost throughout; largesteps fit lowers it (cmd_fit.c) */
}

int ls_job_fit(const ls_job_problem *p, const ls_fit_config *cfg, const ls_job_schedule *s, int progress,
               uint32_t track_every, const ls_fit_capacity *capacity, ls_arena *arena, ls_job_run *r)
{
    const uint32_t iterations = s->iterations, remesh_count = s->remesh_count;
    const uint32_t *remesh_at = s->remesh_at;
    const double time_budget_ms = s->time_budget_ms;
    uint32_t track_cap = track_every > 0 && p->have_mesh ? iterations / track_every + 2u : 0u;
    const uint32_t settle_at = iterations - (uint32_t)((double)iterations * (double)s->settle);
    ls_fit_config c = *cfg;
    ls_fit_views fv;
    ls_fit fit;
    ls_arena fit_arena;
    ls_monitor mon;
    ls_diag d;
    ls_real *pos;
    uint32_t it, next = 0, still = 0;
    uint32_t saved_pairs = 0;
    uint32_t guard_every = s->guard_every, clean_checks = 0, starts = 0; /* the guard's interval now (LS_JOB_GUARD_MIN) */
    uint32_t ref_vertices; /* of the mesh after the last scheduled remesh (or the initial mesh) */
    double t0;
    ls_status st;
    memset(r, 0, sizeof *r);
    ls_diag_clear(&d);
    c.width = p->width;
    c.height = p->height;
    c.guard = s->guard_every > 0 ? 1u : 0u;
    c.shading = p->shading;
    c.light = p->light;
    r->loss = (ls_real *)ls_arena_alloc(arena, iterations + 1u, sizeof(ls_real));
    r->ms = (double *)ls_arena_alloc(arena, iterations + 1u, sizeof(double));
    if (r->ms == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL);
    if (track_cap > 0) {
        r->track_it = (uint32_t *)ls_arena_alloc(arena, track_cap, sizeof(uint32_t));
        r->track_ms = (double *)ls_arena_alloc(arena, track_cap, sizeof(double));
        r->track_h_rel = (ls_real *)ls_arena_alloc(arena, track_cap, sizeof(ls_real));
        r->track_rms_rel = (ls_real *)ls_arena_alloc(arena, track_cap, sizeof(ls_real));
        if (r->track_rms_rel == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL);
    }
    fv.count = p->views;
    fv.mvp = p->mvps;
    fv.targets = (const ls_real *const *)p->targets;
    if (capacity != NULL) {
        /* the whole job in one block of exactly the query's bytes */
        void *mem;
        if (!ls_job_capacity(p, s, capacity, arena, &r->capacity)) return 0;
        st = ls_fit_job_bytes(&c, &fv, &p->initial, &r->capacity, arena, &r->job_bytes, &d);
        if (st != LS_OK) return capacity_fail("sizing the fit", st, &d);
        mem = ls_arena_alloc(arena, r->job_bytes, 1);
        if (mem == NULL || ls_arena_init(&fit_arena, mem, r->job_bytes) != LS_OK) {
            fprintf(stderr, "largesteps: memory: the fit needs %.1f MiB for a capacity of %u vertices "
                            "(ls_fit_job_bytes) and %.1f MiB are left of the program's working memory: "
                            "lower --max-vertices, --res, --views or --threads\n",
                    (double)r->job_bytes / 1048576.0, (unsigned)r->capacity.max_vertices,
                    (double)ls_arena_available(arena) / 1048576.0);
            return 0;
        }
    }
    t0 = ls_job_now_ms();
    st = capacity != NULL ? ls_fit_init_job(&fit, &c, &fv, &p->initial, &r->capacity, &fit_arena, &d)
                          : ls_fit_init(&fit, &c, &fv, &p->initial, arena, &d);
    if (st != LS_OK) return capacity_fail("setting up the fit", st, &d);
    ref_vertices = fit.vertex_count;
    r->setup_ms = ls_job_now_ms() - t0;
    r->fit_bytes = fit.block.capacity;
    r->peak_used = fit.block.capacity;
    memset(&mon, 0, sizeof mon);
    mon.clock = ls_posix_clock_ns;
    ls_report_eta eta_est; /* the ETA counts the remeshes to come (report.h) */
    ls_report_eta_init(&eta_est, remesh_at, remesh_count, (double)s->remesh_h);
    t0 = ls_job_now_ms();
    for (it = 0; it < iterations; it++) {
        const int remesh_due = next < remesh_count && remesh_at[next] == it;
        /* the guard's check, and always one before a scheduled remesh: the remesh starts
           from a checked mesh, and one that adds self-intersections to it is refused */
        if (s->guard_every > 0 && (it % guard_every == 0 || !fit.saved_valid || remesh_due)) {
            uint32_t pairs = 0;
            if (!fit_pairs(&fit, &pairs)) return 0;
            if (fit.saved_valid && fit.saved_iteration < fit.iteration && pairs > saved_pairs) {
                uint32_t back = fit.saved_iteration;
                int remeshed = 0;
                (void)ls_fit_rollback(&fit);
                r->rollbacks++;
                if (s->guard_remesh > 0) {
                    /* back to the vertex count of the last scheduled remesh (remeshes at the current
                       mean edge would creep finer, one after the other): h ~ sqrt(V / V0) */
                    ls_remesh_info ri;
                    ls_real h = s->guard_remesh * (ls_real)sqrt((double)fit.vertex_count / (double)ref_vertices);
                    int done;
                    if (h > (ls_real)1.5) h = (ls_real)1.5;
                    if (h < (ls_real)0.7) h = (ls_real)0.7;
                    st = guarded_remesh(&fit, capacity != NULL ? NULL : arena, h, (ls_real)1, &ri, &done, &d);
                    if (st != LS_OK) return capacity_fail("remeshing after a roll-back", st, &d);
                    remeshed = done == 1;
                    if (!remeshed) r->remeshes_refused++;
                    /* the new mesh is the checkpoint, before the first step of the reset optimizer */
                    if (remeshed && !fit_pairs(&fit, &saved_pairs)) return 0;
                    if (remeshed) (void)ls_fit_save(&fit);
                }
                fit.optim.config.lr *= s->guard_lr;
                /* checked more often while the fit cannot leave its start (LS_JOB_GUARD_SPIRAL) */
                starts = back == 0u ? starts + 1u : 0u;
                if (starts >= LS_JOB_GUARD_SPIRAL) { /* back to the start again and again: nothing kept */
                    guard_every = guard_every / 2u > LS_JOB_GUARD_MIN ? guard_every / 2u : LS_JOB_GUARD_MIN;
                    if (guard_every > s->guard_every) guard_every = s->guard_every;
                }
                clean_checks = 0;
                if (progress)
                    printf("%sself-intersections at iteration %u (%u pairs): back to iteration %u%s, lr x %g\n",
                           progress == 2 ? "\n" : "", (unsigned)it, (unsigned)pairs, (unsigned)back,
                           s->guard_remesh <= 0 ? ""
                           : remeshed          ? ", remeshed"
                                               : ", its remesh refused (it would self-intersect more)",
                           (double)s->guard_lr);
            } else {
                (void)ls_fit_save(&fit);
                saved_pairs = pairs;
                if (guard_every < s->guard_every && ++clean_checks >= LS_JOB_GUARD_CLEAN) { /* and less once it stops */
                    guard_every = 2u * guard_every < s->guard_every ? 2u * guard_every : s->guard_every;
                    clean_checks = 0;
                }
            }
        }
        if (remesh_due) {
            ls_remesh_info ri;
            double tr = ls_job_now_ms();
            uint32_t before = fit.vertex_count;
            size_t held = fit.block.capacity;
            if (capacity != NULL) ls_arena_reset_peak(&fit.job);
            int done;
            /* the finest stage's boost (fit.h: read at every step), refused remesh or not */
            if (s->boost_final >= 0 && next + 1u == remesh_count) fit.config.boost = s->boost_final;
            st = guarded_remesh(&fit, capacity != NULL ? NULL : arena, s->remesh_h, s->remesh_lr, &ri, &done, &d);
            if (st != LS_OK) return capacity_fail("remeshing", st, &d);
            if (done == 1) ref_vertices = fit.vertex_count;
            if (done == 1 && s->guard_every > 0) { /* the remeshed mesh is the checkpoint */
                if (!fit_pairs(&fit, &saved_pairs)) return 0;
                (void)ls_fit_save(&fit);
            }
            if (done != 1) {
                fit.optim.config.lr *= s->remesh_lr;
                r->remeshes_refused++;
            }
            next++;
            ls_report_eta_remesh(&eta_est, it, tr - t0, ls_job_now_ms() - t0);
            if (ri.max_vertices > r->remesh_live_max) r->remesh_live_max = ri.max_vertices;
            /* the old fit and the remesher's work at once */
            held += capacity != NULL ? fit.job.peak - fit.job_fit_bytes : 0u;
            if (held > r->peak_used) r->peak_used = held;
            if (fit.block.capacity > r->peak_used) r->peak_used = fit.block.capacity;
            if (progress && done == 1)
                printf("%sremeshed before iteration %u: %u -> %u vertices in %.1f ms\n", progress == 2 ? "\n" : "",
                       (unsigned)it, (unsigned)before, (unsigned)fit.vertex_count, ls_job_now_ms() - tr);
            else if (progress && done == 0)
                printf("%sremesh before iteration %u refused: its result would self-intersect more than the mesh; "
                       "the fit goes on with its %u vertices, lr x %g\n",
                       progress == 2 ? "\n" : "", (unsigned)it, (unsigned)before, (double)s->remesh_lr);
        }
        if (it == settle_at && settle_at < iterations) fit.optim.config.lr *= s->settle_lr;
        if (track_cap > 0 && it % track_every == 0) {
            double t1 = ls_job_now_ms();
            if (!track(p, &fit, it, t1 - t0, arena, r)) return 0;
            r->track_total_ms += ls_job_now_ms() - t1;
            t0 += ls_job_now_ms() - t1; /* the measurement is not the fit's time */
        }
        st = ls_fit_step(&fit, &mon, &d);
        if (st != LS_OK) {
            fprintf(stderr, "largesteps: iteration %u: ", (unsigned)it);
            return ls_job_fail("fit step", st, &d);
        }
        /* a gradient of exact zeros moves nothing: the same state again and again */
        still = all_zero(fit.grad, 3u * (size_t)fit.vertex_count + 3u) ? still + 1u : 0u;
        if (still == LS_JOB_STILL_LIMIT) {
            fprintf(stderr, "largesteps: the gradient has been zero for %u iterations (iteration %u, loss %g): "
                            "nothing moves the mesh. The rendered images do not depend on it: the mesh is outside "
                            "the views or hidden, or the targets are empty or equal to the renders (check the "
                            "cameras, the images' alpha, --shading)\n",
                    (unsigned)LS_JOB_STILL_LIMIT, (unsigned)it, (double)fit.loss);
            return 0;
        }
        r->loss[it] = fit.loss;
        r->ms[it] = ls_job_now_ms() - t0;
        r->iterations = it + 1u;
        if (progress && (progress == 2 || (it + 1) % (iterations / 10u + 1u) == 0 || it + 1 == iterations)) {
            double eta = ls_report_eta_ms(&eta_est, it + 1u, iterations, r->ms[it]);
            printf("%siteration %u/%u  loss %.6g  elapsed %.1f s  eta %.1f s%s", progress == 2 ? "\r" : "",
                   (unsigned)(it + 1), (unsigned)iterations, (double)fit.loss, r->ms[it] / 1000.0, eta / 1000.0,
                   progress == 2 ? "   " : "\n");
            fflush(stdout);
        }
        if (time_budget_ms > 0 && r->ms[it] >= time_budget_ms) break;
    }
    if (s->guard_every > 0 && fit.saved_valid && fit.saved_iteration < fit.iteration) { /* the last stretch */
        uint32_t pairs = 0;
        if (!fit_pairs(&fit, &pairs)) return 0;
        if (pairs > saved_pairs) {
            (void)ls_fit_rollback(&fit);
            r->rollbacks++;
        }
    }
    if (progress == 2) printf("\n");
    if (track_cap > 0 && r->iterations > 0 && !track(p, &fit, r->iterations, r->ms[r->iterations - 1], arena, r)) return 0;
    r->total_ms = r->iterations > 0 ? r->ms[r->iterations - 1] : 0.0;
    r->timing = fit.timing;
    r->remeshes = fit.remeshes;
    r->fit_bytes_end = fit.block.capacity;
    r->factor_nnz = fit.param.f.lp != NULL ? fit.param.f.l_nnz : 0u;
    memcpy(r->sh, fit.sh, sizeof r->sh);
    /* the result outlives the fit: copied above it */
    pos = (ls_real *)ls_arena_alloc(arena, 3u * (size_t)fit.vertex_count, sizeof(ls_real));
    r->result.triangles = (uint32_t *)ls_arena_alloc(arena, 3u * (size_t)fit.face_count, sizeof(uint32_t));
    if (r->result.triangles == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL);
    {
        ls_mesh m;
        st = ls_fit_mesh(&fit, pos, &m);
        if (st != LS_OK) return ls_job_fail("final mesh", st, &d);
        memcpy(r->result.triangles, m.triangles, 3u * (size_t)m.face_count * sizeof(uint32_t));
        r->result.positions = pos;
        r->result.vertex_count = m.vertex_count;
        r->result.face_count = m.face_count;
    }
    if (fit.albedo != NULL) {
        r->albedo = (ls_real *)ls_arena_alloc(arena, 3u * (size_t)fit.vertex_count, sizeof(ls_real));
        if (r->albedo == NULL) return ls_job_fail("memory", LS_ERR_NOMEM, NULL);
        memcpy(r->albedo, fit.albedo, 3u * (size_t)fit.vertex_count * sizeof(ls_real));
    }
    return 1;
}

int ls_job_metrics(const ls_job_problem *p, const ls_mesh *result, ls_arena *arena, ls_distance_report *dist,
                   ls_tangle_report *tangle)
{
    ls_diag d;
    ls_status st;
    if (!p->have_mesh) return 0;
    ls_diag_clear(&d);
    st = job_distance(p, result, arena, dist, &d);
    if (st != LS_OK) return ls_job_fail("distances", st, &d);
    st = ls_tangle_parallel(result, NULL, &p->parallel, ls_job_workers(p), arena, tangle, &d);
    if (st != LS_OK) return ls_job_fail("tangling metrics", st, &d);
    return 1;
}
