/* main.c - the `largesteps` command-line program (POSIX host).
 *
 *   largesteps info       the library's build configuration and self-test
 *   largesteps info MESH  counts, validation findings, genus and bounding box
 *                         of an OBJ, PLY or OFF file
 *   largesteps version    the version string
 *
 * The other commands live in cmd_NAME.c (commands.h); every command reads
 * files here and hands memory buffers to src/. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <errno.h>
#include "ls_posix.h"
#include "commands.h"
#include "args.h"

static int usage(FILE *out)
{
    fprintf(out, "usage: largesteps <command> [arguments]   (each command: --help)\n"
                 "  fit [TARGET|SCENE] -o DIR   reconstruct a mesh from renders of a target (default: the\n"
                 "                              embedded bunny); writes result.obj, contact.png, log.csv,\n"
                 "                              convergence.svg, metrics.json\n"
                 "  experiment NAME -o DIR      the paper's experiments: lambda-sweep, compare, silhouettes, views, texture\n"
                 "  render MESH -o DIR          render views and a contact sheet\n"
                 "  remesh IN -o OUT            isotropic remeshing\n"
                 "  metrics A B                 distances and tangling metrics between two meshes\n"
                 "  toy1d -o DIR                the 1D toy of large steps, with SVG plots\n"
                 "  info                        the build configuration and the self-test\n"
                 "  info MESH                   counts, validation findings, genus and bounding box of a mesh\n"
                 "  version                     the library version\n"
                 "options of every command:\n" LS_ARGS_GLOBAL_HELP);
    return out == stderr ? 2 : 0;
}

static int cmd_info(void)
{
    ls_build_info info;
    ls_status st;
    ls_build_info_get(&info);
    st = ls_selftest(sizeof(ls_real));
    printf("largesteps %s\n", ls_version_string());
    printf("  ls_real          %s (%u bytes)\n", info.real_name, (unsigned)info.real_bytes);
    printf("  LDLT sums        %s\n", sizeof(ls_acc) == sizeof(double) ? "double" : "float");
    printf("  arena alignment  %u bytes\n", (unsigned)info.arena_align);
    printf("  pointer, size_t  %u, %u bytes\n", (unsigned)info.pointer_bytes, (unsigned)info.size_bytes);
    printf("  byte order       %s\n", info.big_endian ? "big-endian" : "little-endian");
    printf("  status messages  %s\n", info.status_strings ? "yes" : "names only");
    printf("  compiler         %s\n", info.compiler);
    printf("  self-test        %s: %s\n", ls_status_name(st), ls_status_str(st));
    return st == LS_OK ? 0 : 1;
}

static const char *format_name(uint32_t format)
{
    return format == LS_MESH_FORMAT_PLY ? "PLY" : format == LS_MESH_FORMAT_OFF ? "OFF" : "OBJ";
}

/* One finding line: the count and, when there is one, the first element. */
static void finding(const char *name, uint32_t count, const char *kind, uint32_t first, int *problems)
{
    if (count == 0) {
        printf("  %-24s 0\n", name);
        return;
    }
    printf("  %-24s %u (first: %s %u)\n", name, (unsigned)count, kind, (unsigned)first);
    (*problems)++;
}

static void edge_finding(const char *name, uint32_t count, const uint32_t first[2], int *problems)
{
    if (count == 0) {
        printf("  %-24s 0\n", name);
        return;
    }
    printf("  %-24s %u (first: edge %u-%u)\n", name, (unsigned)count, (unsigned)first[0], (unsigned)first[1]);
    (*problems)++;
}

static int cmd_info_mesh(const char *path)
{
    unsigned char *data = NULL, *work = NULL;
    size_t bytes = 0, mesh_bytes = 0, check_bytes = 0, total;
    ls_mesh_file_info info;
    ls_mesh mesh;
    ls_mesh_report r;
    ls_arena arena;
    ls_diag diag;
    ls_real lo[3], hi[3];
    ls_status st;
    int problems = 0;
    st = ls_posix_read_data(path, &data, &bytes);
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: cannot read %s: %s\n", path, ls_posix_read_error());
        return 1;
    }
    ls_diag_clear(&diag);
    st = ls_mesh_read_info(data, bytes, LS_MESH_FORMAT_AUTO, &info, &diag);
    if (st == LS_OK) st = ls_mesh_read_bytes(&info, &mesh_bytes);
    if (st == LS_OK) {
        ls_mesh sizing;
        sizing.positions = NULL;
        sizing.triangles = NULL;
        sizing.vertex_count = info.vertex_count;
        sizing.face_count = info.face_count;
        st = ls_mesh_validate_bytes(&sizing, &check_bytes);
    }
    if (st == LS_OK) st = ls_size_sum(mesh_bytes, check_bytes, &total);
    if (st == LS_OK) {
        work = (unsigned char *)malloc(total > 0 ? total : 1);
        if (work == NULL) st = LS_ERR_NOMEM;
    }
    if (st == LS_OK) st = ls_arena_init(&arena, work, total);
    if (st == LS_OK) st = ls_mesh_read(data, bytes, info.format, &arena, &mesh, &diag);
    if (st == LS_OK) st = ls_mesh_validate(&mesh, &arena, &r);
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: %s", path);
        if (diag.has_line) fprintf(stderr, ":%u:%u", (unsigned)diag.line, (unsigned)diag.column);
        else if (diag.has_offset) fprintf(stderr, ": byte %llu", (unsigned long long)diag.offset);
        fprintf(stderr, ": %s: %s\n", ls_status_name(st), diag.what != NULL && diag.what[0] != 0 ? diag.what : ls_status_str(st));
        free(work);
        free(data);
        return 1;
    }
    printf("mesh         %s\n", path);
    printf("format       %s%s, %llu bytes\n", format_name(info.format),
           info.format == LS_MESH_FORMAT_PLY ? (info.binary ? " (binary)" : " (ascii)") : "", (unsigned long long)bytes);
    printf("vertices     %u (%u used)\n", (unsigned)mesh.vertex_count, (unsigned)r.used_vertices);
    printf("triangles    %u (from %u polygons; %u usable)\n", (unsigned)mesh.face_count, (unsigned)info.polygon_count,
           (unsigned)r.usable_faces);
    printf("edges        %u\n", (unsigned)r.edge_count);
    printf("components   %u\n", (unsigned)r.components);
    printf("boundary     %u edges in %u loops\n", (unsigned)r.boundary_edges, (unsigned)r.boundary_loops);
    printf("euler        %lld\n", (long long)r.euler);
    if (r.has_genus) printf("genus        %d\n", (int)r.genus);
    else printf("genus        undefined (not an oriented 2-manifold)\n");
    if (ls_mesh_bounds(&mesh, lo, hi) == LS_OK) {
        double d0 = (double)hi[0] - (double)lo[0], d1 = (double)hi[1] - (double)lo[1], d2 = (double)hi[2] - (double)lo[2];
        printf("bounds       min %.9g %.9g %.9g\n", (double)lo[0], (double)lo[1], (double)lo[2]);
        printf("             max %.9g %.9g %.9g\n", (double)hi[0], (double)hi[1], (double)hi[2]);
        printf("             diagonal %.6g\n", sqrt(d0 * d0 + d1 * d1 + d2 * d2));
    } else {
        printf("bounds       none (no finite vertex)\n");
    }
    printf("findings\n");
    finding("non-finite vertices", r.nonfinite_vertices, "vertex", r.first_nonfinite_vertex, &problems);
    finding("out-of-range indices", r.bad_index_faces, "face", r.first_bad_index_face, &problems);
    finding("degenerate faces", r.degenerate_faces, "face", r.first_degenerate_face, &problems);
    finding("zero-area faces", r.zero_area_faces, "face", r.first_zero_area_face, &problems);
    finding("duplicate faces", r.duplicate_faces, "face", r.first_duplicate_face, &problems);
    finding("unreferenced vertices", r.unreferenced_vertices, "vertex", r.first_unreferenced_vertex, &problems);
    edge_finding("boundary edges", r.boundary_edges, r.first_boundary_edge, &problems);
    edge_finding("non-manifold edges", r.nonmanifold_edges, r.first_nonmanifold_edge, &problems);
    finding("non-manifold vertices", r.nonmanifold_vertices, "vertex", r.first_nonmanifold_vertex, &problems);
    edge_finding("orientation conflicts", r.orientation_conflicts, r.first_orientation_conflict, &problems);
    printf("verdict      %s\n", problems == 0 ? "closed, oriented 2-manifold without defects"
                                               : ls_mesh_require(&r, LS_MESH_REQ_ALL, &diag) == LS_OK ? "usable" : diag.what);
    free(work);
    free(data);
    return 0;
}

static int info_usage(FILE *out)
{
    fprintf(out, "usage: largesteps info [MESH]\n"
                 "  without MESH: the library's build configuration and the self-test\n"
                 "  MESH         an OBJ, PLY or OFF file (gzip-compressed too): counts, validation\n"
                 "               findings, genus and bounding box\n" LS_ARGS_GLOBAL_HELP);
    return out == stderr ? 2 : 0;
}

static int version_usage(FILE *out)
{
    fprintf(out, "usage: largesteps version\n  prints the library version\n");
    return out == stderr ? 2 : 0;
}

static int is_help(const char *s)
{
    return strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0;
}

static int dispatch(int argc, char **argv)
{
    if (argc < 2) return usage(stderr);
    if (strcmp(argv[1], "info") == 0) {
        if (argc >= 3 && is_help(argv[2])) return info_usage(stdout);
        if (argc == 3 && strcmp(argv[2], "--") != 0 && argv[2][0] == '-') {
            fprintf(stderr, "largesteps info: unknown option '%s'\n", argv[2]);
            return info_usage(stderr);
        }
        if (argc == 4 && strcmp(argv[2], "--") == 0) return cmd_info_mesh(argv[3]);
        if (argc > 3) return info_usage(stderr);
        return argc == 3 ? cmd_info_mesh(argv[2]) : cmd_info();
    }
    if (strcmp(argv[1], "version") == 0) {
        if (argc >= 3 && is_help(argv[2])) return version_usage(stdout);
        if (argc > 2) return version_usage(stderr);
        printf("%s\n", ls_version_string());
        return 0;
    }
    if (strcmp(argv[1], "toy1d") == 0) return ls_cmd_toy1d(argc - 1, argv + 1);
    if (strcmp(argv[1], "metrics") == 0) return ls_cmd_metrics(argc - 1, argv + 1);
    if (strcmp(argv[1], "remesh") == 0) return ls_cmd_remesh(argc - 1, argv + 1);
    if (strcmp(argv[1], "render") == 0) return ls_cmd_render(argc - 1, argv + 1);
    if (strcmp(argv[1], "fit") == 0) return ls_cmd_fit(argc - 1, argv + 1);
    if (strcmp(argv[1], "experiment") == 0) return ls_cmd_experiment(argc - 1, argv + 1);
    if (strcmp(argv[1], "help") == 0 || is_help(argv[1])) return usage(stdout);
    fprintf(stderr, "largesteps: unknown command '%s'\n", argv[1]);
    return usage(stderr);
}

int main(int argc, char **argv)
{
    int rc;
    ls_posix_cleanup_on_signals();
    argc = ls_args_global(argc, argv);
    if (argc < 0) return 2;
    rc = dispatch(argc, argv);
    /* what went to stdout must have arrived: a full disk or a closed pipe
     * is a failure, never a silent success */
    errno = 0;
    if (fflush(stdout) != 0 || ferror(stdout)) {
        int err = errno;
        fprintf(stderr, "largesteps: writing to standard output failed: %s\n",
                err != 0 ? strerror(err) : "write error");
        return rc != 0 ? rc : 1;
    }
    return rc;
}
