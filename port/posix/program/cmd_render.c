/* cmd_render.c - `largesteps render`: renders a mesh from a set of views into
 * PNG files and a contact sheet.
 *
 *   largesteps render MESH [--views N] [--res W] [--ss S] [--shading mask|sh|lambert]
 *                     [--placement fibonacci|rings|hemisphere] [--bits 8|16] [--fov DEG] -o DIR
 *   largesteps render MESH --cameras transforms.json [--res W] [--ss S] [--shading S] [--bits B] -o DIR
 *
 * MESH is an OBJ, PLY or OFF file (ls_mesh_read). The cameras look at the
 * mesh's bounding-box centre from N directions (a Fibonacci sphere, or rings
 * of constant latitude: the largest divisor r of N with r^2 <= N rings of N/r
 * views, or the Fibonacci lattice over the cap above y = -1/4) at the
 * distance where the bounding sphere fills the image with a 10% margin
 * (ls_camera_frame), with a horizontal field of view of DEG degrees
 * (default 45), square W x W images (default 256) with S x S samples per
 * pixel (default 2). The framing and the SH lighting are those of the fit's
 * mesh targets (fit_job.h), so that a dataset rendered here with the fit's
 * views is the problem `largesteps fit MESH` solves. Shading (default sh):
 * `mask` white silhouette; `sh` diffuse spherical-harmonics irradiance of
 * that lighting (a soft sky from above plus a key light from the front
 * right), on the uniform-weight vertex normals; `lambert` two directional lights (key from
 * upper front right, dim blue fill from below behind) plus ambient 0.05.
 * Background black; alpha is coverage.
 *
 * With --cameras, the views are a camera dataset's (ls_scene_parse_transforms:
 * poses, field of view, principal point, clip planes, and its image size when
 * it gives one, else W x W), so targets can be rendered for given cameras.
 *
 * Writes DIR/view_000.png ... (RGBA, 16 bits per sample unless --bits 8) and
 * DIR/contact.png (every view on a near-square grid, 1-pixel grey lines
 * between them) and DIR/transforms.json (the views as a camera dataset with
 * the lighting used: `largesteps fit DIR/transforms.json` fits it), all
 * written together or not at all. DIR is
 * created when missing. Prints, per view, the times of rasterization,
 * shading and encoding, the arena bytes the view used and the file size. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <sys/stat.h>
#include <sys/types.h>
#include "ls_posix.h"
#include "commands.h"
#include "args.h"
#include "fit_job.h"

#define SHADE_NAMES "mask|sh|lambert"

typedef struct render_args {
    const char *mesh_path, *out_dir;
    const char *cameras; /* --cameras: a camera dataset whose cameras are used */
    uint32_t views, res, ss, mode, rings, bits;
    uint32_t normals;    /* --normals: LS_JOB_NORMALS_* (ls_job_shown_mesh) */
    double crease_deg;
    double fov_deg;
    int placed;          /* --views, --placement or --fov given (not with --cameras) */
} render_args;

static int usage(FILE *f)
{
    fprintf(f, "usage: largesteps render MESH [--views N] [--res W] [--ss 1|2|4] [--shading " SHADE_NAMES "]\n"
               "                         [--placement fibonacci|rings|hemisphere] [--bits 8|16] [--fov DEG] -o DIR\n"
               "       largesteps render MESH --cameras transforms.json [--res W] [--ss S] [--shading S]\n"
               "                         [--bits B] -o DIR\n"
               "  MESH          an OBJ, PLY or OFF file (gzip-compressed too)\n"
               "  --views N     views (1..4000; default 8)\n"
               "  --cameras F   the cameras of a camera dataset (transforms.json: its frames' poses, field\n"
               "                of view, principal point, clip planes, and its w x h if given, else\n"
               "                --res), instead of views placed around the mesh\n"
               "  --res W       image size W x W (1..%u; default 256)\n"
               "  --ss S        supersampling: 1, 2 or 4 (default 2)\n"
               "  --shading S   " SHADE_NAMES " (default sh)\n"
               "  --normals N   smooth (default: vertex normals averaged over their faces) | auto (as\n"
               "                `fit` shows its targets: smooth, but a mesh made of flat pieces, a CAD\n"
               "                part, split at its creases sharper than 60 degrees) | flat (each face\n"
               "                its own normal) | DEGREES (0..180: split at the edges whose faces meet\n"
               "                at more than this angle)\n"
               "  --placement P fibonacci (default: the whole sphere) | rings | hemisphere (the Fibonacci\n"
               "                lattice above y = -1/4: the upper half and a little below)\n"
               "  --bits B      8 or 16 bits per sample (default 16)\n"
               "  --fov DEG     field of view in degrees, 0 < DEG < 180 (default 45, the fit's)\n"
               "  -o DIR        output directory (required; created if missing): view_000.png ... and\n"
               "                contact.png, written together or not at all\n" LS_ARGS_GLOBAL_HELP,
            (unsigned)LS_RASTER_MAX_DIM);
    return f == stderr ? 2 : 0;
}

/* 1: parsed; 0: a bad argument (reported); -1: --help printed. */
static int parse_args(int argc, char **argv, render_args *a)
{
    int i;
    memset(a, 0, sizeof *a);
    a->views = 8;
    a->res = 256;
    a->ss = 2;
    a->mode = LS_SHADE_SH;
    a->bits = 16;
    a->fov_deg = LS_JOB_FOV_DEG;
    for (i = 1; i < argc; i++) {
        const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int ok = 1;
        if (strcmp(o, "--help") == 0 || strcmp(o, "-h") == 0) return usage(stdout), -1;
        if (o[0] != '-') {
            if (a->mesh_path != NULL) return fprintf(stderr, "largesteps render: more than one mesh ('%s')\n", o), 0;
            a->mesh_path = o;
            continue;
        }
        if (strcmp(o, "-o") != 0 && strcmp(o, "--views") != 0 && strcmp(o, "--res") != 0 && strcmp(o, "--ss") != 0 &&
            strcmp(o, "--bits") != 0 && strcmp(o, "--fov") != 0 && strcmp(o, "--shading") != 0 &&
            strcmp(o, "--placement") != 0 && strcmp(o, "--cameras") != 0 && strcmp(o, "--normals") != 0)
            return fprintf(stderr, "largesteps render: unknown option '%s'\n", o), 0;
        if (v == NULL) return fprintf(stderr, "largesteps render: %s needs a value\n", o), 0;
        i++;
        if (strcmp(o, "--views") == 0 || strcmp(o, "--placement") == 0 || strcmp(o, "--fov") == 0) a->placed = 1;
        if (strcmp(o, "-o") == 0) {
            a->out_dir = v;
        } else if (strcmp(o, "--cameras") == 0) {
            a->cameras = v;
        } else if (strcmp(o, "--views") == 0) {
            ok = ls_arg_u32("render", o, v, 1, 4000, &a->views);
        } else if (strcmp(o, "--res") == 0) {
            ok = ls_arg_u32("render", o, v, 1, LS_RASTER_MAX_DIM, &a->res);
        } else if (strcmp(o, "--ss") == 0) {
            ok = ls_arg_u32("render", o, v, 1, 4, &a->ss);
            if (ok && a->ss == 3) ok = 0, fprintf(stderr, "largesteps render: --ss: '3' is not 1, 2 or 4\n");
        } else if (strcmp(o, "--bits") == 0) {
            ok = ls_arg_u32("render", o, v, 8, 16, &a->bits);
            if (ok && a->bits != 8 && a->bits != 16) ok = 0, fprintf(stderr, "largesteps render: --bits: '%s' is not 8 or 16\n", v);
        } else if (strcmp(o, "--fov") == 0) {
            ok = ls_arg_real("render", o, v, 0, 180, LS_ARG_LO_OPEN | LS_ARG_HI_OPEN, &a->fov_deg);
        } else if (strcmp(o, "--normals") == 0) {
            if (!ls_job_parse_normals(v, &a->normals, &a->crease_deg))
                ok = 0, fprintf(stderr, "largesteps render: --normals: '%s' is not smooth, auto, flat or an angle in "
                                        "degrees between 0 and 180\n", v);
        } else if (strcmp(o, "--shading") == 0) {
            if (strcmp(v, "mask") == 0) a->mode = LS_SHADE_MASK;
            else if (strcmp(v, "sh") == 0) a->mode = LS_SHADE_SH;
            else if (strcmp(v, "lambert") == 0) a->mode = LS_SHADE_LAMBERT;
            else ok = 0, fprintf(stderr, "largesteps render: --shading: '%s' is not one of " SHADE_NAMES "\n", v);
        } else {
            if (strcmp(v, "fibonacci") == 0) a->rings = 0;
            else if (strcmp(v, "rings") == 0) a->rings = 1;
            else if (strcmp(v, "hemisphere") == 0) a->rings = 2;
            else ok = 0, fprintf(stderr, "largesteps render: --placement: '%s' is not fibonacci, rings or hemisphere\n", v);
        }
        if (!ok) return 0;
    }
    if (a->mesh_path == NULL) return fprintf(stderr, "largesteps render: no mesh\n"), 0;
    if (a->out_dir == NULL) return fprintf(stderr, "largesteps render: -o DIR is required\n"), 0;
    if (a->cameras != NULL && a->placed)
        return fprintf(stderr, "largesteps render: --cameras gives the views: not with --views, --placement or --fov\n"), 0;
    return 1;
}

/* Adds an image to the run's output set (ls_posix_outset_add_image).
 * Returns the file size, or 0 after printing an error. */
static size_t write_png(ls_posix_outset *set, const char *name, const ls_image *img, uint32_t bits, ls_arena *arena)
{
    ls_image_format fmt;
    ls_status st;
    size_t size = 0;
    fmt.type = LS_IMAGE_PNG;
    fmt.channels = 4;
    fmt.bits = bits;
    fmt.big_endian = 0;
    if (!ls_posix_outset_add_image(set, name, img, &fmt, arena, &st)) {
        if (st != LS_OK) fprintf(stderr, "largesteps: cannot encode %s: %s\n", name, ls_status_str(st));
        else fprintf(stderr, "largesteps: %s\n", ls_posix_write_error());
        return 0;
    }
    size = ls_posix_last_image_bytes(); /* compressed: known once written */
    return size;
}

/* Everything one run holds (memory from two arenas: the geometry with the
 * visibility buffer, and the images with every call's scratch). */
typedef struct render_run {
    render_args a;
    ls_mesh mesh;
    ls_real *normals, *dirs, *rgba;
    ls_camera_framing fr;
    ls_vis vis;
    ls_image view;
    ls_contact sheet;
    ls_shade_opts opts;
    ls_light lights[2];
    ls_real sh[27];
    ls_arena geo, work;
    void *geo_mem, *work_mem;
    size_t vis_bytes, rgba_bytes;
    int with_sheet; /* 0 when the sheet would pass the image size limits */
    double *c2w;    /* [16 views] camera-to-world of each view (transforms.json) */
    uint32_t w, h;  /* image size */
    ls_real *w2v;   /* [16 views] world -> view of each view */
    ls_real *mvp;   /* [16 views] clip transform of each view */
    ls_real fov, near_plane, far_plane, center[2]; /* the intrinsics written to transforms.json */
    uint32_t fov_axis;
    ls_scene scene; /* --cameras: the dataset (its memory: scene_mem) */
    void *scene_mem;
} render_run;

/* The run's mesh seen through mvp, as ls_raster and ls_shade read it. */
static const ls_view *run_view(const render_run *r, const ls_real *mvp, ls_view *view)
{
    memset(view, 0, sizeof *view);
    view->vis = &r->vis;
    view->positions = r->mesh.positions;
    view->indices = r->mesh.triangles;
    view->triangle_count = r->mesh.face_count;
    view->vertex_count = r->mesh.vertex_count;
    view->normals = r->normals;
    view->opts = &r->opts;
    view->mvp = mvp;
    return view;
}

static int fail(const char *what, ls_status st, const ls_diag *d)
{
    fprintf(stderr, "largesteps: %s: %s", what, ls_status_name(st));
    if (d != NULL && d->has_line) fprintf(stderr, " (line %u)", (unsigned)d->line);
    if (d != NULL && d->has_index) fprintf(stderr, " (index %llu)", (unsigned long long)d->index);
    fprintf(stderr, ": %s\n", d != NULL && d->what != NULL && d->what[0] != 0 ? d->what : ls_status_str(st));
    return 1;
}

/* --cameras: the dataset's cameras (r->scene), its view count and image
 * size (--res where it gives none). */
static int load_cameras(render_run *r)
{
    unsigned char *text = NULL;
    size_t bytes = 0, need = 0;
    ls_arena arena;
    ls_diag d;
    ls_status st;
    ls_diag_clear(&d);
    st = ls_posix_read_file(r->a.cameras, &text, &bytes);
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: cannot read %s: %s\n", r->a.cameras, ls_posix_read_error());
        return 1;
    }
    st = ls_scene_parse_transforms_bytes((const char *)text, bytes, &need, &d);
    r->scene_mem = st == LS_OK ? malloc(need + 8) : NULL;
    if (st == LS_OK && (r->scene_mem == NULL || ls_arena_init(&arena, r->scene_mem, need + 8) != LS_OK)) st = LS_ERR_NOMEM;
    if (st == LS_OK) st = ls_scene_parse_transforms((const char *)text, bytes, &arena, &r->scene, &d);
    free(text);
    if (st == LS_ERR_NOMEM) return fail("memory", st, NULL);
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: %s:%u:%u: %s\n", r->a.cameras, (unsigned)d.line, (unsigned)d.column, d.what);
        return 1;
    }
    if (r->scene.camera_count > 4000u) {
        fprintf(stderr, "largesteps: %s: %u frames, more than render's 4000\n", r->a.cameras, (unsigned)r->scene.camera_count);
        return 1;
    }
    if (r->scene.width == 0) r->scene.width = r->scene.height = r->a.res;
    if (r->scene.width > LS_RASTER_MAX_DIM || r->scene.height > LS_RASTER_MAX_DIM) {
        fprintf(stderr, "largesteps: %s: images of %u x %u, larger than %u on a side\n", r->a.cameras,
                (unsigned)r->scene.width, (unsigned)r->scene.height, (unsigned)LS_RASTER_MAX_DIM);
        return 1;
    }
    r->a.views = r->scene.camera_count;
    r->w = r->scene.width;
    r->h = r->scene.height;
    return 0;
}

/* Each view's transforms: the dataset's cameras, or directions around the
 * framed mesh; and the intrinsics transforms.json records. */
static ls_status place_views(render_run *r)
{
    uint32_t v;
    ls_status st = LS_OK;
    if (r->a.cameras != NULL) {
        const ls_scene_camera *c = &r->scene.cameras[0];
        for (v = 0; v < r->a.views && st == LS_OK; v++) {
            ls_real proj[16];
            st = ls_scene_projection(&r->scene, v, proj);
            memcpy(r->w2v + 16u * v, r->scene.cameras[v].view, 16u * sizeof(ls_real));
            if (st == LS_OK) ls_mat4_mul(proj, r->scene.cameras[v].view, r->mvp + 16u * v);
        }
        r->fov = c->fov;
        r->fov_axis = c->fov_axis;
        r->near_plane = c->near_plane;
        r->far_plane = c->far_plane;
        r->center[0] = c->center[0];
        r->center[1] = c->center[1];
        return st;
    }
    if (r->a.rings == 2) {
        /* the Fibonacci lattice over the cap above y = -1/4: the upper hemisphere and a little
           below it, as a capture from around an object on a table sees it */
        for (v = 0; v < r->a.views; v++) {
            const double y = 1.0 - 1.25 * ((double)v + 0.5) / (double)r->a.views, rr = sqrt(1.0 - y * y);
            const double az = (double)v * 3.14159265358979323846 * (3.0 - sqrt(5.0));
            r->dirs[3u * v] = (ls_real)(rr * ls_cos(az));
            r->dirs[3u * v + 1u] = (ls_real)y;
            r->dirs[3u * v + 2u] = (ls_real)(rr * ls_sin(az));
        }
    } else if (r->a.rings) {
        uint32_t rings = 1, k;
        for (k = 1; (uint64_t)k * k <= r->a.views; k++)
            if (r->a.views % k == 0) rings = k;
        st = ls_camera_ring_dirs(rings, r->a.views / rings, r->dirs);
    } else {
        st = ls_camera_fibonacci_dirs(r->a.views, r->dirs);
    }
    for (v = 0; v < r->a.views && st == LS_OK; v++)
        st = ls_camera_framed_view(&r->fr, r->dirs + 3 * (size_t)v, r->w2v + 16u * v, r->mvp + 16u * v);
    r->fov = (ls_real)(r->a.fov_deg * 3.14159265358979323846 / 180.0);
    r->fov_axis = LS_FOV_X;
    r->near_plane = r->fr.near_plane;
    r->far_plane = r->fr.far_plane;
    return st;
}

/* Reads the mesh, frames it, places the views and sizes the work arena. */
static int setup(render_run *r)
{
    unsigned char *data = NULL;
    size_t bytes = 0, mesh_bytes, flat_bytes = 0, geo_bytes, work_bytes, scratch = 0, sz;
    uint32_t shown_vertices;
    ls_mesh_file_info info;
    ls_diag d;
    ls_size s;
    ls_status st;
    uint32_t v, cols;
    ls_view view;
    ls_diag_clear(&d);
    r->w = r->h = r->a.res;
    if (r->a.cameras != NULL && load_cameras(r) != 0) return 1;
    st = ls_posix_read_data(r->a.mesh_path, &data, &bytes);
    if (st != LS_OK) {
        fprintf(stderr, "largesteps: cannot read %s: %s\n", r->a.mesh_path, ls_posix_read_error());
        return 1;
    }
    st = ls_mesh_read_info(data, bytes, LS_MESH_FORMAT_AUTO, &info, &d);
    if (st == LS_OK) st = ls_mesh_read_bytes(&info, &mesh_bytes);
    /* --normals flat renders the mesh unwelded: 3 F vertices of its own;
     * split at its creases, at most V + 3 F (auto: counted first, in less) */
    shown_vertices = info.vertex_count;
    if (st == LS_OK && r->a.normals == LS_JOB_NORMALS_FLAT) {
        st = ls_mesh_unweld_bytes(info.face_count, &flat_bytes);
        shown_vertices = 3u * info.face_count;
    } else if (st == LS_OK && r->a.normals != LS_JOB_NORMALS_SMOOTH) {
        st = ls_mesh_split_creases_bytes(info.vertex_count, info.face_count, &flat_bytes);
        shown_vertices = info.vertex_count + 3u * info.face_count;
    }
    if (st == LS_OK) st = ls_vis_bytes(r->w, r->h, r->a.ss, shown_vertices, &r->vis_bytes);
    if (st != LS_OK) {
        free(data);
        return fail(r->a.mesh_path, st, &d);
    }
    ls_size_init(&s);
    ls_size_add(&s, mesh_bytes, 1);
    ls_size_add(&s, flat_bytes, 1);
    ls_size_add(&s, shown_vertices, 3 * sizeof(ls_real));
    ls_size_add(&s, r->a.views, 3 * sizeof(ls_real));
    ls_size_add(&s, r->a.views, 32 * sizeof(ls_real));
    ls_size_add(&s, r->vis_bytes, 1);
    st = ls_size_get(&s, &geo_bytes);
    r->geo_mem = st == LS_OK ? malloc(geo_bytes + 8) : NULL;
    if (r->geo_mem == NULL || ls_arena_init(&r->geo, r->geo_mem, geo_bytes) != LS_OK) {
        free(data);
        return fail("memory", LS_ERR_NOMEM, NULL);
    }
    st = ls_mesh_read(data, bytes, info.format, &r->geo, &r->mesh, &d);
    free(data);
    if (st != LS_OK) return fail(r->a.mesh_path, st, &d);
    r->normals = (ls_real *)ls_arena_alloc(&r->geo, shown_vertices, 3 * sizeof(ls_real));
    r->dirs = (ls_real *)ls_arena_alloc(&r->geo, r->a.views, 3 * sizeof(ls_real));
    r->w2v = (ls_real *)ls_arena_alloc(&r->geo, r->a.views, 16 * sizeof(ls_real));
    r->mvp = (ls_real *)ls_arena_alloc(&r->geo, r->a.views, 16 * sizeof(ls_real));
    if (r->normals == NULL || r->dirs == NULL || r->mvp == NULL) return fail("memory", LS_ERR_NOMEM, NULL);
    if (r->a.cameras == NULL) { /* framed as the mesh read: the same views whatever --normals */
        st = ls_camera_frame(r->mesh.positions, r->mesh.vertex_count, (ls_real)(r->a.fov_deg * 3.14159265358979323846 / 180.0),
                             LS_FOV_X, 1, (ls_real)LS_JOB_MARGIN, &r->fr, &d);
        if (st == LS_ERR_INVALID) d.what = "cannot frame the mesh: no vertices, or all at one point";
    }
    if (st == LS_OK) st = place_views(r);
    if (st == LS_OK) {
        ls_mesh u;
        int creased;
        double share;
        st = ls_job_shown_mesh(&r->mesh, r->a.normals, r->a.crease_deg, &r->geo, &u, &creased, &share, &d);
        if (st == LS_OK) r->mesh = u;
    }
    if (st == LS_OK) st = ls_mesh_vertex_normals(&r->mesh, LS_NORMALS_UNIFORM, r->normals, &d);
    if (st == LS_OK) st = ls_vis_init(&r->vis, &r->geo, r->w, r->h, r->a.ss, r->mesh.vertex_count);
    if (st != LS_OK) return fail(r->a.mesh_path, st, &d);
    /* the work arena: shaded output, the view image, the sheet, and the
     * largest scratch of any call (each view's exact raster scratch) */
    for (v = 0; v < r->a.views && st == LS_OK; v++) {
        st = ls_raster_scratch_bytes(&r->vis, run_view(r, r->mvp + 16u * v, &view), &sz);
        if (st == LS_OK && sz > scratch) scratch = sz;
    }
    if (st == LS_OK) st = ls_shade_image_bytes(r->w, r->h, &r->rgba_bytes);
    ls_size_init(&s);
    ls_size_add(&s, r->rgba_bytes, 1);
    if (st == LS_OK) st = ls_image_bytes(r->w, r->h, &sz);
    ls_size_add(&s, sz, 1);
    if (st == LS_OK) {
        /* a sheet beyond the image size limits is left out (with a note) */
        ls_status cs = ls_contact_bytes(r->a.views, r->w, r->h, 0, 1, &sz);
        r->with_sheet = cs == LS_OK;
        if (cs == LS_ERR_TOO_LARGE) fprintf(stderr, "largesteps: note: the contact sheet would be too large; not written\n");
        else if (cs != LS_OK) st = cs;
        if (r->with_sheet) ls_size_add(&s, sz, 1);
    }
    if (st == LS_OK) {
        ls_image_format fmt = {LS_IMAGE_PNG, 4, 16, 0};
        st = ls_image_encode_bytes(r->w, r->h, &fmt, &sz); /* the same for the sheet */
        if (sz > scratch) scratch = sz;
    }
    ls_size_add(&s, scratch, 1);
    if (st == LS_OK) st = ls_size_get(&s, &work_bytes);
    if (st != LS_OK) return fail("sizing", st, NULL);
    r->work_mem = malloc(work_bytes + 8);
    if (r->work_mem == NULL || ls_arena_init(&r->work, r->work_mem, work_bytes) != LS_OK)
        return fail("memory", LS_ERR_NOMEM, NULL);
    r->rgba = (ls_real *)ls_arena_alloc(&r->work, r->rgba_bytes, 1);
    st = r->rgba == NULL ? LS_ERR_NOMEM : ls_image_create(&r->view, r->w, r->h, &r->work);
    if (st == LS_OK && r->with_sheet) {
        const float grey[4] = {0.5f, 0.5f, 0.5f, 1.0f};
        st = ls_contact_init(&r->sheet, &r->work, r->a.views, r->w, r->h, 0, 1, grey);
    }
    if (st != LS_OK) return fail("memory", st, NULL);
    cols = r->with_sheet ? r->sheet.columns : 0;
    printf("mesh      %s: %u vertices, %u triangles\n", r->a.mesh_path, (unsigned)r->mesh.vertex_count,
           (unsigned)r->mesh.face_count);
    if (r->a.cameras != NULL)
        printf("views     %u (the cameras of %s), %ux%u pixels, %ux%u samples each\n", (unsigned)r->a.views,
               r->a.cameras, (unsigned)r->w, (unsigned)r->h, (unsigned)r->a.ss, (unsigned)r->a.ss);
    else
        printf("views     %u (%s), %ux%u pixels, %ux%u samples each, fov %.6g deg, distance %.6g (radius %.6g)\n",
               (unsigned)r->a.views, r->a.rings == 2 ? "hemisphere" : r->a.rings ? "rings" : "fibonacci",
               (unsigned)r->w, (unsigned)r->h,
               (unsigned)r->a.ss, (unsigned)r->a.ss, r->a.fov_deg, (double)r->fr.distance, (double)r->fr.radius);
    printf("memory    geometry %lu bytes (visibility buffer %lu), work %lu bytes (largest scratch %lu)",
           (unsigned long)geo_bytes, (unsigned long)r->vis_bytes, (unsigned long)work_bytes, (unsigned long)scratch);
    if (r->with_sheet)
        printf("; contact sheet %ux%u (%u columns)", (unsigned)r->sheet.image.width, (unsigned)r->sheet.image.height,
               (unsigned)cols);
    printf("\n");
    return 0;
}

static void shading_options(render_run *r)
{
    static const ls_real key[3] = {(ls_real)0.48, (ls_real)0.64, (ls_real)0.6};
    static const ls_real fill[3] = {(ls_real)-0.6, (ls_real)-0.48, (ls_real)-0.64};
    int k;
    ls_shade_opts_init(&r->opts);
    r->opts.mode = r->a.mode;
    for (k = 0; k < 3; k++) {
        r->lights[0].dir[k] = key[k];
        r->lights[1].dir[k] = fill[k];
        r->opts.ambient[k] = (ls_real)0.05;
    }
    r->lights[0].rgb[0] = (ls_real)1;
    r->lights[0].rgb[1] = (ls_real)0.95;
    r->lights[0].rgb[2] = (ls_real)0.9;
    r->lights[1].rgb[0] = (ls_real)0.15;
    r->lights[1].rgb[1] = (ls_real)0.2;
    r->lights[1].rgb[2] = (ls_real)0.35;
    r->opts.lights = r->lights;
    r->opts.light_count = 2;
    r->opts.sh = r->sh;
}

static double ms(uint64_t t0, uint64_t t1)
{
    return (double)(t1 - t0) * 1e-6;
}

/* DIR/transforms.json: the views as a camera dataset (scene.h's format, read
 * by `largesteps fit DIR/transforms.json`), with the lighting recorded. */
static int dataset_body(FILE *f, void *ctx)
{
    const render_run *r = (const render_run *)ctx;
    uint32_t v, i, k;
    fprintf(f, "{\n  \"camera_angle_%s\": %.17g,\n  \"w\": %u,\n  \"h\": %u,\n", r->fov_axis == LS_FOV_Y ? "y" : "x",
            (double)r->fov, (unsigned)r->w, (unsigned)r->h);
    if (r->center[0] != 0 || r->center[1] != 0) /* the principal point in pixels (scene.h) */
        fprintf(f, "  \"cx\": %.17g,\n  \"cy\": %.17g,\n", ((double)r->center[0] + 1.0) * r->w / 2.0,
                (1.0 - (double)r->center[1]) * r->h / 2.0);
    fprintf(f, "  \"largesteps_clip\": [%.17g, %.17g],\n  \"largesteps_background\": [0, 0, 0],\n",
            (double)r->near_plane, (double)r->far_plane);
    if (r->opts.mode == LS_SHADE_MASK) {
        fprintf(f, "  \"largesteps_lighting\": \"mask\",\n");
    } else if (r->opts.mode == LS_SHADE_SH) {
        fprintf(f, "  \"largesteps_sh\": [");
        for (k = 0; k < 27; k++) fprintf(f, "%s%.17g", k > 0 ? ", " : "", (double)r->sh[k]);
        fprintf(f, "],\n");
    } /* lambert: no SH form; the dataset leaves its lighting unknown */
    fprintf(f, "  \"frames\": [\n");
    for (v = 0; v < r->a.views; v++) {
        const double *m = r->c2w + 16u * v;
        fprintf(f, "    {\"file_path\": \"view_%03u.png\", \"transform_matrix\": [", (unsigned)v);
        for (i = 0; i < 4; i++)
            fprintf(f, "%s[%.17g, %.17g, %.17g, %.17g]", i > 0 ? ", " : "", m[4 * i], m[4 * i + 1], m[4 * i + 2],
                    m[4 * i + 3]);
        fprintf(f, "]}%s\n", v + 1 < r->a.views ? "," : "");
    }
    fprintf(f, "  ]\n}\n");
    return 1;
}

/* The camera-to-world matrix of a rigid world-to-view matrix. */
static void invert_view(const ls_real view[16], double c2w[16])
{
    int i, k;
    for (i = 0; i < 3; i++) {
        for (k = 0; k < 3; k++) c2w[4 * i + k] = (double)view[4 * k + i];
        c2w[4 * i + 3] = -((double)view[i] * (double)view[3] + (double)view[4 + i] * (double)view[7] +
                           (double)view[8 + i] * (double)view[11]);
    }
    c2w[12] = c2w[13] = c2w[14] = 0;
    c2w[15] = 1;
}

/* The views, the contact sheet and the dataset appear together or not at all. */
static int render_views_into(render_run *r, ls_posix_outset *set);

static int render_views(render_run *r)
{
    ls_posix_outset *set = ls_posix_outset_begin(r->a.out_dir);
    int rc;
    if (set == NULL) return fprintf(stderr, "largesteps render: out of memory\n"), 1;
    r->c2w = (double *)malloc(16u * sizeof(double) * r->a.views);
    if (r->c2w == NULL) {
        ls_posix_outset_abort(set);
        return fprintf(stderr, "largesteps render: out of memory\n"), 1;
    }
    rc = render_views_into(r, set);
    if (rc == 0 && !ls_posix_outset_add(set, "transforms.json", dataset_body, r)) {
        fprintf(stderr, "largesteps: %s\n", ls_posix_write_error());
        rc = 1;
    }
    free(r->c2w);
    r->c2w = NULL;
    if (rc != 0) {
        ls_posix_outset_abort(set);
        return rc;
    }
    return ls_posix_outset_commit(set) ? 0 : 1;
}

static int render_views_into(render_run *r, ls_posix_outset *set)
{
    uint32_t v;
    uint64_t t_all = ls_posix_clock_ns(NULL);
    size_t files = 0;
    ls_diag d;
    for (v = 0; v < r->a.views; v++) {
        const ls_real *mvp = r->mvp + 16u * v;
        ls_view view;
        uint64_t t0, t1, t2, t3;
        size_t i, n = 4 * (size_t)r->w * r->h, fsize, used;
        char name[64];
        ls_status st;
        ls_diag_clear(&d);
        invert_view(r->w2v + 16u * v, r->c2w + 16u * v);
        t0 = ls_posix_clock_ns(NULL);
        st = ls_raster(&r->vis, run_view(r, mvp, &view), &r->work, &d);
        t1 = ls_posix_clock_ns(NULL);
        if (st == LS_OK) st = ls_shade(&view, r->rgba, &d);
        t2 = ls_posix_clock_ns(NULL);
        if (st != LS_OK) return fail("render", st, &d);
        for (i = 0; i < n; i++) r->view.pixels[i] = (float)r->rgba[i];
        st = r->with_sheet ? ls_contact_put_image(&r->sheet, v, &r->view) : LS_OK;
        if (st != LS_OK) return fail("contact sheet", st, NULL);
        snprintf(name, sizeof name, "view_%03u.png", (unsigned)v);
        fsize = write_png(set, name, &r->view, r->a.bits, &r->work);
        t3 = ls_posix_clock_ns(NULL);
        if (fsize == 0) return 1;
        files += fsize;
        used = r->vis_bytes + r->vis.scratch_bytes + r->rgba_bytes;
        printf("view %03u  raster %8.3f ms  shade %8.3f ms  write %8.3f ms  %9lu bytes used "
               "(vis %lu + raster scratch %lu + rgba %lu; %lu bin entries, %u clipped)  %s %lu bytes\n",
               (unsigned)v, ms(t0, t1), ms(t1, t2), ms(t2, t3), (unsigned long)used, (unsigned long)r->vis_bytes,
               (unsigned long)r->vis.scratch_bytes, (unsigned long)r->rgba_bytes, (unsigned long)r->vis.bin_entries,
               (unsigned)r->vis.clipped_triangles, name, (unsigned long)fsize);
    }
    if (r->with_sheet) {
        uint64_t t0 = ls_posix_clock_ns(NULL), t1;
        size_t fsize = write_png(set, "contact.png", &r->sheet.image, r->a.bits, &r->work);
        t1 = ls_posix_clock_ns(NULL);
        if (fsize == 0) return 1;
        printf("contact   %ux%u  write %8.3f ms  contact.png %lu bytes\n", (unsigned)r->sheet.image.width,
               (unsigned)r->sheet.image.height, ms(t0, t1), (unsigned long)fsize);
        files += fsize;
    }
    printf("total     %u views in %.3f ms, %lu bytes written to %s\n", (unsigned)r->a.views,
           ms(t_all, ls_posix_clock_ns(NULL)), (unsigned long)files, r->a.out_dir);
    return 0;
}

int ls_cmd_render(int argc, char **argv)
{
    render_run r;
    int rc;
    struct stat sb;
    memset(&r, 0, sizeof r);
    rc = parse_args(argc, argv, &r.a);
    if (rc <= 0) return rc < 0 ? 0 : usage(stderr);
    if (!ls_posix_check_output_dir(r.a.out_dir)) return 2;
    if (stat(r.a.out_dir, &sb) != 0) {
        if (ls_posix_mkdir_p(r.a.out_dir) != 0) {
            fprintf(stderr, "largesteps: cannot create %s: %s\n", r.a.out_dir, strerror(errno));
            return 1;
        }
    } else if (!S_ISDIR(sb.st_mode)) {
        fprintf(stderr, "largesteps: %s is not a directory\n", r.a.out_dir);
        return 1;
    }
    memcpy(r.sh, ls_job_default_sh, sizeof r.sh); /* the fit's lighting of mesh targets */
    rc = setup(&r);
    if (rc == 0) {
        shading_options(&r);
        rc = render_views(&r);
    }
    free(r.geo_mem);
    free(r.work_mem);
    free(r.scene_mem);
    return rc;
}
