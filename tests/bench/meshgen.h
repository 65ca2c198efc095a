/* tests/bench/meshgen.h - test and benchmark meshes for the solver: icospheres,
 * grids, a tiny OBJ reader, and M = I + lambda L (uniform Laplacian L = D - A)
 * as triplets. Test-side code (malloc, stdio); the library's laplacian and
 * OBJ modules are separate issues, so these are deliberately independent. */
#ifndef LS_TEST_MESHGEN_H
#define LS_TEST_MESHGEN_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include <math.h>

#if defined(__GNUC__) || defined(__clang__)
#define MG_FN static __attribute__((unused))
#else
#define MG_FN static
#endif

typedef struct tmesh {
    uint32_t nv, nf;
    double *pos;   /* 3 nv */
    uint32_t *tri; /* 3 nf */
} tmesh;

MG_FN void tmesh_free(tmesh *m)
{
    free(m->pos);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

/* midpoint cache: open addressing on the edge key */
typedef struct mg_map {
    uint64_t *key;
    uint32_t *val;
    size_t mask;
} mg_map;

MG_FN uint32_t mg_midpoint(mg_map *mp, tmesh *m, uint32_t a, uint32_t b)
{
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    uint64_t k = ((uint64_t)lo << 32) | hi, h = k * 0x9E3779B97F4A7C15ull;
    size_t s = (size_t)(h >> 20) & mp->mask;
    while (mp->key[s] != UINT64_MAX) {
        if (mp->key[s] == k) return mp->val[s];
        s = (s + 1) & mp->mask;
    }
    mp->key[s] = k;
    mp->val[s] = m->nv;
    {
        double *p = m->pos + 3 * (size_t)m->nv, r;
        int c;
        for (c = 0; c < 3; c++) p[c] = 0.5 * (m->pos[3 * (size_t)a + c] + m->pos[3 * (size_t)b + c]);
        r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (c = 0; c < 3; c++) p[c] /= r;
    }
    return m->nv++;
}

/* icosphere with 10 * 4^level + 2 vertices */
MG_FN tmesh icosphere(int level)
{
    static const double t0 = 1.6180339887498949;
    static const int ico_f[60] = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
                                  11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8,
                                  3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    double v[36] = {-1, t0, 0, 1, t0, 0, -1, -t0, 0, 1, -t0, 0, 0, -1, t0, 0, 1, t0,
                    0, -1, -t0, 0, 1, -t0, t0, 0, -1, t0, 0, 1, -t0, 0, -1, -t0, 0, 1};
    tmesh m;
    size_t nvmax = 10 * ((size_t)1 << (2 * level)) + 2, nfmax = 20 * ((size_t)1 << (2 * level));
    int l, i;
    m.pos = (double *)malloc(3 * nvmax * sizeof(double));
    m.tri = (uint32_t *)malloc(3 * nfmax * sizeof(uint32_t));
    m.nv = 12;
    m.nf = 20;
    for (i = 0; i < 12; i++) {
        double r = sqrt(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
        m.pos[3 * i] = v[3 * i] / r;
        m.pos[3 * i + 1] = v[3 * i + 1] / r;
        m.pos[3 * i + 2] = v[3 * i + 2] / r;
    }
    for (i = 0; i < 60; i++) m.tri[i] = (uint32_t)ico_f[i];
    for (l = 0; l < level; l++) {
        mg_map mp;
        size_t cap = 1, f, nf = m.nf;
        uint32_t *nt = (uint32_t *)malloc(12 * nf * sizeof(uint32_t));
        while (cap < 4 * 3 * nf) cap <<= 1;
        mp.key = (uint64_t *)malloc(cap * sizeof(uint64_t));
        mp.val = (uint32_t *)malloc(cap * sizeof(uint32_t));
        mp.mask = cap - 1;
        memset(mp.key, 0xFF, cap * sizeof(uint64_t));
        for (f = 0; f < nf; f++) {
            uint32_t a = m.tri[3 * f], b = m.tri[3 * f + 1], c = m.tri[3 * f + 2];
            uint32_t ab = mg_midpoint(&mp, &m, a, b), bc = mg_midpoint(&mp, &m, b, c), ca = mg_midpoint(&mp, &m, c, a);
            uint32_t q[12];
            q[0] = a; q[1] = ab; q[2] = ca;
            q[3] = b; q[4] = bc; q[5] = ab;
            q[6] = c; q[7] = ca; q[8] = bc;
            q[9] = ab; q[10] = bc; q[11] = ca;
            memcpy(nt + 12 * f, q, sizeof q);
        }
        free(mp.key);
        free(mp.val);
        free(m.tri);
        m.tri = nt;
        m.nf = (uint32_t)(4 * nf);
    }
    return m;
}

/* w x h vertex grid on [0,1]^2, two triangles per cell */
MG_FN tmesh gridmesh(uint32_t w, uint32_t h)
{
    tmesh m;
    uint32_t x, y, f = 0;
    m.nv = w * h;
    m.nf = 2 * (w - 1) * (h - 1);
    m.pos = (double *)malloc(3 * (size_t)m.nv * sizeof(double));
    m.tri = (uint32_t *)malloc(3 * (size_t)m.nf * sizeof(uint32_t));
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            m.pos[3 * (size_t)(y * w + x)] = (double)x / (double)(w - 1);
            m.pos[3 * (size_t)(y * w + x) + 1] = (double)y / (double)(h - 1);
            m.pos[3 * (size_t)(y * w + x) + 2] = 0;
        }
    for (y = 0; y + 1 < h; y++)
        for (x = 0; x + 1 < w; x++) {
            uint32_t a = y * w + x, b = a + 1, c = a + w, d = c + 1;
            m.tri[3 * f] = a; m.tri[3 * f + 1] = b; m.tri[3 * f + 2] = d; f++;
            m.tri[3 * f] = a; m.tri[3 * f + 1] = d; m.tri[3 * f + 2] = c; f++;
        }
    return m;
}

/* minimal OBJ: "v x y z" and "f a b c ..." (a/b/c forms, fans for polygons) */
MG_FN int obj_read(const char *path, tmesh *m)
{
    FILE *fp = fopen(path, "rb");
    char line[1024];
    size_t cv = 1024, cf = 1024;
    memset(m, 0, sizeof *m);
    if (fp == NULL) return 0;
    m->pos = (double *)malloc(3 * cv * sizeof(double));
    m->tri = (uint32_t *)malloc(3 * cf * sizeof(uint32_t));
    while (fgets(line, sizeof line, fp)) {
        if (line[0] == 'v' && line[1] == ' ') {
            if (m->nv == cv) {
                cv *= 2;
                m->pos = (double *)realloc(m->pos, 3 * cv * sizeof(double));
            }
            sscanf(line + 2, "%lf %lf %lf", &m->pos[3 * (size_t)m->nv], &m->pos[3 * (size_t)m->nv + 1],
                   &m->pos[3 * (size_t)m->nv + 2]);
            m->nv++;
        } else if (line[0] == 'f' && line[1] == ' ') {
            long idx[64];
            int k = 0, i;
            char *s = line + 2, *e;
            while (k < 64) {
                long v = strtol(s, &e, 10);
                if (e == s) break;
                idx[k++] = v < 0 ? (long)m->nv + v : v - 1;
                s = e;
                while (*s && *s != ' ' && *s != '\t') s++;
            }
            for (i = 1; i + 1 < k; i++) {
                if (m->nf == cf) {
                    cf *= 2;
                    m->tri = (uint32_t *)realloc(m->tri, 3 * cf * sizeof(uint32_t));
                }
                m->tri[3 * (size_t)m->nf] = (uint32_t)idx[0];
                m->tri[3 * (size_t)m->nf + 1] = (uint32_t)idx[i];
                m->tri[3 * (size_t)m->nf + 2] = (uint32_t)idx[i + 1];
                m->nf++;
            }
        }
    }
    fclose(fp);
    return m->nv > 0;
}

MG_FN int mg_cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* Unique undirected edges (i < j) of the mesh, sorted; returns the count. */
MG_FN size_t mesh_edges(const tmesh *m, uint64_t **out)
{
    size_t f, n = 0, w = 0, i;
    uint64_t *e = (uint64_t *)malloc(3 * (size_t)m->nf * sizeof(uint64_t));
    for (f = 0; f < m->nf; f++) {
        int c;
        for (c = 0; c < 3; c++) {
            uint32_t a = m->tri[3 * f + (size_t)c], b = m->tri[3 * f + (size_t)((c + 1) % 3)];
            uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
            if (lo != hi) e[n++] = ((uint64_t)lo << 32) | hi;
        }
    }
    qsort(e, n, sizeof(uint64_t), mg_cmp_u64);
    for (i = 0; i < n; i++)
        if (w == 0 || e[w - 1] != e[i]) e[w++] = e[i];
    *out = e;
    return w;
}

/* Triplets of M = I + lambda (D - A): upper triangle (full = 0) or both.
 * Arrays are malloc'ed; returns the count. Values computed in double, then
 * rounded once to T (ls_real). */
typedef struct mtrip {
    size_t count;
    uint32_t n, *r, *c;
    double *v;
} mtrip;

MG_FN mtrip laplacian_system(const tmesh *m, double lambda, int full)
{
    mtrip t;
    uint64_t *e;
    size_t ne = mesh_edges(m, &e), i, k = 0;
    uint32_t *deg = (uint32_t *)calloc(m->nv, sizeof(uint32_t));
    t.n = m->nv;
    t.count = (full ? 2 * ne : ne) + m->nv;
    t.r = (uint32_t *)malloc(t.count * sizeof(uint32_t));
    t.c = (uint32_t *)malloc(t.count * sizeof(uint32_t));
    t.v = (double *)malloc(t.count * sizeof(double));
    for (i = 0; i < ne; i++) {
        uint32_t a = (uint32_t)(e[i] >> 32), b = (uint32_t)e[i];
        deg[a]++;
        deg[b]++;
        t.r[k] = a; t.c[k] = b; t.v[k++] = -lambda;
        if (full) { t.r[k] = b; t.c[k] = a; t.v[k++] = -lambda; }
    }
    for (i = 0; i < m->nv; i++) {
        t.r[k] = (uint32_t)i;
        t.c[k] = (uint32_t)i;
        t.v[k++] = 1.0 + lambda * (double)deg[i];
    }
    free(e);
    free(deg);
    return t;
}

MG_FN void mtrip_free(mtrip *t)
{
    free(t->r);
    free(t->c);
    free(t->v);
}

#endif /* LS_TEST_MESHGEN_H */
