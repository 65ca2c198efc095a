/* cmd_metrics.c - `largesteps metrics A B [--json] [--samples N]`: distances
 * between meshes A and B (largesteps/distance.h: vertex-sampled Hausdorff as
 * igl::hausdorff, dense area-uniform face samples: Hausdorff, mean, RMS,
 * absolute and relative to B's bounding-box diagonal; normal angle error),
 * and the tangling metrics of each mesh (largesteps/tangle.h:
 * self-intersecting pairs, angle and quality percentiles; inverted faces of A
 * relative to B when both have the same triangles). A and B: OBJ, PLY or OFF. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "commands.h"
#include "report.h"
#include "ls_posix.h"
#include "args.h"

static int metrics_usage(FILE *f)
{
    fprintf(f, "usage: largesteps metrics A B [--json] [--samples N]\n"
               "  A, B        meshes (OBJ, PLY or OFF; gzip-compressed too); B is the target (relative values\n"
               "              use its bounding-box diagonal)\n"
               "  --json      print one JSON object instead of the table (default: the table); numbers\n"
               "              that are not finite are null, listed in \"not_finite\"\n"
               "  --samples N face samples on each mesh (0..4294967295; default 10 per vertex, at least 1000)\n"
               LS_ARGS_GLOBAL_HELP);
    return f == stderr ? 2 : 0;
}

typedef struct loaded {
    ls_mesh mesh;
    unsigned char *work;
} loaded;

static int load(const char *path, loaded *out)
{
    unsigned char *data = NULL;
    size_t bytes = 0, need = 0;
    ls_mesh_file_info info;
    ls_arena arena;
    ls_diag diag;
    ls_status st;
    out->work = NULL;
    st = ls_posix_read_data(path, &data, &bytes);
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: cannot read %s: %s\n", path, ls_posix_read_error());
        return 0;
    }
    ls_diag_clear(&diag);
    st = ls_mesh_read_info(data, bytes, LS_MESH_FORMAT_AUTO, &info, &diag);
    if (st == LS_OK) st = ls_mesh_read_bytes(&info, &need);
    if (st == LS_OK) {
        out->work = (unsigned char *)malloc(need > 0 ? need : 8);
        if (out->work == NULL) st = LS_ERR_NOMEM;
    }
    if (st == LS_OK) st = ls_arena_init(&arena, out->work, need);
    if (st == LS_OK) st = ls_mesh_read(data, bytes, info.format, &arena, &out->mesh, &diag);
    free(data);
    if (st == LS_OK && out->mesh.face_count == 0) {
        st = LS_ERR_MESH;
        diag.what = "no faces";
        diag.has_line = 0;
    }
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: %s", path);
        if (diag.has_line) fprintf(stderr, ":%u:%u", (unsigned)diag.line, (unsigned)diag.column);
        fprintf(stderr, ": %s: %s\n", ls_status_name(st),
                diag.what != NULL && diag.what[0] != 0 ? diag.what : ls_status_str(st));
        free(out->work);
        out->work = NULL;
        return 0;
    }
    return 1;
}

static void text_one_way(const char *name, const ls_dist_one_way *w, double diag)
{
    double d = diag > 0 ? diag : 1;
    printf("%s vertices  max %-12.6g mean %-12.6g rms %-12.6g (/diag: %.6g %.6g %.6g; %u samples)\n", name,
           (double)w->vertex.max, (double)w->vertex.mean, (double)w->vertex.rms, (double)w->vertex.max / d,
           (double)w->vertex.mean / d, (double)w->vertex.rms / d, (unsigned)w->vertex.count);
    printf("%s faces     max %-12.6g mean %-12.6g rms %-12.6g (/diag: %.6g %.6g %.6g; %u samples)\n", name,
           (double)w->face.max, (double)w->face.mean, (double)w->face.rms, (double)w->face.max / d,
           (double)w->face.mean / d, (double)w->face.rms / d, (unsigned)w->face.count);
    printf("%s normals   max %-9.4g deg  mean %-9.4g deg  rms %.4g deg\n", name, (double)w->normal.max,
           (double)w->normal.mean, (double)w->normal.rms);
}

int ls_cmd_metrics(int argc, char **argv)
{
    const char *pa = NULL, *pb = NULL;
    int json = 0, i, rc = 1, same;
    long long samples = -1;
    loaded a, b;
    size_t need = 0, t1 = 0, t2 = 0;
    unsigned char *work = NULL;
    ls_arena arena;
    ls_distance_report d;
    ls_tangle_report ta, tb;
    ls_diag diag;
    ls_status st;
    uint32_t sa, sb;
    uint64_t t0, t_dist, t_tangle;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) return metrics_usage(stdout);
        if (strcmp(argv[i], "--json") == 0) json = 1;
        else if (strcmp(argv[i], "--samples") == 0) {
            uint32_t n = 0;
            if (i + 1 >= argc) return fprintf(stderr, "largesteps metrics: --samples needs a value\n"), 2;
            if (!ls_arg_u32("metrics", "--samples", argv[++i], 0, UINT32_MAX, &n)) return 2;
            samples = (long long)n;
        } else if (argv[i][0] == '-' && argv[i][1] != 0) {
            fprintf(stderr, "largesteps metrics: unknown option '%s'\n", argv[i]);
            return metrics_usage(stderr);
        } else if (pa == NULL) pa = argv[i];
        else if (pb == NULL) pb = argv[i];
        else return fprintf(stderr, "largesteps metrics: more than two meshes ('%s')\n", argv[i]), metrics_usage(stderr);
    }
    if (pa == NULL || pb == NULL) {
        fprintf(stderr, "largesteps metrics: two meshes are needed\n");
        return metrics_usage(stderr);
    }
    if (!load(pa, &a)) return 1;
    if (!load(pb, &b)) {
        free(a.work);
        return 1;
    }
    sa = samples >= 0 ? (uint32_t)samples : ls_distance_default_samples(&a.mesh);
    sb = samples >= 0 ? (uint32_t)samples : ls_distance_default_samples(&b.mesh);
    same = a.mesh.face_count == b.mesh.face_count &&
           memcmp(a.mesh.triangles, b.mesh.triangles, 3u * sizeof(uint32_t) * a.mesh.face_count) == 0;
    st = ls_mesh_distance_bytes(a.mesh.face_count, b.mesh.face_count, &need);
    if (st == LS_OK) st = ls_tangle_bytes(a.mesh.face_count, &t1);
    if (st == LS_OK) st = ls_tangle_bytes(b.mesh.face_count, &t2);
    if (t1 > need) need = t1;
    if (t2 > need) need = t2;
    if (st == LS_OK) {
        work = (unsigned char *)malloc(need + 8);
        if (work == NULL) st = LS_ERR_NOMEM;
    }
    if (st == LS_OK) st = ls_arena_init(&arena, work, need);
    ls_diag_clear(&diag);
    t0 = ls_posix_clock_ns(NULL);
    if (st == LS_OK) st = ls_mesh_distance(&a.mesh, &b.mesh, sa, sb, &arena, &d, &diag);
    t_dist = ls_posix_clock_ns(NULL) - t0;
    t0 = ls_posix_clock_ns(NULL);
    if (st == LS_OK) st = ls_tangle(&a.mesh, same ? &b.mesh : NULL, &arena, &ta, &diag);
    if (st == LS_OK) st = ls_tangle(&b.mesh, NULL, &arena, &tb, &diag);
    t_tangle = ls_posix_clock_ns(NULL) - t0;
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: metrics: %s: %s\n", ls_status_name(st),
                diag.what != NULL && diag.what[0] != 0 ? diag.what : ls_status_str(st));
        goto done;
    }
    if (json) {
        printf("{\n  \"a\": {\"path\": ");
        ls_report_json_string(stdout, pa);
        printf(", \"vertices\": %u, \"faces\": %u, \"samples\": %u},\n", (unsigned)a.mesh.vertex_count,
               (unsigned)a.mesh.face_count, (unsigned)sa);
        printf("  \"b\": {\"path\": ");
        ls_report_json_string(stdout, pb);
        printf(", \"vertices\": %u, \"faces\": %u, \"samples\": %u},\n", (unsigned)b.mesh.vertex_count,
               (unsigned)b.mesh.face_count, (unsigned)sb);
        ls_report_json_distance(stdout, &d);
        ls_report_json_tangle(stdout, "tangle_a", &ta, 1);
        ls_report_json_tangle(stdout, "tangle_b", &tb, 1);
        printf("  \"time_ms\": {\"distance\": %.3f, \"tangle\": %.3f},\n", (double)t_dist * 1e-6,
               (double)t_tangle * 1e-6);
        printf("  \"arena_bytes\": %llu\n}\n", (unsigned long long)need);
    } else {
        printf("A  %s: %u vertices, %u faces, %u face samples\n", pa, (unsigned)a.mesh.vertex_count,
               (unsigned)a.mesh.face_count, (unsigned)sa);
        printf("B  %s: %u vertices, %u faces, %u face samples\n", pb, (unsigned)b.mesh.vertex_count,
               (unsigned)b.mesh.face_count, (unsigned)sb);
        printf("B bounding-box diagonal %.9g (relative values divide by it)\n\n", (double)d.diag);
        printf("symmetric            absolute      / diag(B)\n");
        printf("  H vertices         %-13.6g %.6g   (= igl::hausdorff)\n", (double)d.vertex_hausdorff,
               (double)d.vertex_hausdorff_rel);
        printf("  H (all samples)    %-13.6g %.6g\n", (double)d.hausdorff, (double)d.hausdorff_rel);
        printf("  mean (%s)%s %-13.6g %.6g\n", sa > 0 ? "faces" : "vertices", sa > 0 ? "      " : "   ", (double)d.mean,
               (double)d.mean_rel);
        printf("  rms (%s)%s  %-13.6g %.6g\n\n", sa > 0 ? "faces" : "vertices", sa > 0 ? "      " : "   ", (double)d.rms,
               (double)d.rms_rel);
        text_one_way("A->B", &d.ab, (double)d.diag);
        text_one_way("B->A", &d.ba, (double)d.diag);
        printf("\n");
        ls_report_text_tangle(stdout, "A", &ta);
        ls_report_text_tangle(stdout, "B", &tb);
        printf("\ntime: distances %.1f ms, tangle %.1f ms; arena %llu bytes\n", (double)t_dist * 1e-6,
               (double)t_tangle * 1e-6, (unsigned long long)need);
    }
    rc = 0;
done:
    free(work);
    free(a.work);
    free(b.work);
    return rc;
}
