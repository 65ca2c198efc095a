/* cmd_remesh.c - `largesteps remesh IN [--h H | --factor F] [--iters N]
 * [--no-project] -o OUT`: isotropic remeshing (largesteps/remesh.h) to
 * target edge length H, or F times the mean edge length (default 0.5, the
 * Large Steps rule). Writes OBJ, or binary PLY when OUT ends in ".ply", whole
 * or not at all (a temporary file renamed). Prints the counts, h, edge-length
 * and angle statistics, the time and the arena bytes (bound and used). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include "commands.h"
#include "ls_posix.h"
#include "args.h"

static int remesh_usage(FILE *f)
{
    fprintf(f, "usage: largesteps remesh IN [--h H | --factor F] [--iters N] [--no-project]\n"
               "                         [--sharp-angle A] [--vertex-cap N] -o OUT\n"
               "  IN              the input mesh (OBJ, PLY or OFF; gzip-compressed too)\n"
               "  --h H           target edge length (H > 0; default: F x the mean edge length)\n"
               "  --factor F      target = F x mean edge length (0 < F <= 1000; default 0.5)\n"
               "  --iters N       iterations (1..1000; default 5)\n"
               "  --no-project    do not project onto the input surface (default: project)\n"
               "  --sharp-angle A keep input vertices whose faces' normals differ by more than A degrees\n"
               "                  (0..180; default 90; 180 keeps none, as the reference)\n"
               "  --vertex-cap N  vertex capacity (1..2147483647; default: the bound of ls_remesh_capacity)\n"
               "  -o OUT          output mesh: .obj or .ply (required; written whole or not at all)\n"
               LS_ARGS_GLOBAL_HELP);
    return f == stderr ? 2 : 0;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    size_t i;
    if (n < m) return 0;
    for (i = 0; i < m; i++) {
        char c = s[n - m + i];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != suffix[i]) return 0;
    }
    return 1;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y ? 1 : 0;
}

/* Edge lengths over the 3 edges of every face (interior edges twice) and
 * the corner angles in degrees. */
static void print_stats(const ls_mesh *m, double h)
{
    size_t n = 3u * (size_t)m->face_count, inside = 0;
    double *len = (double *)malloc(n * sizeof(double) + 8), *ang = (double *)malloc(n * sizeof(double) + 8);
    double sum = 0;
    uint32_t f, j;
    if (len == NULL || ang == NULL) {
        free(len);
        free(ang);
        return;
    }
    for (f = 0; f < m->face_count; f++) {
        for (j = 0; j < 3; j++) {
            const ls_real *a = m->positions + 3u * m->triangles[3u * f + j];
            const ls_real *b = m->positions + 3u * m->triangles[3u * f + (j + 1) % 3];
            const ls_real *c = m->positions + 3u * m->triangles[3u * f + (j + 2) % 3];
            double u[3], v[3], lu, lv, d;
            int k;
            for (k = 0; k < 3; k++) {
                u[k] = (double)b[k] - (double)a[k];
                v[k] = (double)c[k] - (double)a[k];
            }
            lu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            lv = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            d = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (lu * lv);
            if (d > 1) d = 1;
            if (d < -1) d = -1;
            len[3u * f + j] = lu;
            ang[3u * f + j] = acos(d) * 57.29577951308232;
            sum += lu;
            if (lu >= 0.8 * h && lu <= 4.0 / 3.0 * h) inside++;
        }
    }
    qsort(len, n, sizeof(double), cmp_double);
    qsort(ang, n, sizeof(double), cmp_double);
    printf("edges        mean %.6g (%.3f h), min %.6g, median %.6g, max %.6g; %.1f %% in [4/5 h, 4/3 h]\n",
           sum / (double)n, sum / (double)n / h, len[0], len[n / 2], len[n - 1], 100.0 * (double)inside / (double)n);
    printf("angles       min %.2f, 1 %% %.2f, 5 %% %.2f, median %.2f, max %.2f degrees\n", ang[0], ang[n / 100],
           ang[n / 20], ang[n / 2], ang[n - 1]);
    free(len);
    free(ang);
}

typedef struct mesh_file {
    const ls_mesh *mesh;
    int ply;
} mesh_file;

static int mesh_body(FILE *f, void *ctx)
{
    const mesh_file *m = (const mesh_file *)ctx;
    return (m->ply ? ls_mesh_write_ply(m->mesh, ls_posix_write_file, f) : ls_mesh_write_obj(m->mesh, ls_posix_write_file, f)) ==
           LS_OK;
}

static int write_mesh(const char *path, const ls_mesh *m)
{
    mesh_file mf;
    mf.mesh = m;
    mf.ply = ends_with(path, ".ply");
    return ls_posix_write_whole(path, mesh_body, &mf);
}

int ls_cmd_remesh(int argc, char **argv)
{
    const char *in_path = NULL, *out_path = NULL;
    double h = 0, factor = 0.5, sharp = LS_REMESH_SHARP_ANGLE;
    int project = 1, i, rc = 1, h_set = 0, factor_set = 0;
    uint32_t vcap = 0, iters = 5;
    unsigned char *data = NULL, *work = NULL, *work2 = NULL;
    size_t bytes = 0, read_bytes = 0, vbytes = 0, bound = 0;
    ls_mesh_file_info finfo;
    ls_mesh mesh, out;
    ls_mesh_report rep;
    ls_remesh_params params;
    ls_remesh_info info;
    ls_arena arena, arena2;
    ls_diag diag;
    ls_real mean = 0;
    uint64_t t0, t1;
    ls_status st;
    for (i = 1; i < argc; i++) {
        const char *o = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1;
        if (strcmp(o, "--help") == 0 || strcmp(o, "-h") == 0) return remesh_usage(stdout);
        if (strcmp(o, "--no-project") == 0) {
            project = 0;
            continue;
        }
        if (o[0] != '-' || strcmp(o, "-") == 0) {
            if (in_path != NULL) return fprintf(stderr, "largesteps remesh: more than one input ('%s')\n", o), remesh_usage(stderr);
            in_path = o;
            continue;
        }
        if (strcmp(o, "--h") != 0 && strcmp(o, "--factor") != 0 && strcmp(o, "--iters") != 0 &&
            strcmp(o, "--vertex-cap") != 0 && strcmp(o, "--sharp-angle") != 0 && strcmp(o, "-o") != 0) {
            fprintf(stderr, "largesteps remesh: unknown option '%s'\n", o);
            return remesh_usage(stderr);
        }
        if (val == NULL) return fprintf(stderr, "largesteps remesh: %s needs a value\n", o), 2;
        i++;
        if (strcmp(o, "--h") == 0) ok = ls_arg_real("remesh", o, val, 0, 1e300, LS_ARG_LO_OPEN, &h), h_set = 1;
        else if (strcmp(o, "--factor") == 0) ok = ls_arg_real("remesh", o, val, 0, 1000, LS_ARG_LO_OPEN, &factor), factor_set = 1;
        else if (strcmp(o, "--iters") == 0) ok = ls_arg_u32("remesh", o, val, 1, 1000, &iters);
        else if (strcmp(o, "--vertex-cap") == 0) ok = ls_arg_u32("remesh", o, val, 1, 2147483647u, &vcap);
        else if (strcmp(o, "--sharp-angle") == 0) ok = ls_arg_real("remesh", o, val, 0, 180, LS_ARG_CLOSED, &sharp);
        else out_path = val;
        if (!ok) return 2;
    }
    if (h_set && factor_set) {
        fprintf(stderr, "largesteps remesh: --h and --factor conflict (give one: an edge length or a factor)\n");
        return 2;
    }
    if (in_path == NULL || out_path == NULL) {
        fprintf(stderr, "largesteps remesh: %s\n", in_path == NULL ? "no input mesh" : "no output: -o OUT is required");
        return remesh_usage(stderr);
    }
    if (!ends_with(out_path, ".obj") && !ends_with(out_path, ".ply")) {
        fprintf(stderr, "largesteps remesh: -o: '%s' has an unknown extension (.obj or .ply)\n", out_path);
        return 2;
    }
    if (!ls_posix_check_output(out_path)) return 2;
    ls_diag_clear(&diag);
    st = ls_posix_read_data(in_path, &data, &bytes);
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: cannot read %s: %s\n", in_path, ls_posix_read_error());
        return 1;
    }
    st = ls_mesh_read_info(data, bytes, LS_MESH_FORMAT_AUTO, &finfo, &diag);
    if (st == LS_OK) st = ls_mesh_read_bytes(&finfo, &read_bytes);
    if (st == LS_OK) {
        ls_mesh sizing;
        memset(&sizing, 0, sizeof sizing);
        sizing.vertex_count = finfo.vertex_count;
        sizing.face_count = finfo.face_count;
        st = ls_mesh_validate_bytes(&sizing, &vbytes);
    }
    if (st == LS_OK) {
        work = (unsigned char *)malloc(read_bytes + vbytes + 8);
        if (work == NULL) st = LS_ERR_NOMEM;
    }
    if (st == LS_OK) st = ls_arena_init(&arena, work, read_bytes + vbytes);
    if (st == LS_OK) st = ls_mesh_read(data, bytes, finfo.format, &arena, &mesh, &diag);
    if (st == LS_OK) st = ls_mesh_validate(&mesh, &arena, &rep);
    if (st == LS_OK) st = ls_remesh_mean_edge(&mesh, &mean);
    if (st == LS_OK) {
        if (!(h > 0)) h = factor * (double)mean;
        ls_remesh_params_default(&params, (ls_real)h);
        params.iterations = (uint32_t)iters;
        params.project = (uint32_t)project;
        params.vertex_cap = vcap;
        params.sharp_angle = (ls_real)sharp;
        st = ls_remesh_bytes_bound(&mesh, &rep, &params, &bound);
    }
    if (st == LS_OK) {
        work2 = (unsigned char *)malloc(bound + 8);
        if (work2 == NULL) st = LS_ERR_NOMEM;
    }
    if (st == LS_OK) st = ls_arena_init(&arena2, work2, bound);
    t0 = ls_posix_clock_ns(NULL);
    if (st == LS_OK) st = ls_remesh(&mesh, &params, &arena2, &out, &info, &diag);
    t1 = ls_posix_clock_ns(NULL);
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: %s: %s: %s\n", in_path, ls_status_name(st),
                diag.what != NULL && diag.what[0] != 0 ? diag.what : ls_status_str(st));
        goto done;
    }
    printf("input        %s: %u vertices, %u faces, mean edge %.6g\n", in_path, (unsigned)mesh.vertex_count,
           (unsigned)mesh.face_count, (double)mean);
    printf("target       h = %.6g (%.3f x mean edge), %u iterations, projection %s\n", h, h / (double)mean, (unsigned)iters,
           project ? "on" : "off");
    printf("output       %s: %u vertices, %u faces\n", out_path, (unsigned)out.vertex_count, (unsigned)out.face_count);
    printf("operations   %u splits, %u collapses, %u flips\n", (unsigned)info.splits, (unsigned)info.collapses,
           (unsigned)info.flips);
    print_stats(&out, h);
    {
        size_t tb = 0;
        unsigned char *tw;
        ls_arena ta;
        ls_tangle_report tr;
        if (ls_tangle_bytes(out.face_count, &tb) == LS_OK && (tw = (unsigned char *)malloc(tb + 8)) != NULL) {
            if (ls_arena_init(&ta, tw, tb) == LS_OK && ls_tangle(&out, NULL, &ta, &tr, NULL) == LS_OK)
                printf("tangling     %u self-intersecting face pairs\n", (unsigned)tr.intersecting_pairs);
            free(tw);
        }
    }
    printf("time         %.1f ms\n", (double)(t1 - t0) / 1e6);
    printf("memory       %llu bytes used of %llu bound (vertex capacity %u, peak %u vertices)\n",
           (unsigned long long)info.bytes_used, (unsigned long long)bound, (unsigned)info.vertex_cap,
           (unsigned)info.max_vertices);
    if (!write_mesh(out_path, &out)) {
        fprintf(stderr, "largesteps: cannot write %s\n", out_path);
        goto done;
    }
    rc = 0;
done:
    free(work2);
    free(work);
    free(data);
    return rc;
}
