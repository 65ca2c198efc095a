/* tests/geo_test.h - helpers shared by the BVH, distance and tangle tests:
 * small built-in meshes, fixture loading into a malloc'd arena, an LCG, and
 * the brute-force closest point (every triangle, lowest index on ties). */
#ifndef LS_TEST_GEO_H
#define LS_TEST_GEO_H

#include <stdlib.h>
#include "test.h"
#include "../port/posix/ls_posix.h"

/* 1 under QEMU (LS_TEST_EMULATED=1, set by the Makefile for cross targets):
 * the tests then shrink their brute-force loops. */
static inline int geo_emulated(void)
{
    const char *e = getenv("LS_TEST_EMULATED");
    return e != NULL && e[0] == '1';
}

/* n, or n / 8 (at least 1) under emulation. */
static inline uint32_t geo_scaled(uint32_t n)
{
    return geo_emulated() ? (n / 8u > 0 ? n / 8u : 1u) : n;
}

typedef struct geo_rng {
    uint64_t s;
} geo_rng;

/* Uniform in [0, 1) (test_rng_unit; g->s from test_rng_seed). */
static inline double geo_rand(geo_rng *g)
{
    return test_rng_unit(&g->s);
}

/* The signed volume a closed mesh encloses (divergence theorem), in double:
 * > 0 for outward faces. */
static inline double geo_signed_volume(const ls_mesh *m)
{
    double v = 0.0;
    uint32_t f;
    for (f = 0; f < m->face_count; f++) {
        const ls_real *a = m->positions + 3u * m->triangles[3u * f], *b = m->positions + 3u * m->triangles[3u * f + 1u],
                      *c = m->positions + 3u * m->triangles[3u * f + 2u];
        v += ((double)a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) -
              (double)a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
              (double)a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0])) / 6.0;
    }
    return v;
}

/* A heap arena of n bytes (aligned); free a->base with free(). */
static inline ls_arena *geo_arena(ls_arena *a, size_t n)
{
    void *buf = malloc(n + 8);
    if (buf == NULL || ls_arena_init(a, buf, n) != LS_OK) return NULL;
    return a;
}

/* Reads a file whole into a malloc'd buffer (free it), a gzip file
 * decompressed (ls_posix_read_data). 0 on any failure. */
static inline int geo_read_file(const char *path, unsigned char **data, size_t *bytes)
{
    return ls_posix_read_data(path, data, bytes) == LS_OK;
}

/* Reads a mesh file (".gz" too, see geo_read_file) into the arena; 0 on failure. */
static inline int geo_read(const char *path, ls_arena *a, ls_mesh *m)
{
    unsigned char *d = NULL;
    size_t n = 0;
    ls_status st;
    if (!geo_read_file(path, &d, &n)) return 0;
    st = ls_mesh_read(d, n, LS_MESH_FORMAT_AUTO, a, m, NULL);
    free(d);
    return st == LS_OK;
}

/* A mesh from static arrays, copied into the arena. */
static inline int geo_mesh(ls_arena *a, ls_mesh *m, const double *pos, uint32_t nv, const uint32_t *tri, uint32_t nf)
{
    uint32_t i;
    if (ls_mesh_alloc(m, nv, nf, a) != LS_OK) return 0;
    for (i = 0; i < 3 * nv; i++) m->positions[i] = (ls_real)pos[i];
    for (i = 0; i < 3 * nf; i++) m->triangles[i] = tri[i];
    return 1;
}

/* A UV sphere of radius r centred at c: `rings` latitude bands, `segs`
 * longitude segments, poles shared; outward orientation. Positions from libm
 * (tests may use it). */
static inline int geo_sphere(ls_arena *a, ls_mesh *m, double r, const double c[3], uint32_t rings, uint32_t segs)
{
    uint32_t nv = 2 + (rings - 1) * segs, nf = 2 * segs * (rings - 1), i, j, f = 0;
    const double pi = 3.14159265358979323846;
    if (ls_mesh_alloc(m, nv, nf, a) != LS_OK) return 0;
    m->positions[0] = (ls_real)c[0];
    m->positions[1] = (ls_real)c[1];
    m->positions[2] = (ls_real)(c[2] + r);
    m->positions[3] = (ls_real)c[0];
    m->positions[4] = (ls_real)c[1];
    m->positions[5] = (ls_real)(c[2] - r);
    for (i = 1; i < rings; i++) {
        double th = pi * (double)i / (double)rings;
        for (j = 0; j < segs; j++) {
            double ph = 2 * pi * (double)j / (double)segs;
            ls_real *p = m->positions + 3 * (2 + (i - 1) * segs + j);
            p[0] = (ls_real)(c[0] + r * sin(th) * cos(ph));
            p[1] = (ls_real)(c[1] + r * sin(th) * sin(ph));
            p[2] = (ls_real)(c[2] + r * cos(th));
        }
    }
#define GEO_V(i, j) (2 + ((i) - 1) * segs + ((j) % segs))
    for (j = 0; j < segs; j++) {
        uint32_t *t = m->triangles + 3 * f++;
        t[0] = 0;
        t[1] = GEO_V(1, j);
        t[2] = GEO_V(1, j + 1);
    }
    for (i = 1; i + 1 < rings; i++) {
        for (j = 0; j < segs; j++) {
            uint32_t *t = m->triangles + 3 * f++;
            t[0] = GEO_V(i, j);
            t[1] = GEO_V(i + 1, j);
            t[2] = GEO_V(i + 1, j + 1);
            t = m->triangles + 3 * f++;
            t[0] = GEO_V(i, j);
            t[1] = GEO_V(i + 1, j + 1);
            t[2] = GEO_V(i, j + 1);
        }
    }
    for (j = 0; j < segs; j++) {
        uint32_t *t = m->triangles + 3 * f++;
        t[0] = 1;
        t[1] = GEO_V(rings - 1, j + 1);
        t[2] = GEO_V(rings - 1, j);
    }
#undef GEO_V
    return f == nf;
}

/* Brute force: the minimum over every triangle of (dist2, index). */
static inline void geo_brute_closest(const ls_mesh *m, const ls_real p[3], ls_bvh_hit *hit)
{
    uint32_t f;
    memset(hit, 0, sizeof *hit);
    hit->face = UINT32_MAX;
    for (f = 0; f < m->face_count; f++) {
        const uint32_t *t = m->triangles + 3 * f;
        ls_real q[3], b[3], d2;
        ls_closest_point_triangle(p, m->positions + 3 * t[0], m->positions + 3 * t[1], m->positions + 3 * t[2], q, b, &d2);
        if (hit->face == UINT32_MAX || d2 < hit->dist2) {
            hit->face = f;
            hit->dist2 = d2;
            memcpy(hit->point, q, sizeof q);
            memcpy(hit->bary, b, sizeof b);
        }
    }
}

#endif /* LS_TEST_GEO_H */
