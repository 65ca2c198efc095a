/* grid_solve.c - M x = b on a texture grid by cosine / Fourier transforms:
 * an iterative radix-2 FFT, Bluestein's chirp z-transform for other lengths,
 * Makhoul's cosine transform through one FFT, two real lines per complex FFT. */
#include <largesteps/grid_solve.h>
#include <largesteps/laplacian.h>
#include <largesteps/math.h>
#include <string.h>

#define PI_R ((ls_real)3.14159265358979323846)

/* ---- sizes and tables ------------------------------------------------------ */

static uint32_t pow2_at_least(uint32_t n)
{
    uint32_t p = 1u;
    while (p < n) p <<= 1;
    return p;
}

/* The FFT length of n points: n itself when a power of two, else the
 * Bluestein length (a power of two >= 2n - 1). */
static uint32_t fft_length(uint32_t n)
{
    if ((n & (n - 1u)) == 0) return n;
    return pow2_at_least(2u * n - 1u);
}

/* Takes `count` reals: added to *s when sizing, else from the arena
 * (NULL when it does not fit). One function for both, so that the query
 * and the allocation cannot drift apart. */
static ls_real *take(ls_arena *arena, ls_size *s, size_t count, int *ok)
{
    ls_real *r;
    if (s != NULL) {
        ls_size_add(s, count, sizeof(ls_real));
        return NULL;
    }
    r = (ls_real *)ls_arena_alloc(arena, count, sizeof(ls_real));
    if (r == NULL) *ok = 0;
    return r;
}

/* Lays out one direction's tables (sizing when s != NULL). */
static void plan_layout(ls_grid_fft *f, uint32_t n, uint32_t dct, ls_arena *arena, ls_size *s, int *ok)
{
    memset(f, 0, sizeof *f);
    f->n = n;
    f->p = fft_length(n);
    f->dct = dct;
    f->tw = take(arena, s, f->p, ok); /* p/2 complex */
    if (f->p != n) {
        f->chirp = take(arena, s, 2u * (size_t)n, ok);
        f->filt = take(arena, s, 2u * (size_t)f->p, ok);
    }
    if (dct) f->post = take(arena, s, 2u * (size_t)n, ok);
    f->mu = take(arena, s, n, ok);
}

/* Columns gathered at once by the y pass (rows of the block are read
 * contiguously instead of one texel per row and page). */
#define GRID_BLOCK 8u

/* The solver's layout (g's width, height, wrap and k set): both directions,
 * the line buffer, the Bluestein work buffer and the column block. */
static void solver_layout(ls_grid_solver *g, ls_arena *arena, ls_size *s, int *ok)
{
    uint32_t w = g->width, h = g->height, big = w > h ? w : h, pw = 0;
    plan_layout(&g->fx, w, !g->wrap, arena, s, ok);
    plan_layout(&g->fy, h, 1u, arena, s, ok);
    g->line = take(arena, s, 2u * (size_t)big, ok);
    if (g->fx.p != w) pw = g->fx.p;
    if (g->fy.p != h && g->fy.p > pw) pw = g->fy.p;
    g->work = pw != 0 ? take(arena, s, 2u * (size_t)pw, ok) : NULL;
    g->block_w = w < GRID_BLOCK ? w : GRID_BLOCK;
    g->block = take(arena, s, (size_t)g->block_w * g->k * h, ok);
}

/* Checks the shape and starts *g: zero, the shape, weight 0 (M = I). */
static ls_status shape_init(ls_grid_solver *g, uint32_t width, uint32_t height, uint32_t wrap, uint32_t k)
{
    if (width == 0 || height == 0 || k == 0 || width > LS_GRID_MAX_SIDE || height > LS_GRID_MAX_SIDE)
        return LS_ERR_INVALID;
    if ((uint64_t)width * height * k > (uint64_t)UINT32_MAX) return LS_ERR_TOO_LARGE;
    memset(g, 0, sizeof *g);
    g->width = width;
    g->height = height;
    g->wrap = wrap != 0 && width >= 3u;
    g->k = k;
    g->form = LS_SYSTEM_LAMBDA;
    g->identity = 1;
    g->weight = (ls_real)0;
    g->shift = (ls_real)1;
    return LS_OK;
}

ls_status ls_grid_solver_bytes(uint32_t width, uint32_t height, uint32_t wrap, uint32_t k, size_t *bytes)
{
    ls_grid_solver g;
    ls_size s;
    int ok = 1;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    st = shape_init(&g, width, height, wrap, k);
    if (st != LS_OK) return st;
    ls_size_init(&s);
    solver_layout(&g, NULL, &s, &ok);
    return ls_size_get(&s, bytes);
}

/* ---- the FFT ---------------------------------------------------------------- */

/* Two radix-2 stages at once (butterfly lengths len and 2 len) on the
 * bit-reversed array: groups of four points, half the passes over z.
 * sgn = 1 forward, -1 inverse (conjugate twiddles). */
LS_NO_VECTORIZE static void stage_pair(const ls_real *tw, size_t p, ls_real *z, size_t len, ls_real sgn)
{
    size_t h = len >> 1, s1 = p / len, s2 = s1 >> 1, base, j;
    for (base = 0; base < p; base += 2u * len)
        for (j = 0; j < h; j++) {
            ls_real *x0 = z + 2u * (base + j), *x1 = x0 + 2u * h, *x2 = x0 + 2u * len, *x3 = x2 + 2u * h;
            ls_real w1r = tw[2u * (j * s1)], w1i = sgn * tw[2u * (j * s1) + 1u];
            ls_real w2r = tw[2u * (j * s2)], w2i = sgn * tw[2u * (j * s2) + 1u];
            ls_real tr = w1r * x1[0] - w1i * x1[1], ti = w1r * x1[1] + w1i * x1[0];
            ls_real a0r = x0[0] + tr, a0i = x0[1] + ti, a1r = x0[0] - tr, a1i = x0[1] - ti;
            ls_real ur = w1r * x3[0] - w1i * x3[1], ui = w1r * x3[1] + w1i * x3[0];
            ls_real a2r = x2[0] + ur, a2i = x2[1] + ui, a3r = x2[0] - ur, a3i = x2[1] - ui;
            /* second stage: a0, a2 with w2; a1, a3 with w2 e^{-+i pi/2} */
            tr = w2r * a2r - w2i * a2i;
            ti = w2r * a2i + w2i * a2r;
            ur = w2r * a3r - w2i * a3i;
            ui = w2r * a3i + w2i * a3r;
            x0[0] = a0r + tr;
            x0[1] = a0i + ti;
            x2[0] = a0r - tr;
            x2[1] = a0i - ti;
            x1[0] = a1r + sgn * ui;
            x1[1] = a1i - sgn * ur;
            x3[0] = a1r - sgn * ui;
            x3[1] = a1i + sgn * ur;
        }
}

/* In-place complex FFT of length p (a power of two) on (re, im) pairs:
 * sign -1 in the exponent (forward), +1 when inverse (no 1/p). Bit
 * reversal, one plain radix-2 stage when log2 p is odd, then pairs of
 * stages. */
LS_NO_VECTORIZE static void radix2(const ls_real *tw, size_t p, ls_real *z, int inverse)
{
    size_t i, j, len = 2u, logp = 0;
    ls_real sgn = inverse ? (ls_real)-1 : (ls_real)1;
    for (i = 1, j = 0; i < p; i++) { /* bit reversal */
        size_t bit = p >> 1;
        for (; (j & bit) != 0; bit >>= 1) j ^= bit;
        j ^= bit;
        if (i < j) {
            ls_real r = z[2u * i], m = z[2u * i + 1u];
            z[2u * i] = z[2u * j];
            z[2u * i + 1u] = z[2u * j + 1u];
            z[2u * j] = r;
            z[2u * j + 1u] = m;
        }
    }
    while (((size_t)1 << logp) < p) logp++;
    if ((logp & 1u) != 0) { /* the length-2 stage: twiddle 1 */
        for (i = 0; i < p; i += 2u) {
            ls_real *u = z + 2u * i, *v = u + 2u, r = v[0], m = v[1];
            v[0] = u[0] - r;
            v[1] = u[1] - m;
            u[0] = u[0] + r;
            u[1] = u[1] + m;
        }
        len = 4u;
    }
    for (; len < p; len <<= 2) stage_pair(tw, p, z, len, sgn);
}

/* (a + ib)(c + id) into out[0], out[1] (out may alias neither input). */
static void cmul(ls_real a, ls_real b, ls_real c, ls_real d, ls_real *out)
{
    out[0] = a * c - b * d;
    out[1] = a * d + b * c;
}

/* In-place DFT of length f->n: forward (e^{-2 pi i jk/n}) or inverse
 * (e^{+...}, no 1/n). Bluestein: X_k = c_k sum_j (x_j c_j) conj(c_{k-j}),
 * c_j = e^{-i pi j^2 / n}, the sum a cyclic convolution of length p; the
 * inverse is the conjugate of the forward transform of the conjugate. */
LS_NO_VECTORIZE static void dft(const ls_grid_fft *f, ls_real *z, ls_real *work, int inverse)
{
    size_t j, n = f->n, p = f->p;
    ls_real sg = inverse ? (ls_real)-1 : (ls_real)1, t[2];
    if (p == n) {
        radix2(f->tw, p, z, inverse);
        return;
    }
    for (j = 0; j < n; j++) cmul(z[2u * j], sg * z[2u * j + 1u], f->chirp[2u * j], f->chirp[2u * j + 1u], work + 2u * j);
    memset(work + 2u * n, 0, 2u * (p - n) * sizeof(ls_real));
    radix2(f->tw, p, work, 0);
    for (j = 0; j < p; j++) {
        cmul(work[2u * j], work[2u * j + 1u], f->filt[2u * j], f->filt[2u * j + 1u], t);
        work[2u * j] = t[0];
        work[2u * j + 1u] = t[1];
    }
    radix2(f->tw, p, work, 1);
    for (j = 0; j < n; j++) {
        cmul(work[2u * j], work[2u * j + 1u], f->chirp[2u * j], f->chirp[2u * j + 1u], t);
        z[2u * j] = t[0];
        z[2u * j + 1u] = sg * t[1];
    }
}

/* sin and cos of pi * num / den (0 <= num <= 2 den). */
static void sincos_pi(uint64_t num, uint64_t den, ls_real *s, ls_real *c)
{
    ls_real a = PI_R * ((ls_real)num / (ls_real)den);
    LS_RSINCOS(a, s, c);
}

static void plan_fill(ls_grid_fft *f)
{
    size_t j, n = f->n, p = f->p;
    for (j = 0; j < p / 2u; j++) {
        ls_real s, c;
        sincos_pi(2u * (uint64_t)j, p, &s, &c);
        f->tw[2u * j] = c;
        f->tw[2u * j + 1u] = -s;
    }
    if (p != n) {
        ls_real inv_p = (ls_real)1 / (ls_real)p; /* exact: p is a power of two */
        for (j = 0; j < n; j++) {
            ls_real s, c;
            sincos_pi(((uint64_t)j * j) % (2u * (uint64_t)n), n, &s, &c);
            f->chirp[2u * j] = c;
            f->chirp[2u * j + 1u] = -s;
        }
        memset(f->filt, 0, 2u * (size_t)p * sizeof(ls_real));
        for (j = 0; j < n; j++) {
            f->filt[2u * j] = f->chirp[2u * j];
            f->filt[2u * j + 1u] = -f->chirp[2u * j + 1u];
            if (j > 0) {
                f->filt[2u * (p - j)] = f->chirp[2u * j];
                f->filt[2u * (p - j) + 1u] = -f->chirp[2u * j + 1u];
            }
        }
        radix2(f->tw, p, f->filt, 0);
        for (j = 0; j < 2u * p; j++) f->filt[j] *= inv_p;
    }
    if (f->dct) {
        for (j = 0; j < n; j++) {
            ls_real s, c;
            sincos_pi(j, 2u * (uint64_t)n, &s, &c);
            f->post[2u * j] = c;
            f->post[2u * j + 1u] = -s;
            /* 4 sin^2(pi k / 2n) = 2 - 2 cos(pi k / n) without cancellation */
            f->mu[j] = (ls_real)4 * s * s;
        }
    } else {
        for (j = 0; j < n; j++) {
            size_t m = (j + 1u) / 2u; /* packed index -> frequency */
            ls_real s, c;
            sincos_pi(m, n, &s, &c);
            f->mu[j] = (ls_real)4 * s * s;
        }
    }
}

ls_status ls_grid_solver_init(ls_grid_solver *g, uint32_t width, uint32_t height, uint32_t wrap, uint32_t k,
                              ls_arena *arena)
{
    ls_arena_mark mark;
    ls_grid_solver q;
    int ok = 1;
    ls_status st;
    if (g == NULL || arena == NULL) return LS_ERR_INVALID;
    st = shape_init(&q, width, height, wrap, k);
    if (st != LS_OK) return st;
    mark = ls_arena_save(arena);
    solver_layout(&q, arena, NULL, &ok);
    if (!ok) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    plan_fill(&q.fx);
    plan_fill(&q.fy);
    *g = q;
    return LS_OK;
}

ls_status ls_grid_solver_set_weight(ls_grid_solver *g, uint32_t form, ls_real weight, ls_diag *diag)
{
    ls_diag_clear(diag);
    if (g == NULL || g->fx.mu == NULL)
        return ls_diag_set(diag, LS_ERR_INVALID, "g: NULL or not initialized (ls_grid_solver_init first)", LS_DIAG_NO_INDEX);
    if (form != LS_SYSTEM_LAMBDA && form != LS_SYSTEM_ALPHA)
        return ls_diag_set(diag, LS_ERR_INVALID, "form: allowed LS_SYSTEM_LAMBDA or LS_SYSTEM_ALPHA", LS_DIAG_NO_INDEX);
    if (!(weight >= (ls_real)0) || !LS_RISFINITE(weight) || (form == LS_SYSTEM_ALPHA && !(weight < (ls_real)1))) {
        (void)ls_diag_set(diag, LS_ERR_INVALID,
                          form == LS_SYSTEM_ALPHA ? "weight: alpha in [0, 1)" : "weight: lambda finite and >= 0",
                          LS_DIAG_NO_INDEX);
        if (diag != NULL) {
            diag->has_value = 1;
            diag->value = weight;
        }
        return LS_ERR_INVALID;
    }
    g->form = form;
    g->weight = weight;
    g->shift = form == LS_SYSTEM_ALPHA ? (ls_real)1 - weight : (ls_real)1;
    g->identity = weight == (ls_real)0;
    return LS_OK;
}

/* ---- line transforms -------------------------------------------------------- */

/* Position of input sample i in Makhoul's reordering: evens ascending, then
 * odds descending. */
static size_t makhoul(size_t i, size_t n)
{
    return (i & 1u) != 0 ? n - 1u - i / 2u : i / 2u;
}

/* Forward transform of the real lines a and b (b may be NULL: a zero line),
 * element j at a[j * es]: cosine (DCT-II) or real Fourier (packed
 * Re X0, Re X1, Im X1, ..., Re X_{n/2} for even n), in place. One complex
 * FFT of z = a + i b; the spectra are split by Hermitian symmetry. */
static void forward_pair(const ls_grid_fft *f, ls_real *z, ls_real *work, ls_real *a, ls_real *b, size_t es)
{
    size_t i, n = f->n, kmax = f->dct ? n - 1u : n / 2u;
    const ls_real half = (ls_real)0.5;
    for (i = 0; i < n; i++) {
        size_t d = f->dct ? makhoul(i, n) : i;
        z[2u * d] = a[i * es];
        z[2u * d + 1u] = b != NULL ? b[i * es] : (ls_real)0;
    }
    dft(f, z, work, 0);
    for (i = 0; i <= kmax; i++) {
        size_t m = i == 0 ? 0 : n - i;
        ls_real zr = z[2u * i], zi = z[2u * i + 1u], yr = z[2u * m], yi = z[2u * m + 1u];
        ls_real ar = (zr + yr) * half, ai = (zi - yi) * half, br = (zi + yi) * half, bi = (yr - zr) * half;
        if (f->dct) {
            ls_real pr = f->post[2u * i], pi = f->post[2u * i + 1u];
            a[i * es] = pr * ar - pi * ai;
            if (b != NULL) b[i * es] = pr * br - pi * bi;
        } else if (i == 0 || 2u * i == n) {
            size_t q = i == 0 ? 0 : (size_t)n - 1u;
            a[q * es] = ar;
            if (b != NULL) b[q * es] = br;
        } else {
            a[(2u * (size_t)i - 1u) * es] = ar;
            a[2u * (size_t)i * es] = ai;
            if (b != NULL) {
                b[(2u * (size_t)i - 1u) * es] = br;
                b[2u * (size_t)i * es] = bi;
            }
        }
    }
}

/* Inverse of forward_pair without the 1/n: z = V_a + i V_b with V the
 * line's spectrum (cosine: V_i = conj(post_i) (C_i - i C_{n-i}), C_n = 0;
 * Fourier: the Hermitian extension of the packed values), one inverse FFT,
 * the real part to a and the imaginary part to b. */
LS_NO_VECTORIZE static void inverse_pair(const ls_grid_fft *f, ls_real *z, ls_real *work, ls_real *a, ls_real *b, size_t es)
{
    size_t i, n = f->n;
    const ls_real zero = (ls_real)0;
    if (f->dct) {
        for (i = 0; i < n; i++) {
            size_t q = i == 0 ? 0 : (size_t)(n - i) * es;
            ls_real pr = f->post[2u * i], pi = -f->post[2u * i + 1u];
            ls_real ar = a[i * es], ai = i == 0 ? zero : -a[q];
            ls_real br = b != NULL ? b[i * es] : zero, bi = i == 0 || b == NULL ? zero : -b[q];
            /* z = (p a) + i (p b), p = conj(post_i) */
            z[2u * i] = (pr * ar - pi * ai) - (pr * bi + pi * br);
            z[2u * i + 1u] = (pr * ai + pi * ar) + (pr * br - pi * bi);
        }
    } else {
        for (i = 0; i < n; i++) {
            size_t m = 2u * i <= n ? i : n - i;
            size_t qr = m == 0 ? 0 : 2u * m == n ? (size_t)n - 1u : 2u * (size_t)m - 1u;
            int has_im = m != 0 && 2u * m != n;
            ls_real sg = 2u * i <= n ? (ls_real)1 : (ls_real)-1;
            ls_real ar = a[qr * es], ai = has_im ? sg * a[(qr + 1u) * es] : zero;
            ls_real br = b != NULL ? b[qr * es] : zero, bi = has_im && b != NULL ? sg * b[(qr + 1u) * es] : zero;
            z[2u * i] = ar - bi;
            z[2u * i + 1u] = ai + br;
        }
    }
    dft(f, z, work, 1);
    for (i = 0; i < n; i++) {
        size_t d = f->dct ? makhoul(i, n) : i;
        a[i * es] = z[2u * d];
        if (b != NULL) b[i * es] = z[2u * d + 1u];
    }
}

/* Transforms every row (dir 0) or column (dir 1) of every channel, two
 * neighbouring lines of one channel at a time (the channels of a line pair
 * one after the other: they share cache lines). */
static void lines_pair(ls_grid_solver *g, const ls_grid_fft *f, ls_real *a, ls_real *b, size_t es, int inverse)
{
    if (inverse)
        inverse_pair(f, g->line, g->work, a, b, es);
    else
        forward_pair(f, g->line, g->work, a, b, es);
}

/* The x pass: every row of every channel, two neighbouring rows of one
 * channel at a time. */
static void pass_x(ls_grid_solver *g, ls_real *x, int inverse)
{
    size_t k = g->k, ls = (size_t)g->width * k;
    uint32_t c, i;
    for (i = 0; i < g->height; i += 2u)
        for (c = 0; c < g->k; c++) {
            ls_real *a = x + (size_t)i * ls + c;
            lines_pair(g, &g->fx, a, i + 1u < g->height ? a + ls : NULL, k, inverse);
        }
}

/* The y pass: blocks of block_w columns copied to g->block (column-major,
 * channel by channel), two neighbouring columns of one channel at a time,
 * copied back. */
static void pass_y(ls_grid_solver *g, ls_real *x, int inverse)
{
    size_t k = g->k, h = g->height, wk = (size_t)g->width * k, y, q;
    uint32_t x0, bx, c;
    ls_real *blk = g->block;
    for (x0 = 0; x0 < g->width; x0 += g->block_w) {
        uint32_t nb = g->width - x0 < g->block_w ? g->width - x0 : g->block_w;
        size_t nq = (size_t)nb * k;
        for (y = 0; y < h; y++) {
            const ls_real *row = x + y * wk + (size_t)x0 * k;
            for (q = 0; q < nq; q++) blk[q * h + y] = row[q];
        }
        for (bx = 0; bx < nb; bx += 2u)
            for (c = 0; c < g->k; c++) {
                ls_real *a = blk + ((size_t)bx * k + c) * h;
                lines_pair(g, &g->fy, a, bx + 1u < nb ? a + k * h : NULL, 1, inverse);
            }
        for (y = 0; y < h; y++) {
            ls_real *row = x + y * wk + (size_t)x0 * k;
            for (q = 0; q < nq; q++) row[q] = blk[q * h + y];
        }
    }
}

/* 1 when every value is finite: v * 0 is (+-)0 for a finite v and NaN for a
 * NaN or an infinity, and a NaN stays in a sum. Four sums break the
 * dependency chain; no branch or call per value (this runs on every solve). */
static int all_finite(const ls_real *v, size_t count)
{
    const ls_real zero = (ls_real)0;
    ls_real s0 = zero, s1 = zero, s2 = zero, s3 = zero;
    size_t i = 0;
    for (; i + 4u <= count; i += 4u) {
        s0 += v[i] * zero;
        s1 += v[i + 1u] * zero;
        s2 += v[i + 2u] * zero;
        s3 += v[i + 3u] * zero;
    }
    for (; i < count; i++) s0 += v[i] * zero;
    return (s0 + s1) + (s2 + s3) == zero;
}

/* Solves M x1 = b and, when x2 != NULL, M^2 x2 = b: one forward transform
 * of b (in x1), the spectrum divided once (x1) and twice (x2), and an
 * inverse transform of each. x1's operations are those of a lone solve. */
static ls_status solve_powers(ls_grid_solver *g, const ls_real *b, ls_real *x1, ls_real *x2)
{
    size_t n, nk, c;
    uint32_t ix, iy;
    ls_real nr;
    n = (size_t)g->width * g->height;
    nk = n * g->k;
    if (!all_finite(b, nk)) return LS_ERR_NONFINITE;
    if (x1 != b) memmove(x1, b, nk * sizeof(ls_real));
    if (g->identity) {
        if (x2 != NULL) memcpy(x2, x1, nk * sizeof(ls_real));
        return LS_OK;
    }
    pass_x(g, x1, 0);
    pass_y(g, x1, 0);
    nr = (ls_real)n;
    for (iy = 0; iy < g->height; iy++)
        for (ix = 0; ix < g->width; ix++) {
            size_t at = ((size_t)iy * g->width + ix) * g->k;
            ls_real *v = x1 + at, d = g->shift + g->weight * (g->fx.mu[ix] + g->fy.mu[iy]);
            ls_real r = (ls_real)1 / (d * nr);
            if (x2 != NULL) {
                ls_real r2 = (ls_real)1 / ((d * d) * nr);
                for (c = 0; c < g->k; c++) x2[at + c] = v[c] * r2;
            }
            for (c = 0; c < g->k; c++) v[c] *= r;
        }
    pass_y(g, x1, 1);
    pass_x(g, x1, 1);
    if (x2 != NULL) {
        pass_y(g, x2, 1);
        pass_x(g, x2, 1);
    }
    if (!all_finite(x1, nk) || (x2 != NULL && !all_finite(x2, nk))) {
        memset(x1, 0, nk * sizeof(ls_real));
        if (x2 != NULL) memset(x2, 0, nk * sizeof(ls_real));
        return LS_ERR_NONFINITE;
    }
    return LS_OK;
}

ls_status ls_grid_solver_solve(ls_grid_solver *g, const ls_real *b, ls_real *x)
{
    if (g == NULL || b == NULL || x == NULL || g->line == NULL) return LS_ERR_INVALID;
    return solve_powers(g, b, x, NULL);
}

ls_status ls_grid_solver_solve2(ls_grid_solver *g, const ls_real *b, ls_real *x1, ls_real *x2)
{
    if (g == NULL || b == NULL || x1 == NULL || x2 == NULL || g->line == NULL || x2 == x1 || x2 == b)
        return LS_ERR_INVALID;
    return solve_powers(g, b, x1, x2);
}

ls_status ls_grid_solver_apply(const ls_grid_solver *g, const ls_real *x, ls_real *y)
{
    size_t w, h, k, ix, iy, c;
    if (g == NULL || x == NULL || y == NULL || g->line == NULL) return LS_ERR_INVALID;
    w = g->width;
    h = g->height;
    k = g->k;
    if (g->identity) {
        memcpy(y, x, w * h * k * sizeof(ls_real));
        return LS_OK;
    }
    for (iy = 0; iy < h; iy++)
        for (ix = 0; ix < w; ix++) {
            size_t i = iy * w + ix;
            for (c = 0; c < k; c++) {
                ls_real nb = (ls_real)0, v = x[i * k + c];
                uint32_t deg = 0;
                if (iy > 0) {
                    nb += x[(i - w) * k + c];
                    deg++;
                }
                if (ix > 0 || g->wrap) {
                    nb += x[(ix > 0 ? i - 1u : i + w - 1u) * k + c];
                    deg++;
                }
                if (ix + 1u < w || g->wrap) {
                    nb += x[(ix + 1u < w ? i + 1u : i + 1u - w) * k + c];
                    deg++;
                }
                if (iy + 1u < h) {
                    nb += x[(i + w) * k + c];
                    deg++;
                }
                y[i * k + c] = g->shift * v + g->weight * ((ls_real)deg * v - nb);
            }
        }
    return LS_OK;
}
