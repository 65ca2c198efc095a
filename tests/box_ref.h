/* tests/box_ref.h - shared pieces of the tests' independent exact
 * box-coverage renderers (test_silhouette.c, test_raster_refine.c), in
 * float64: Sutherland-Hodgman half-plane clipping, signed area, convex
 * intersection, orientation, the convex hull, and the two test cameras
 * (orthographic and perspective view-projections as doubles). Static
 * functions: include once per test program. MAXP (vertices per polygon)
 * may be defined before the include. */
#ifndef LS_TEST_BOX_REF_H
#define LS_TEST_BOX_REF_H

#ifndef MAXP
#define MAXP 64
#endif

typedef struct poly {
    int n;
    double x[MAXP], y[MAXP];
} poly;

/* Keeps the part of `in` where (q - p) x (pt - p) * sign >= 0. */
static void clip_half(const poly *in, double px, double py, double qx, double qy, poly *out)
{
    int i;
    out->n = 0;
    for (i = 0; i < in->n; i++) {
        int j = (i + 1) % in->n;
        double si = (qx - px) * (in->y[i] - py) - (qy - py) * (in->x[i] - px);
        double sj = (qx - px) * (in->y[j] - py) - (qy - py) * (in->x[j] - px);
        if (si >= 0 && out->n < MAXP) {
            out->x[out->n] = in->x[i];
            out->y[out->n++] = in->y[i];
        }
        if ((si >= 0) != (sj >= 0) && out->n < MAXP) {
            double t = si / (si - sj);
            out->x[out->n] = in->x[i] + t * (in->x[j] - in->x[i]);
            out->y[out->n++] = in->y[i] + t * (in->y[j] - in->y[i]);
        }
    }
}

static double area(const poly *p)
{
    double a = 0;
    int i;
    for (i = 0; i < p->n; i++) {
        int j = (i + 1) % p->n;
        a += p->x[i] * p->y[j] - p->x[j] * p->y[i];
    }
    return 0.5 * a;
}

/* a n b for convex polygons, b counter-clockwise (positive area). */
static void intersect(const poly *a, const poly *b, poly *out)
{
    poly tmp = *a;
    int i;
    for (i = 0; i < b->n; i++) {
        int j = (i + 1) % b->n;
        clip_half(&tmp, b->x[i], b->y[i], b->x[j], b->y[j], out);
        tmp = *out;
    }
    *out = tmp;
}

static void make_ccw(poly *p)
{
    if (area(p) < 0) {
        int i;
        for (i = 0; i < p->n / 2; i++) {
            double tx = p->x[i], ty = p->y[i];
            p->x[i] = p->x[p->n - 1 - i];
            p->y[i] = p->y[p->n - 1 - i];
            p->x[p->n - 1 - i] = tx;
            p->y[p->n - 1 - i] = ty;
        }
    }
}

/* Convex hull (gift wrapping) of n points, counter-clockwise in (x, y). */
static void hull(const double *x, const double *y, int n, poly *out)
{
    int start = 0, cur, i;
    out->n = 0;
    for (i = 1; i < n; i++)
        if (x[i] < x[start] || (x[i] == x[start] && y[i] < y[start])) start = i;
    cur = start;
    do {
        int next = (cur + 1) % n;
        out->x[out->n] = x[cur];
        out->y[out->n++] = y[cur];
        for (i = 0; i < n; i++) {
            double cr = (x[next] - x[cur]) * (y[i] - y[cur]) - (y[next] - y[cur]) * (x[i] - x[cur]);
            if (cr < 0) next = i;
        }
        cur = next;
    } while (cur != start && out->n < n && out->n < MAXP);
    make_ccw(out);
}

/* Window coordinates (pixels, y down) of an img x img image and NDC depth of world point q. */
static void ref_to_window(const double mvp[16], int img, const double *q, double *x, double *y, double *z)
{
    double c[4];
    int r;
    for (r = 0; r < 4; r++) c[r] = mvp[4 * r] * q[0] + mvp[4 * r + 1] * q[1] + mvp[4 * r + 2] * q[2] + mvp[4 * r + 3];
    *x = (c[0] / c[3] + 1) * 0.5 * img;
    *y = (1 - c[1] / c[3]) * 0.5 * img;
    *z = c[2] / c[3];
}

/* Triangle t clipped at the near plane Z + W >= 0 in clip space, projected
 * to the window, counter-clockwise; returns the mean NDC depth of its
 * corners (an img x img window). *near_inside (if not NULL) is set when a point made by the clip
 * lands inside the image (its discontinuity is not a mesh edge). */
static double ref_tri_window(const double mvp[16], int img, const double *pos, const uint32_t *tri, uint32_t t, poly *out,
                             int *near_inside)
{
    double c[3][4], zs = 0;
    int k, r, n = 0;
    for (k = 0; k < 3; k++) {
        const double *q = pos + 3 * tri[3 * t + k];
        for (r = 0; r < 4; r++) c[k][r] = mvp[4 * r] * q[0] + mvp[4 * r + 1] * q[1] + mvp[4 * r + 2] * q[2] + mvp[4 * r + 3];
    }
    if (near_inside) *near_inside = 0;
    for (k = 0; k < 3; k++) {
        const double *p0 = c[k], *p1 = c[(k + 1) % 3];
        double d0 = p0[2] + p0[3], d1 = p1[2] + p1[3];
        if (d0 >= 0) {
            out->x[n] = (p0[0] / p0[3] + 1) * 0.5 * img;
            out->y[n] = (1 - p0[1] / p0[3]) * 0.5 * img;
            zs += p0[2] / p0[3];
            n++;
        }
        if ((d0 >= 0) != (d1 >= 0)) {
            double s = d0 / (d0 - d1), q[4];
            for (r = 0; r < 4; r++) q[r] = p0[r] + s * (p1[r] - p0[r]);
            out->x[n] = (q[0] / q[3] + 1) * 0.5 * img;
            out->y[n] = (1 - q[1] / q[3]) * 0.5 * img;
            zs += q[2] / q[3];
            if (near_inside && out->x[n] > -1 && out->x[n] < img + 1 && out->y[n] > -1 && out->y[n] < img + 1)
                *near_inside = 1;
            n++;
        }
    }
    out->n = n;
    make_ccw(out);
    return n > 0 ? zs / n : 0;
}

/* The tests' orthographic camera: eye (0.2, 0.3, 3) looking at the origin, [-1, 1]^2, near 0.1, far 10. */
static void ref_camera_ortho(double mvp_out[16])
{
    ls_real view[16], proj[16], mvp[16], eye[3] = {(ls_real)0.2, (ls_real)0.3, 3}, tgt[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    int k;
    ls_camera_look_at(eye, tgt, up, view);
    ls_camera_orthographic(-1, 1, -1, 1, (ls_real)0.1, 10, proj);
    ls_mat4_mul(proj, view, mvp);
    for (k = 0; k < 16; k++) mvp_out[k] = (double)mvp[k];
}

/* The tests' perspective camera: eye (0.4, 0.5, 2.6), vertical fov 0.9, near 0.3, far 20. */
static void ref_camera_persp(double mvp_out[16])
{
    ls_real view[16], proj[16], mvp[16], eye[3] = {(ls_real)0.4, (ls_real)0.5, (ls_real)2.6}, tgt[3] = {0, 0, 0};
    ls_real up[3] = {0, 1, 0};
    int k;
    ls_camera_look_at(eye, tgt, up, view);
    ls_camera_perspective((ls_real)0.9, LS_FOV_Y, 1, (ls_real)0.3, 20, proj);
    ls_mat4_mul(proj, view, mvp);
    for (k = 0; k < 16; k++) mvp_out[k] = (double)mvp[k];
}

#endif /* LS_TEST_BOX_REF_H */
