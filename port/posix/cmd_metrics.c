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
#include "ls_posix.h"

static int metrics_usage(void)
{
    fprintf(stderr, "usage: largesteps metrics A B [--json] [--samples N]\n"
                    "  A, B        meshes (OBJ, PLY or OFF); B is the target (relative values use its\n"
                    "              bounding-box diagonal)\n"
                    "  --json      print one JSON object instead of the table\n"
                    "  --samples N face samples on each mesh (default 10 per vertex, at least 1000)\n");
    return 2;
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
    st = ls_posix_read_file(path, &data, &bytes);
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: cannot read %s: %s\n", path, ls_status_str(st));
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

static void json_string(const char *s)
{
    putchar('"');
    for (; *s != 0; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') printf("\\%c", c);
        else if (c < 0x20) printf("\\u%04x", (unsigned)c);
        else putchar(c);
    }
    putchar('"');
}

static void json_stats(const char *name, const ls_dist_stats *s, int comma)
{
    printf("\"%s\": {\"max\": %.9g, \"mean\": %.9g, \"rms\": %.9g, \"count\": %u, \"argmax\": %lld}%s", name,
           (double)s->max, (double)s->mean, (double)s->rms, (unsigned)s->count,
           s->argmax == UINT32_MAX ? -1LL : (long long)s->argmax, comma ? ", " : "");
}

static void json_one_way(const char *name, const ls_dist_one_way *w)
{
    printf("  \"%s\": {", name);
    json_stats("vertex", &w->vertex, 1);
    json_stats("face", &w->face, 1);
    json_stats("normal_deg", &w->normal, 0);
    printf("},\n");
}

static void json_tangle(const char *name, const ls_tangle_report *t, int comma)
{
    printf("  \"%s\": {\"intersecting_pairs\": %u, \"intersecting_faces\": %u, \"degenerate_faces\": %u, ", name,
           (unsigned)t->intersecting_pairs, (unsigned)t->intersecting_faces, (unsigned)t->degenerate_faces);
    if (t->has_reference) printf("\"inverted_faces\": %u, ", (unsigned)t->inverted_faces);
    else printf("\"inverted_faces\": null, ");
    printf("\"angle_deg\": {\"min\": %.9g, \"p1\": %.9g, \"p5\": %.9g, \"p50\": %.9g, \"max\": %.9g}, ",
           (double)t->angle_min, (double)t->angle_p1, (double)t->angle_p5, (double)t->angle_p50, (double)t->angle_max);
    printf("\"quality\": {\"min\": %.9g, \"p1\": %.9g, \"p5\": %.9g, \"p50\": %.9g, \"mean\": %.9g}}%s\n",
           (double)t->quality_min, (double)t->quality_p1, (double)t->quality_p5, (double)t->quality_p50,
           (double)t->quality_mean, comma ? "," : "");
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

static void text_tangle(const char *name, const ls_tangle_report *t)
{
    printf("%s self-intersecting pairs %u (%u faces)", name, (unsigned)t->intersecting_pairs,
           (unsigned)t->intersecting_faces);
    if (t->intersecting_pairs > 0) printf(", first %u-%u", (unsigned)t->first_pair[0], (unsigned)t->first_pair[1]);
    printf("; degenerate faces %u", (unsigned)t->degenerate_faces);
    if (t->has_reference) printf("; inverted vs B %u", (unsigned)t->inverted_faces);
    printf("\n%s angles    min %.3f p1 %.3f p5 %.3f p50 %.3f max %.3f deg\n", name, (double)t->angle_min,
           (double)t->angle_p1, (double)t->angle_p5, (double)t->angle_p50, (double)t->angle_max);
    printf("%s quality   min %.4f p1 %.4f p5 %.4f p50 %.4f mean %.4f (2 r / R)\n", name, (double)t->quality_min,
           (double)t->quality_p1, (double)t->quality_p5, (double)t->quality_p50, (double)t->quality_mean);
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
        if (strcmp(argv[i], "--json") == 0) json = 1;
        else if (strcmp(argv[i], "--samples") == 0 && i + 1 < argc) {
            char *end = NULL;
            samples = strtoll(argv[++i], &end, 10);
            if (end == argv[i] || *end != 0 || samples < 0 || samples > (long long)UINT32_MAX) return metrics_usage();
        } else if (argv[i][0] == '-' && argv[i][1] != 0) return metrics_usage();
        else if (pa == NULL) pa = argv[i];
        else if (pb == NULL) pb = argv[i];
        else return metrics_usage();
    }
    if (pa == NULL || pb == NULL) return metrics_usage();
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
        json_string(pa);
        printf(", \"vertices\": %u, \"faces\": %u, \"samples\": %u},\n", (unsigned)a.mesh.vertex_count,
               (unsigned)a.mesh.face_count, (unsigned)sa);
        printf("  \"b\": {\"path\": ");
        json_string(pb);
        printf(", \"vertices\": %u, \"faces\": %u, \"samples\": %u},\n", (unsigned)b.mesh.vertex_count,
               (unsigned)b.mesh.face_count, (unsigned)sb);
        printf("  \"diag_b\": %.9g,\n", (double)d.diag);
        printf("  \"vertex_hausdorff\": %.9g, \"vertex_hausdorff_rel\": %.9g,\n", (double)d.vertex_hausdorff,
               (double)d.vertex_hausdorff_rel);
        printf("  \"hausdorff\": %.9g, \"hausdorff_rel\": %.9g,\n", (double)d.hausdorff, (double)d.hausdorff_rel);
        printf("  \"mean\": %.9g, \"mean_rel\": %.9g,\n", (double)d.mean, (double)d.mean_rel);
        printf("  \"rms\": %.9g, \"rms_rel\": %.9g,\n", (double)d.rms, (double)d.rms_rel);
        json_one_way("a_to_b", &d.ab);
        json_one_way("b_to_a", &d.ba);
        json_tangle("tangle_a", &ta, 1);
        json_tangle("tangle_b", &tb, 1);
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
        text_tangle("A", &ta);
        text_tangle("B", &tb);
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
