/* laplacian.c - uniform, cotangent and grid Laplacians, the system matrix
 * M = I + lambda L (or (1 - alpha) I + alpha L), and the Laplacian and
 * bilaplacian regularizers. */
#include <largesteps/laplacian.h>
#include <largesteps/math.h>
#include <string.h>

#define IDX_LIMIT ((size_t)UINT32_MAX - 1u)

static void set_diag(ls_diag *diag, ls_status st, const char *what, uint64_t index, int has_index)
{
    (void)ls_diag_set(diag, st, what, has_index ? index : LS_DIAG_NO_INDEX);
}

/* Entries of a Laplacian with n vertices and e edges in `storage`; 0 and
 * *ok = 0 when it does not fit 32-bit indices. */
static size_t lap_entries(uint32_t n, size_t e, uint32_t storage, int *ok)
{
    size_t c = (storage == LS_LAP_FULL ? 2u * e : e) + (size_t)n;
    *ok = e <= IDX_LIMIT && c <= IDX_LIMIT && c >= (size_t)n;
    return *ok ? c : 0;
}

static void csc_size(ls_size *s, uint32_t n, size_t entries)
{
    ls_size_add(s, (size_t)n + 1u, sizeof(uint32_t));
    ls_size_add(s, entries, sizeof(uint32_t));
    ls_size_add(s, entries, sizeof(ls_real));
}

static int csc_alloc(ls_arena *arena, uint32_t n, size_t entries, ls_csc *m)
{
    m->nrows = n;
    m->ncols = n;
    m->capacity = (uint32_t)entries;
    m->colptr = (uint32_t *)ls_arena_alloc(arena, (size_t)n + 1u, sizeof(uint32_t));
    m->rowidx = (uint32_t *)ls_arena_alloc(arena, entries, sizeof(uint32_t));
    m->values = (ls_real *)ls_arena_alloc(arena, entries, sizeof(ls_real));
    return m->colptr != NULL && m->rowidx != NULL && m->values != NULL;
}

ls_status ls_laplacian_bytes(uint32_t vertex_count, uint32_t face_count, uint32_t edge_count, uint32_t storage,
                             size_t *bytes)
{
    ls_size phase, peak;
    size_t eb = 0;
    int ok;
    size_t entries;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    if (storage != LS_LAP_UPPER && storage != LS_LAP_FULL) return LS_ERR_INVALID;
    entries = lap_entries(vertex_count, edge_count, storage, &ok);
    if (!ok || vertex_count > IDX_LIMIT - 1u) return LS_ERR_TOO_LARGE;
    /* phase 1: the edge extraction (its scratch, then the edges) */
    st = ls_mesh_edges_bytes(face_count, edge_count, &eb);
    if (st != LS_OK) return st;
    ls_size_init(&peak);
    peak.bytes = eb;
    /* phase 2: the edges at the bottom and their copy at the top */
    ls_size_init(&phase);
    ls_size_add(&phase, edge_count, 2u * sizeof(uint32_t));
    ls_size_add(&phase, edge_count, 2u * sizeof(uint32_t));
    ls_size_max(&peak, &phase);
    /* phase 3: the matrix and the copy */
    ls_size_init(&phase);
    csc_size(&phase, vertex_count, entries);
    ls_size_add(&phase, edge_count, 2u * sizeof(uint32_t));
    ls_size_max(&peak, &phase);
    return ls_size_get(&peak, bytes);
}

/* Position of entry (row, col) in m, or UINT32_MAX: binary search in the
 * column's sorted rows. O(log column length). */
static uint32_t find_entry(const ls_csc *m, uint32_t row, uint32_t col)
{
    uint32_t lo = m->colptr[col], hi = m->colptr[col + 1u];
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2u;
        if (m->rowidx[mid] < row) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return (lo < m->colptr[col + 1u] && m->rowidx[lo] == row) ? lo : UINT32_MAX;
}

/* The pattern of a Laplacian from `count` sorted unique edges ev (pairs
 * a < b, sorted by (a, b)): off-diagonal values -1, diagonal 0. Column j is
 * its rows < j (edges (a, j): a ascending in edge order), the diagonal, then
 * (full storage) its rows > j (edges (j, b): b ascending). colptr serves as
 * the cursor and is shifted back at the end. O(n + E). */
static void fill_pattern(const uint32_t *ev, uint32_t count, uint32_t storage, ls_csc *m)
{
    uint32_t n = m->ncols, j, q;
    uint32_t *cp = m->colptr;
    size_t e;
    memset(cp, 0, ((size_t)n + 1u) * sizeof(uint32_t));
    for (e = 0; e < count; e++) {
        cp[ev[2u * e + 1u] + 1u]++;
        if (storage == LS_LAP_FULL) cp[ev[2u * e] + 1u]++;
    }
    for (j = 0; j < n; j++) cp[j + 1u] += cp[j] + 1u;
    for (e = 0; e < count; e++) { /* rows above the diagonal */
        q = cp[ev[2u * e + 1u]]++;
        m->rowidx[q] = ev[2u * e];
        m->values[q] = (ls_real)-1;
    }
    for (j = 0; j < n; j++) { /* the diagonal */
        q = cp[j]++;
        m->rowidx[q] = j;
        m->values[q] = (ls_real)0;
    }
    if (storage == LS_LAP_FULL) {
        for (e = 0; e < count; e++) { /* rows below the diagonal */
            q = cp[ev[2u * e]]++;
            m->rowidx[q] = ev[2u * e + 1u];
            m->values[q] = (ls_real)-1;
        }
    }
    for (j = n; j > 0; j--) cp[j] = cp[j - 1u];
    cp[0] = 0;
}

/* Sets every diagonal entry to minus the sum of its row's off-diagonal
 * entries, added in ascending column order of the neighbours in both
 * storages (so upper and full give the same bits). */
static void fill_diagonal(ls_csc *m, uint32_t storage)
{
    uint32_t n = m->ncols, j, p;
    if (storage == LS_LAP_FULL) {
        for (j = 0; j < n; j++) {
            ls_real s = (ls_real)0;
            uint32_t d = UINT32_MAX;
            for (p = m->colptr[j]; p < m->colptr[j + 1u]; p++) {
                if (m->rowidx[p] == j) {
                    d = p;
                } else {
                    s -= m->values[p];
                }
            }
            m->values[d] = s;
        }
        return;
    }
    /* upper: the diagonal is the last entry of each column; vertex v's sum
     * gets its neighbours < v (column v, ascending) then its neighbours > v
     * (row v of the later columns, ascending) */
    for (j = 0; j < n; j++) {
        for (p = m->colptr[j]; p + 1u < m->colptr[j + 1u]; p++) {
            uint32_t i = m->rowidx[p];
            m->values[m->colptr[j + 1u] - 1u] -= m->values[p];
            m->values[m->colptr[i + 1u] - 1u] -= m->values[p];
        }
    }
}

/* Builds the pattern of the mesh's Laplacian: edges at the bottom, copied to
 * the top, the matrix at the bottom where the edges were; the copy stays as
 * scratch until the caller restores. */
static ls_status build_pattern(const ls_mesh *mesh, uint32_t storage, ls_arena *arena, ls_csc *m, ls_diag *diag)
{
    ls_mesh_edges e;
    uint32_t *copy;
    ls_arena_mark mark = ls_arena_save(arena), keep;
    size_t entries;
    int ok;
    ls_status st = ls_mesh_edges_build(mesh, arena, &e, diag);
    if (st != LS_OK) return st;
    entries = lap_entries(mesh->vertex_count, e.count, storage, &ok);
    if (!ok || mesh->vertex_count > IDX_LIMIT - 1u) {
        ls_arena_restore(arena, mark);
        set_diag(diag, LS_ERR_TOO_LARGE, "Laplacian too large for 32-bit indices", 0, 0);
        return LS_ERR_TOO_LARGE;
    }
    copy = (uint32_t *)ls_arena_scratch(arena, e.count, 2u * sizeof(uint32_t));
    if (copy == NULL) goto nomem;
    if (e.count > 0) memcpy(copy, e.v, (size_t)e.count * 2u * sizeof(uint32_t));
    keep.bottom = mark.bottom;
    keep.top = arena->top;
    ls_arena_restore(arena, keep);
    if (!csc_alloc(arena, mesh->vertex_count, entries, m)) goto nomem;
    fill_pattern(copy, e.count, storage, m);
    return LS_OK;
nomem:
    ls_arena_restore(arena, mark);
    set_diag(diag, LS_ERR_NOMEM, "arena too small for the Laplacian", 0, 0);
    return LS_ERR_NOMEM;
}

/* The first bad argument of a Laplacian build, or NULL. */
static const char *args_problem(const ls_mesh *mesh, uint32_t storage, const ls_arena *arena, const ls_csc *out)
{
    if (mesh == NULL) return "mesh is NULL";
    if (arena == NULL) return "arena is NULL";
    if (out == NULL) return "out is NULL";
    if (storage != LS_LAP_UPPER && storage != LS_LAP_FULL) return "storage: allowed LS_LAP_UPPER or LS_LAP_FULL";
    return NULL;
}

ls_status ls_laplacian_uniform(const ls_mesh *mesh, uint32_t storage, ls_arena *arena, ls_csc *out, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    ls_csc m;
    ls_status st;
    const char *bad;
    bad = args_problem(mesh, storage, arena, out);
    if (bad != NULL) {
        set_diag(diag, LS_ERR_INVALID, bad, 0, 0);
        return LS_ERR_INVALID;
    }
    mark = ls_arena_save(arena);
    st = build_pattern(mesh, storage, arena, &m, diag);
    if (st != LS_OK) return st;
    fill_diagonal(&m, storage);
    ls_arena_restore(arena, (ls_arena_mark){arena->bottom, mark.top});
    *out = m;
    return LS_OK;
}

/* Adds -w to the entry of edge (a, b) (a != b), in both triangles for full
 * storage. */
static void add_weight(ls_csc *m, uint32_t storage, uint32_t a, uint32_t b, ls_real w)
{
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    m->values[find_entry(m, lo, hi)] -= w;
    if (storage == LS_LAP_FULL) m->values[find_entry(m, hi, lo)] -= w;
}

/* The three cotangents of face (a, b, c), each for the angle at that
 * corner: cot = dot / |cross|, |cross|^2 = 4 area^2 clamped. Returns 1 when
 * the area was clamped. */
static int face_cots(const ls_real *pa, const ls_real *pb, const ls_real *pc, ls_real cot[3])
{
    ls_real ab[3], ac[3], bc[3], cr[3], area2, twice_area;
    int k, clamped = 0;
    for (k = 0; k < 3; k++) {
        ab[k] = pb[k] - pa[k];
        ac[k] = pc[k] - pa[k];
        bc[k] = pc[k] - pb[k];
    }
    cr[0] = ab[1] * ac[2] - ab[2] * ac[1];
    cr[1] = ab[2] * ac[0] - ab[0] * ac[2];
    cr[2] = ab[0] * ac[1] - ab[1] * ac[0];
    area2 = (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) * (ls_real)0.25;
    if (!(area2 >= LS_COT_MIN_AREA2)) {
        area2 = LS_COT_MIN_AREA2;
        clamped = 1;
    }
    twice_area = (ls_real)2 * LS_RSQRT(area2);
    cot[0] = (ab[0] * ac[0] + ab[1] * ac[1] + ab[2] * ac[2]) / twice_area;
    cot[1] = -(ab[0] * bc[0] + ab[1] * bc[1] + ab[2] * bc[2]) / twice_area;
    cot[2] = (ac[0] * bc[0] + ac[1] * bc[1] + ac[2] * bc[2]) / twice_area;
    return clamped;
}

ls_status ls_laplacian_cot(const ls_mesh *mesh, uint32_t convention, uint32_t storage, ls_arena *arena,
                           ls_csc *out, uint32_t *clamped, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_arena_mark mark;
    ls_csc m;
    ls_status st;
    uint32_t f, v, count = 0;
    const char *bad;
    bad = args_problem(mesh, storage, arena, out);
    if (bad == NULL && convention != LS_COT_REFERENCE && convention != LS_COT_HALF)
        bad = "convention: allowed LS_COT_REFERENCE or LS_COT_HALF";
    if (bad == NULL && mesh->vertex_count > 0 && mesh->positions == NULL)
        bad = "mesh->positions is NULL with vertex_count > 0";
    if (bad != NULL) {
        set_diag(diag, LS_ERR_INVALID, bad, 0, 0);
        return LS_ERR_INVALID;
    }
    for (v = 0; v < 3u * mesh->vertex_count; v++) {
        if (!LS_RISFINITE(mesh->positions[v])) {
            set_diag(diag, LS_ERR_NONFINITE, "vertex coordinate is NaN or infinite", v / 3u, 1);
            return LS_ERR_NONFINITE;
        }
    }
    mark = ls_arena_save(arena);
    st = build_pattern(mesh, storage, arena, &m, diag);
    if (st != LS_OK) return st;
    for (v = 0; v < m.colptr[m.ncols]; v++) m.values[v] = (ls_real)0;
    for (f = 0; f < mesh->face_count; f++) {
        const uint32_t *t = mesh->triangles + 3u * (size_t)f;
        ls_real cot[3];
        int k;
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        count += (uint32_t)face_cots(mesh->positions + 3u * (size_t)t[0], mesh->positions + 3u * (size_t)t[1],
                                     mesh->positions + 3u * (size_t)t[2], cot);
        for (k = 0; k < 3; k++) {
            ls_real w = convention == LS_COT_HALF ? cot[k] * (ls_real)0.5 : cot[k];
            add_weight(&m, storage, t[(k + 1) % 3], t[(k + 2) % 3], w);
        }
    }
    fill_diagonal(&m, storage);
    ls_arena_restore(arena, (ls_arena_mark){arena->bottom, mark.top});
    if (clamped != NULL) *clamped = count;
    *out = m;
    return LS_OK;
}

/* ---- grid ---------------------------------------------------------------- */

/* The wrap in x is effective from nx = 3 on: for nx <= 2 the ends are the
 * same vertex or already neighbours. */
static uint32_t grid_wraps(uint32_t nx, uint32_t wrap_x)
{
    return wrap_x != 0 && nx >= 3u;
}

static ls_status grid_entries(uint32_t nx, uint32_t ny, uint32_t wrap_x, uint32_t storage, uint32_t *n,
                              size_t *entries)
{
    size_t nn, e;
    int ok;
    if (nx == 0 || ny == 0 || (storage != LS_LAP_UPPER && storage != LS_LAP_FULL)) return LS_ERR_INVALID;
    if ((size_t)nx > IDX_LIMIT / (size_t)ny) return LS_ERR_TOO_LARGE;
    nn = (size_t)nx * ny;
    if (nn > IDX_LIMIT - 1u) return LS_ERR_TOO_LARGE;
    e = (size_t)(nx - 1u) * ny + (size_t)nx * (ny - 1u) + (grid_wraps(nx, wrap_x) ? (size_t)ny : 0u);
    *entries = lap_entries((uint32_t)nn, e, storage, &ok);
    *n = (uint32_t)nn;
    return ok ? LS_OK : LS_ERR_TOO_LARGE;
}

ls_status ls_laplacian_grid_wrap_bytes(uint32_t nx, uint32_t ny, uint32_t wrap_x, uint32_t storage, size_t *bytes)
{
    ls_size s;
    uint32_t n = 0;
    size_t entries = 0;
    ls_status st;
    if (bytes == NULL) return LS_ERR_INVALID;
    *bytes = 0;
    st = grid_entries(nx, ny, wrap_x, storage, &n, &entries);
    if (st != LS_OK) return st;
    ls_size_init(&s);
    csc_size(&s, n, entries);
    return ls_size_get(&s, bytes);
}

ls_status ls_laplacian_grid_bytes(uint32_t nx, uint32_t ny, uint32_t storage, size_t *bytes)
{
    return ls_laplacian_grid_wrap_bytes(nx, ny, 0u, storage, bytes);
}

static void grid_entry(ls_csc *m, uint32_t *w, uint32_t row, ls_real value)
{
    m->rowidx[*w] = row;
    m->values[(*w)++] = value;
}

ls_status ls_laplacian_grid_wrap(uint32_t nx, uint32_t ny, uint32_t wrap_x, uint32_t storage, ls_arena *arena,
                                 ls_csc *out)
{
    ls_arena_mark mark;
    ls_csc m;
    uint32_t n = 0, x, y, w = 0, wrap = grid_wraps(nx, wrap_x);
    size_t entries = 0;
    ls_status st;
    if (arena == NULL || out == NULL) return LS_ERR_INVALID;
    st = grid_entries(nx, ny, wrap_x, storage, &n, &entries);
    if (st != LS_OK) return st;
    mark = ls_arena_save(arena);
    if (!csc_alloc(arena, n, entries, &m)) {
        ls_arena_restore(arena, mark);
        return LS_ERR_NOMEM;
    }
    for (y = 0; y < ny; y++) {
        for (x = 0; x < nx; x++) {
            uint32_t j = y * nx + x;
            ls_real deg = (ls_real)(wrap ? 2 + (y > 0) + (y + 1u < ny)
                                         : (x > 0) + (x + 1u < nx) + (y > 0) + (y + 1u < ny));
            m.colptr[j] = w;
            if (y > 0) grid_entry(&m, &w, j - nx, (ls_real)-1);
            if (wrap && x + 1u == nx) grid_entry(&m, &w, j - x, (ls_real)-1);
            if (x > 0) grid_entry(&m, &w, j - 1u, (ls_real)-1);
            grid_entry(&m, &w, j, deg);
            if (storage == LS_LAP_FULL) {
                if (x + 1u < nx) grid_entry(&m, &w, j + 1u, (ls_real)-1);
                if (wrap && x == 0) grid_entry(&m, &w, j + nx - 1u, (ls_real)-1);
                if (y + 1u < ny) grid_entry(&m, &w, j + nx, (ls_real)-1);
            }
        }
    }
    m.colptr[n] = w;
    *out = m;
    return LS_OK;
}

ls_status ls_laplacian_grid(uint32_t nx, uint32_t ny, uint32_t storage, ls_arena *arena, ls_csc *out)
{
    return ls_laplacian_grid_wrap(nx, ny, 0u, storage, arena, out);
}

/* ---- the system matrix --------------------------------------------------- */

ls_status ls_laplacian_system_bytes(const ls_csc *lap, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL || lap == NULL || lap->colptr == NULL) return LS_ERR_INVALID;
    ls_size_init(&s);
    ls_size_add(&s, ls_csc_nnz(lap), sizeof(ls_real));
    return ls_size_get(&s, bytes);
}

/* Checks the arguments and that the identity term survives on every
 * diagonal; *shift receives s (1 or 1 - alpha). */
static ls_status system_check(const ls_csc *lap, uint32_t form, ls_real weight, ls_real *shift, ls_diag *diag)
{
    uint32_t j;
    if (lap == NULL || lap->colptr == NULL || lap->nrows != lap->ncols ||
        (ls_csc_nnz(lap) > 0 && (lap->rowidx == NULL || lap->values == NULL))) {
        set_diag(diag, LS_ERR_INVALID, "lap: NULL, not square, or colptr/rowidx/values NULL", 0, 0);
        return LS_ERR_INVALID;
    }
    if (form == LS_SYSTEM_LAMBDA) {
        if (!(weight >= (ls_real)0) || !LS_RISFINITE(weight)) {
            set_diag(diag, LS_ERR_INVALID, "weight: lambda finite and >= 0", 0, 0);
            if (diag != NULL) {
                diag->has_value = 1;
                diag->value = weight;
            }
            return LS_ERR_INVALID;
        }
        *shift = (ls_real)1;
    } else if (form == LS_SYSTEM_ALPHA) {
        if (!(weight >= (ls_real)0 && weight < (ls_real)1)) {
            set_diag(diag, LS_ERR_INVALID, "weight: alpha in [0, 1)", 0, 0);
            if (diag != NULL) {
                diag->has_value = 1;
                diag->value = weight;
            }
            return LS_ERR_INVALID;
        }
        *shift = (ls_real)1 - weight;
    } else {
        set_diag(diag, LS_ERR_INVALID, "form: allowed LS_SYSTEM_LAMBDA or LS_SYSTEM_ALPHA", 0, 0);
        return LS_ERR_INVALID;
    }
    for (j = 0; j < lap->ncols; j++) {
        uint32_t d = find_entry(lap, j, j);
        ls_real wd;
        if (d == UINT32_MAX) {
            set_diag(diag, LS_ERR_INVALID, "lap: column without its diagonal entry", j, 1);
            return LS_ERR_INVALID;
        }
        wd = weight * lap->values[d];
        if (lap->values[d] > (ls_real)0 && *shift + wd == wd) {
            set_diag(diag, LS_ERR_NOT_SPD, "weight too large for this precision: the identity term rounds away", j, 1);
            if (diag != NULL) {
                diag->has_value = 1;
                diag->value = weight;
            }
            return LS_ERR_NOT_SPD;
        }
    }
    return LS_OK;
}

static void system_fill(const ls_csc *lap, ls_real weight, ls_real shift, ls_real *values)
{
    uint32_t j, p;
    for (j = 0; j < lap->ncols; j++) {
        for (p = lap->colptr[j]; p < lap->colptr[j + 1u]; p++) {
            ls_real v = weight * lap->values[p];
            values[p] = lap->rowidx[p] == j ? shift + v : v;
        }
    }
}

ls_status ls_laplacian_system(const ls_csc *lap, uint32_t form, ls_real weight, ls_arena *arena, ls_csc *m,
                              ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_real shift = (ls_real)1, *values;
    ls_status st;
    if (arena == NULL || m == NULL) {
        set_diag(diag, LS_ERR_INVALID, arena == NULL ? "arena is NULL" : "m is NULL", 0, 0);
        return LS_ERR_INVALID;
    }
    st = system_check(lap, form, weight, &shift, diag);
    if (st != LS_OK) return st;
    values = (ls_real *)ls_arena_alloc(arena, ls_csc_nnz(lap), sizeof(ls_real));
    if (values == NULL) {
        set_diag(diag, LS_ERR_NOMEM, "arena too small for the system matrix", 0, 0);
        return LS_ERR_NOMEM;
    }
    system_fill(lap, weight, shift, values);
    m->nrows = lap->nrows;
    m->ncols = lap->ncols;
    m->capacity = ls_csc_nnz(lap);
    m->colptr = lap->colptr;
    m->rowidx = lap->rowidx;
    m->values = values;
    return LS_OK;
}

ls_status ls_laplacian_system_update(const ls_csc *lap, uint32_t form, ls_real weight, ls_csc *m, ls_diag *diag)
{
    ls_diag_clear(diag);
    ls_real shift = (ls_real)1;
    ls_status st;
    if (m == NULL || lap == NULL || m->colptr != lap->colptr || m->rowidx != lap->rowidx || m->ncols != lap->ncols ||
        m->values == NULL) {
        set_diag(diag, LS_ERR_INVALID,
                 m == NULL     ? "m is NULL"
                 : lap == NULL ? "lap is NULL"
                               : "m: values NULL, or colptr/rowidx/ncols not those of lap",
                 0, 0);
        return LS_ERR_INVALID;
    }
    st = system_check(lap, form, weight, &shift, diag);
    if (st != LS_OK) return st;
    system_fill(lap, weight, shift, m->values);
    return LS_OK;
}

/* ---- regularizers -------------------------------------------------------- */

static int reg_ok(const ls_csc *lap, uint32_t k, const ls_real *x)
{
    return lap != NULL && lap->colptr != NULL && lap->nrows == lap->ncols && k > 0 && x != NULL;
}

ls_status ls_laplacian_energy_bytes(const ls_csc *lap, uint32_t k, int bilaplacian, int has_grad, size_t *bytes)
{
    ls_size s;
    if (bytes == NULL || lap == NULL || k == 0) return LS_ERR_INVALID;
    ls_size_init(&s);
    if (bilaplacian || !has_grad) ls_size_add(&s, (size_t)lap->ncols * k, sizeof(ls_real));
    return ls_size_get(&s, bytes);
}

/* sum of a[i] * b[i] in index order */
static ls_real dot(const ls_real *a, const ls_real *b, size_t count)
{
    ls_real s = (ls_real)0;
    size_t i;
    for (i = 0; i < count; i++) s += a[i] * b[i];
    return s;
}

ls_status ls_laplacian_energy(const ls_csc *lap, uint32_t k, const ls_real *x, ls_real w, ls_real *value,
                              ls_real *grad, ls_arena *arena)
{
    ls_arena_mark mark;
    ls_real *lx = grad;
    size_t count;
    if (!reg_ok(lap, k, x) || (grad == NULL && arena == NULL)) return LS_ERR_INVALID;
    if (value == NULL && grad == NULL) return LS_OK;
    count = (size_t)lap->ncols * k;
    mark = arena != NULL ? ls_arena_save(arena) : (ls_arena_mark){0, 0};
    if (lx == NULL) {
        lx = (ls_real *)ls_arena_scratch(arena, count, sizeof(ls_real));
        if (lx == NULL) return LS_ERR_NOMEM;
    }
    if (ls_csc_matvec_sym(lap, k, x, lx) != LS_OK) {
        if (arena != NULL) ls_arena_restore(arena, mark);
        return LS_ERR_INVALID;
    }
    if (value != NULL) *value = w * dot(x, lx, count);
    if (grad != NULL) {
        ls_real two_w = (ls_real)2 * w;
        size_t i;
        for (i = 0; i < count; i++) grad[i] *= two_w;
    }
    if (arena != NULL) ls_arena_restore(arena, mark);
    return LS_OK;
}

ls_status ls_laplacian_bilaplacian(const ls_csc *lap, uint32_t k, const ls_real *x, ls_real w, ls_real *value,
                                   ls_real *grad, ls_arena *arena)
{
    ls_arena_mark mark;
    ls_real *lx;
    size_t count;
    if (!reg_ok(lap, k, x) || arena == NULL) return LS_ERR_INVALID;
    count = (size_t)lap->ncols * k;
    mark = ls_arena_save(arena);
    lx = (ls_real *)ls_arena_scratch(arena, count, sizeof(ls_real));
    if (lx == NULL) return LS_ERR_NOMEM;
    if (ls_csc_matvec_sym(lap, k, x, lx) != LS_OK) {
        ls_arena_restore(arena, mark);
        return LS_ERR_INVALID;
    }
    if (value != NULL) *value = w * dot(lx, lx, count);
    if (grad != NULL) {
        ls_real two_w = (ls_real)2 * w;
        size_t i;
        (void)ls_csc_matvec_sym(lap, k, lx, grad);
        for (i = 0; i < count; i++) grad[i] *= two_w;
    }
    ls_arena_restore(arena, mark);
    return LS_OK;
}
