/* tests/test_scene.c - the text scene format and the Mitsuba XML subset:
 * values read back, cameras checked geometrically (where points land in view
 * space, computed here), every malformed statement named with its position,
 * and exact sizing. */
#include "test.h"
#include "sweep.h"

static LS_ARENA_BUFFER(work, 1 << 16);

static const char good_text[] =
    "# a test scene\n"
    "largesteps-scene 1\n"
    "resolution 320 240\n"
    "fov 60 y\n"
    "clip 0.5 50\n"
    "camera 0 0 5  0 0 0\n"
    "image \"views/front view.png\"\n"
    "fov 30\n"
    "views fibonacci 4 2.5 1 2 3   # around (1, 2, 3)\n"
    "views rings 2 3 4\n"
    "lighting sh 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27\n"
    "background 0.25 0.5 1\r\n"
    "target mesh \"meshes/the bunny.obj\"\n"
    "initial icosphere 2\n";

/* p' = view (p, 1): the first three components. */
static void to_view(const ls_real view[16], double x, double y, double z, double out[3])
{
    int r;
    for (r = 0; r < 3; r++)
        out[r] = (double)view[4 * r] * x + (double)view[4 * r + 1] * y + (double)view[4 * r + 2] * z + (double)view[4 * r + 3];
}

static void scene_text_reads_back(void)
{
    ls_arena arena;
    ls_scene s;
    ls_diag d;
    double p[3];
    uint32_t i;
    REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
    CHECK_STATUS(ls_scene_parse(good_text, sizeof good_text - 1, &arena, &s, &d), LS_OK);
    REQUIRE(s.camera_count == 1 + 4 + 6);
    CHECK_EQ(s.width, 320);
    CHECK_EQ(s.height, 240);
    /* camera 0: at (0, 0, 5) looking at the origin, fov 60 on y, clip 0.5..50 */
    to_view(s.cameras[0].view, 0, 0, 0, p);
    CHECK_NEAR(p[0], 0, 1e-6);
    CHECK_NEAR(p[1], 0, 1e-6);
    CHECK_NEAR(p[2], -5, 1e-5);
    to_view(s.cameras[0].view, 1, 0, 5, p); /* world +x is to the right */
    CHECK_NEAR(p[0], 1, 1e-6);
    CHECK_NEAR(s.cameras[0].fov, 60 * 3.14159265358979 / 180, 1e-6);
    CHECK_EQ(s.cameras[0].fov_axis, LS_FOV_Y);
    CHECK_NEAR(s.cameras[0].near_plane, 0.5, 0);
    CHECK_NEAR(s.cameras[0].far_plane, 50, 0);
    CHECK(s.cameras[0].image != NULL && strcmp(s.cameras[0].image, "views/front view.png") == 0);
    /* the Fibonacci cameras: 2.5 from (1, 2, 3), looking at it, fov 30 on x */
    for (i = 1; i <= 4; i++) {
        to_view(s.cameras[i].view, 1, 2, 3, p);
        CHECK_NEAR(p[0], 0, 1e-6);
        CHECK_NEAR(p[1], 0, 1e-6);
        CHECK_NEAR(p[2], -2.5, 1e-5);
        CHECK_EQ(s.cameras[i].fov_axis, LS_FOV_X);
        CHECK_NEAR(s.cameras[i].fov, 30 * 3.14159265358979 / 180, 1e-6);
        CHECK(s.cameras[i].image == NULL);
    }
    for (i = 5; i < 11; i++) {
        to_view(s.cameras[i].view, 0, 0, 0, p);
        CHECK_NEAR(p[2], -4, 1e-5);
    }
    CHECK_EQ(s.lighting, LS_SCENE_LIGHT_SH);
    for (i = 0; i < 27; i++) CHECK(s.sh[i] == (ls_real)(i + 1));
    CHECK(s.background[0] == (ls_real)0.25 && s.background[1] == (ls_real)0.5 && s.background[2] == 1);
    CHECK_EQ(s.target, LS_SCENE_TARGET_MESH);
    CHECK(strcmp(s.target_mesh, "meshes/the bunny.obj") == 0);
    CHECK_EQ(s.initial, LS_SCENE_INITIAL_ICOSPHERE);
    CHECK_EQ(s.initial_level, 2);
    {
        ls_real proj[16];
        CHECK_STATUS(ls_scene_projection(&s, 0, proj), LS_OK);
        /* fov 60 on y: proj[5] = cot(30 deg); aspect 4:3: proj[0] = proj[5] * 3 / 4 */
        CHECK_NEAR(proj[5], 1.7320508075688772, 1e-6);
        CHECK_NEAR(proj[0], 1.7320508075688772 * 0.75, 1e-6);
        CHECK_STATUS(ls_scene_projection(&s, 11, proj), LS_ERR_INVALID);
    }
}

typedef struct bad_case {
    const char *text;
    uint32_t line, column;
    const char *what; /* a substring of diag.what */
} bad_case;

#define HDR "largesteps-scene 1\n"
/* clip planes whose projection overflows ls_real (2 far near > the largest) */
#if LS_REAL_IS_FLOAT
#define HUGE_FAR "3e38"
#define HUGE_FAR_LEN 4u
#else
#define HUGE_FAR "1e308"
#define HUGE_FAR_LEN 5u
#endif
#define OK_REST "resolution 8 8\ncamera 0 0 3 0 0 0\ntarget mesh a.obj\n"

static const bad_case bad_cases[] = {
    {"", 1, 1, "empty scene"},
    {"resolution 8 8\n", 1, 1, "first statement"},
    {"largesteps-scene 2\n", 1, 1, "first statement"},
    {HDR "resolution 8\n", 2, 1, "resolution"},
    {HDR "resolution 8 0\n", 2, 1, "resolution"},
    {HDR "resolution 8 8\nresolution 8 8\n", 3, 1, "twice"},
    {HDR "fov 180\n", 2, 5, "fov"},
    {HDR "fov 40 z\n", 2, 8, "axis"},
    {HDR "clip 2 1\n", 2, 1, "clip"},
    {HDR "clip 1 " HUGE_FAR "\ncamera 0 0 3 0 0 0\n", 3, 1, "overflows"},
    {HDR "camera 0 0 3 0 0\n", 2, 1, "camera"},
    {HDR "camera 0 0 3 0 0 x3\n", 2, 18, "bad number"},
    {HDR "camera 1 1 1 1 1 1\n", 2, 1, "eye equals target"},
    {HDR "camera 0 3 0 0 0 0\n", 2, 1, "parallel"},
    {HDR "views spiral 3 2\n", 2, 7, "fibonacci"},
    {HDR "views fibonacci 0 2\n", 2, 17, "counts"},
    {HDR "views fibonacci 5000 2\n", 2, 17, "counts"},
    {HDR "views fibonacci 4 -1\n", 2, 19, "distance"},
    {HDR "views rings 100 100 3\n", 2, 13, "LS_SCENE_MAX_VIEWS"},
    {HDR "image a.png\n", 2, 1, "no camera"},
    {HDR "camera 0 0 3 0 0 0\nimage a.png\nimage b.png\n", 4, 1, "has one already"},
    {HDR "lighting sh 1 2 3\n", 2, 1, "27 numbers"},
    {HDR "lighting envmap sky.pfm -2\n", 2, 25, "scale"},
    {HDR "lighting sun\n", 2, 10, "mask, sh or envmap"},
    {HDR "background 1 1\n", 2, 1, "background"},
    {HDR "target images\n" "resolution 8 8\ncamera 0 0 3 0 0 0\n", 5, 1, "no 'image'"},
    {HDR "target cube\n", 2, 8, "target"},
    {HDR "initial icosphere 12\n", 2, 19, "level"},
    {HDR "teapot 3\n", 2, 1, "unknown statement"},
    {HDR "image \"a.png\n", 2, 7, "unterminated quote"},
    {HDR "background 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1\n", 2, 1,
     "too many values"},
    {HDR "resolution 8 8\ncamera 0 0 3 0 0 0\n", 4, 1, "no 'target'"},
    {HDR "resolution 8 8\ntarget mesh a.obj\n", 4, 1, "no camera"},
    {HDR "camera 0 0 3 0 0 0\ntarget mesh a.obj\n", 4, 1, "no 'resolution'"},
};

/* Every case of a table fails to parse with LS_ERR_PARSE at its line and
 * column with its message, leaving the arena and the scene untouched, and
 * the sizing query fails the same way. */
typedef ls_status (*parse_fn)(const char *, size_t, ls_arena *, ls_scene *, ls_diag *);
typedef ls_status (*bytes_fn)(const char *, size_t, size_t *, ls_diag *);
static void check_bad_cases(const bad_case *cases, size_t n, parse_fn parse, bytes_fn bytes_query)
{
    size_t i;
    for (i = 0; i < n; i++) {
        const bad_case *c = &cases[i];
        ls_arena arena;
        ls_scene s;
        ls_diag d;
        size_t bytes;
        ls_status st;
        REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
        memset(&s, 0x5A, sizeof s);
        st = parse(c->text, strlen(c->text), &arena, &s, &d);
        CHECK_MSG(st == LS_ERR_PARSE, "case %u: %s", (unsigned)i, ls_status_name(st));
        if (st != LS_ERR_PARSE) continue;
        CHECK_MSG(d.line == c->line && d.column == c->column, "case %u: at %u:%u, wanted %u:%u (%s)", (unsigned)i,
                  (unsigned)d.line, (unsigned)d.column, (unsigned)c->line, (unsigned)c->column, d.what);
        CHECK_MSG(strstr(d.what, c->what) != NULL, "case %u: '%s' lacks '%s'", (unsigned)i, d.what, c->what);
        CHECK_EQ(ls_arena_used(&arena), 0);
        CHECK(((const unsigned char *)&s)[0] == 0x5A);
        CHECK_STATUS(bytes_query(c->text, strlen(c->text), &bytes, NULL), LS_ERR_PARSE);
    }
}

static void scene_text_errors_are_named(void)
{
    check_bad_cases(bad_cases, sizeof bad_cases / sizeof bad_cases[0], ls_scene_parse, ls_scene_parse_bytes);
    {
        static const char nul[] = HDR "resolution 8 8\0\n";
        ls_arena arena;
        ls_scene s;
        ls_diag d;
        size_t bytes;
        REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
        CHECK_STATUS(ls_scene_parse(nul, sizeof nul - 1, &arena, &s, &d), LS_ERR_PARSE);
        CHECK(strstr(d.what, "NUL") != NULL);
        CHECK_STATUS(ls_scene_parse(NULL, 3, &arena, &s, &d), LS_ERR_INVALID);
        CHECK(strstr(d.what, "text is NULL") != NULL);
        CHECK_STATUS(ls_scene_parse(nul, 3, NULL, &s, &d), LS_ERR_INVALID);
        CHECK(strcmp(d.what, "arena is NULL") == 0);
        CHECK_STATUS(ls_scene_parse_mitsuba(nul, 3, &arena, NULL, &d), LS_ERR_INVALID);
        CHECK(strcmp(d.what, "scene is NULL") == 0);
        CHECK_STATUS(ls_scene_parse_transforms_bytes(nul, 3, NULL, &d), LS_ERR_INVALID);
        CHECK(strcmp(d.what, "bytes is NULL") == 0);
        CHECK_STATUS(ls_scene_parse_mitsuba_bytes(NULL, 3, &bytes, &d), LS_ERR_INVALID);
        CHECK(strstr(d.what, "text is NULL") != NULL);
    }
    {
        static const char ok[] = HDR OK_REST;
        ls_arena arena;
        ls_scene s;
        REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
        CHECK_STATUS(ls_scene_parse(ok, sizeof ok - 1, &arena, &s, NULL), LS_OK);
        CHECK_EQ(s.lighting, LS_SCENE_LIGHT_MASK);
        CHECK_EQ(s.initial, LS_SCENE_INITIAL_ICOSPHERE);
        CHECK_EQ(s.initial_level, 3);
        CHECK_NEAR(s.cameras[0].fov, 45 * 3.14159265358979 / 180, 1e-6);
    }
}

static const char mitsuba_text[] =
    "<?xml version=\"1.0\"?>\n"
    "<!-- the reference's layout -->\n"
    "<scene version=\"2.0.0\">\n"
    "  <default name=\"resx\" value=\"200\"/>\n"
    "  <default name=\"resy\" value=\"100\"/>\n"
    "  <sensor type=\"perspective\">\n"
    "    <float name=\"fov\" value=\"45\"/>\n"
    "    <float name=\"near_clip\" value=\"0.1\"/>\n"
    "    <float name=\"far_clip\" value=\"100\"/>\n"
    "    <transform name=\"to_world\">\n"
    "      <lookat origin=\"0, 0, 5\" target=\"0, 0, 0\" up=\"0, 1, 0\"/>\n"
    "    </transform>\n"
    "    <film type=\"hdrfilm\"><integer name=\"width\" value=\"$resx\"/>"
    "<integer name=\"height\" value=\"$resy\"/></film>\n"
    "  </sensor>\n"
    "  <sensor type=\"perspective\">\n"
    "    <float name=\"fov\" value=\"30\"/>\n"
    "    <string name=\"fov_axis\" value=\"y\"/>\n"
    "    <transform name=\"to_world\">\n"
    "      <rotate y=\"1\" angle=\"90\"/>\n"
    "      <translate value=\"0 0 5\"/>\n"
    "    </transform>\n"
    "    <film type=\"hdrfilm\"><integer name=\"width\" value=\"$resx\"/>"
    "<integer name=\"height\" value=\"$resy\"/></film>\n"
    "  </sensor>\n"
    "  <emitter type=\"envmap\"><string name=\"filename\" value=\"sky.pfm\"/>"
    "<float name=\"scale\" value=\"2.5\"/></emitter>\n"
    "  <shape type=\"ply\" id=\"mesh-source\"><string name=\"filename\" value=\"source.ply\"/></shape>\n"
    "  <shape type=\"ply\" id=\"mesh-target\"><string name=\"filename\" value=\"target.ply\"/>"
    "<bsdf type=\"diffuse\"/></shape>\n"
    "</scene>\n";

static void scene_mitsuba_reads_back(void)
{
    ls_arena arena;
    ls_scene s;
    ls_diag d;
    double p[3];
    REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
    CHECK_STATUS(ls_scene_parse_mitsuba(mitsuba_text, sizeof mitsuba_text - 1, &arena, &s, &d), LS_OK);
    REQUIRE(s.camera_count == 2);
    CHECK_EQ(s.width, 200);
    CHECK_EQ(s.height, 100);
    /* sensor 0: at (0, 0, 5) looking at the origin; Mitsuba's image x is
     * world +x there too, so our view keeps +x to the right */
    to_view(s.cameras[0].view, 0, 0, 0, p);
    CHECK_NEAR(p[0], 0, 1e-6);
    CHECK_NEAR(p[2], -5, 1e-5);
    to_view(s.cameras[0].view, 1, 0.5, 5, p);
    CHECK_NEAR(p[0], 1, 1e-6);
    CHECK_NEAR(p[1], 0.5, 1e-6);
    CHECK_NEAR(p[2], 0, 1e-6);
    CHECK_NEAR(s.cameras[0].near_plane, 0.1, 1e-7);
    CHECK_NEAR(s.cameras[0].far_plane, 100, 0);
    CHECK_EQ(s.cameras[0].fov_axis, LS_FOV_X);
    /* sensor 1: translate(0, 0, 5) after rotate(y, 90): at (0, 0, 5) looking along +x */
    to_view(s.cameras[1].view, 1, 0, 5, p);
    CHECK_NEAR(p[0], 0, 1e-6);
    CHECK_NEAR(p[1], 0, 1e-6);
    CHECK_NEAR(p[2], -1, 1e-6);
    CHECK_EQ(s.cameras[1].fov_axis, LS_FOV_Y);
    CHECK_NEAR(s.cameras[1].near_plane, 0.01, 1e-8); /* Mitsuba's default */
    CHECK_EQ(s.lighting, LS_SCENE_LIGHT_ENVMAP);
    CHECK(strcmp(s.envmap, "sky.pfm") == 0);
    CHECK_NEAR(s.envmap_scale, 2.5, 0);
    CHECK_EQ(s.target, LS_SCENE_TARGET_MESH);
    CHECK(strcmp(s.target_mesh, "target.ply") == 0);
    CHECK_EQ(s.initial, LS_SCENE_INITIAL_MESH);
    CHECK(strcmp(s.initial_mesh, "source.ply") == 0);
}

static const bad_case bad_xml[] = {
    {"", 1, 1, "no sensor"},
    {"<shape/>", 1, 1, "root element"},
    {"<scene><sensor type=\"orthographic\"/></scene>", 1, 8, "perspective"},
    {"<scene><sensor type=\"perspective\"></sensor></scene>", 1, 35, "without fov"},
    {"<scene><sensor type=\"perspective\"><float name=\"fov\" value=\"abc\"/></sensor></scene>", 1, 60,
     "fov"},
    {"<scene><sensor type=\"perspective\"><string name=\"fov_axis\" value=\"diagonal\"/></sensor></scene>", 1, 66,
     "fov_axis"},
    {"<scene><sensor type=\"perspective\"><transform name=\"to_world\"><rotate angle=\"3\"/></transform></sensor></scene>",
     1, 62, "transform"},
    {"<scene><sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/><float name=\"far_clip\" value=\"" HUGE_FAR
     "\"/></sensor></scene>", 1, 98u + HUGE_FAR_LEN, "overflows"},
    {"<scene><sensor type=\"perspective\"><transform name=\"to_world\"><scale value=\"0\"/></transform>"
     "<float name=\"fov\" value=\"40\"/></sensor></scene>", 1, 122, "singular"},
    {"<scene><sensor type=\"perspective\">", 1, 35, "unclosed"},
    {"<scene></scene></scene>", 1, 16, "closing tag"},
    {"<scene><sensor type=perspective/></scene>", 1, 21, "malformed"},
    {"<scene><shape type=\"ply\" id=\"mesh-target\"/></scene>", 1, 8, "without filename"},
};

static void scene_mitsuba_errors_are_named(void)
{
    check_bad_cases(bad_xml, sizeof bad_xml / sizeof bad_xml[0], ls_scene_parse_mitsuba, ls_scene_parse_mitsuba_bytes);
}

/* ---- camera datasets (transforms.json) ---- */

/* Two frames in the NeRF-synthetic form (no w, h; no extension on the first
 * path), members in an order where frames come before the intrinsics. Frame 0:
 * the camera at (0, 0, 4) looking down -z; frame 1: at (4, 0, 0) looking
 * down -x (rotated +90 degrees about y). */
static const char transforms_text[] =
    "{\n"
    "  \"frames\": [\n"
    "    {\"file_path\": \"./train/r_0\", \"rotation\": 0.012566,\n"
    "     \"transform_matrix\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]]},\n"
    "    {\"transform_matrix\": [[0, 0, 1, 4], [0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1]],\n"
    "     \"file_path\": \"images\\/caf\\u00e9.jpg\", \"extra\": {\"nested\": [1, {\"a\": null}, true]}}\n"
    "  ],\n"
    "  \"camera_angle_x\": 0.6911112070083618,\n"
    "  \"aabb_scale\": 4\n"
    "}\n";

static void transforms_reads_back(void)
{
    ls_arena arena;
    ls_scene s;
    ls_diag d;
    ls_real proj[16];
    double p[3];
    size_t bytes;
    REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
    CHECK_STATUS(ls_scene_parse_transforms_bytes(transforms_text, sizeof transforms_text - 1, &bytes, &d), LS_OK);
    CHECK_STATUS(ls_scene_parse_transforms(transforms_text, sizeof transforms_text - 1, &arena, &s, &d), LS_OK);
    CHECK_EQ(ls_arena_used(&arena), bytes);
    REQUIRE(s.camera_count == 2);
    CHECK(strcmp(s.cameras[0].image, "./train/r_0.png") == 0);
    CHECK(strcmp(s.cameras[1].image, "images/caf\xc3\xa9.jpg") == 0);
    CHECK_NEAR(s.cameras[0].fov, 0.6911112070083618, 1e-7);
    CHECK_EQ(s.cameras[0].fov_axis, LS_FOV_X);
    CHECK_EQ(s.width, 0); /* no w, h: the images give them */
    CHECK_EQ(s.lighting, LS_SCENE_LIGHT_UNKNOWN);
    CHECK_EQ(s.target, LS_SCENE_TARGET_IMAGES);
    /* the origin is 4 in front of both cameras; a point to the camera's right
     * (+x of camera 0, -z of the world for camera 1) comes out at +x */
    to_view(s.cameras[0].view, 0, 0, 0, p);
    CHECK_NEAR(p[0], 0, 1e-12);
    CHECK_NEAR(p[2], -4, 1e-12);
    to_view(s.cameras[1].view, 0, 0, 0, p);
    CHECK_NEAR(p[0], 0, 1e-12);
    CHECK_NEAR(p[1], 0, 1e-12);
    CHECK_NEAR(p[2], -4, 1e-12);
    to_view(s.cameras[1].view, 0, 0, -1, p);
    CHECK_NEAR(p[0], 1, 1e-12);
    /* without a resolution there is no projection yet */
    CHECK_STATUS(ls_scene_projection(&s, 0, proj), LS_ERR_INVALID);
}

/* fl_x, w, h, cx, cy and the members `largesteps render` writes. The point on
 * the optical axis must land on the principal point. */
static void transforms_intrinsics(void)
{
    static const char text[] =
        "{\"fl_x\": 100, \"fl_y\": 100, \"cx\": 60, \"cy\": 30, \"w\": 160, \"h\": 80,\n"
        " \"largesteps_sh\": [1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27],\n"
        " \"largesteps_background\": [0.5, 0.25, 1], \"largesteps_clip\": [0.1, 20], \"k1\": 0, \"p2\": 0,\n"
        " \"frames\": [{\"file_path\": \"a.png\", \"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}]}";
    ls_arena arena;
    ls_scene s;
    ls_real proj[16], clip[4];
    double fov = 2 * atan(160.0 / 200.0);
    int k;
    REQUIRE(ls_arena_init(&arena, work.bytes, sizeof work.bytes) == LS_OK);
    CHECK_STATUS(ls_scene_parse_transforms(text, sizeof text - 1, &arena, &s, NULL), LS_OK);
    REQUIRE(s.camera_count == 1);
    CHECK_EQ(s.width, 160);
    CHECK_EQ(s.height, 80);
    CHECK_NEAR(s.cameras[0].fov, fov, 1e-6);
    CHECK_NEAR(s.cameras[0].near_plane, 0.1, 1e-7);
    CHECK_NEAR(s.cameras[0].far_plane, 20, 0);
    CHECK_EQ(s.lighting, LS_SCENE_LIGHT_SH);
    for (k = 0; k < 27; k++) CHECK(s.sh[k] == (ls_real)(k + 1));
    CHECK(s.background[0] == (ls_real)0.5 && s.background[1] == (ls_real)0.25 && s.background[2] == 1);
    CHECK_STATUS(ls_scene_projection(&s, 0, proj), LS_OK);
    /* (0, 0, -2) in view space: on the axis; pixel (60, 30) is NDC (-0.25, 0.25) */
    for (k = 0; k < 4; k++) clip[k] = proj[4 * k + 2] * (ls_real)-2 + proj[4 * k + 3];
    CHECK_NEAR(clip[0] / clip[3], -0.25, 1e-6);
    CHECK_NEAR(clip[1] / clip[3], 0.25, 1e-6);
    /* (1, 0, -2): fl_x 100 pixels per unit at depth 1, so 50 pixels right of cx */
    for (k = 0; k < 4; k++) clip[k] = proj[4 * k] + proj[4 * k + 2] * (ls_real)-2 + proj[4 * k + 3];
    CHECK_NEAR((clip[0] / clip[3] + 1) * 80, 60 + 50, 1e-4);
}

#define FRAME "{\"file_path\": \"a\", \"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}"
#define TAIL "\"camera_angle_x\": 0.7, \"frames\": [" FRAME "]}"
static const bad_case bad_json[] = {
    {"", 1, 1, "empty"},
    {"[]", 1, 1, "one JSON object"},
    {"{" TAIL " x", 1, 120, "more text after"},
    {"{\"camera_angle_x\": 0.7, \"frames\": [" FRAME ",]}", 1, 118, "a value was expected"},
    {"{\"camera_angle_x\" 0.7}", 1, 19, "':' was expected"},
    {"{\"camera_angle_x\": 07, \"frames\": []}", 1, 20, "malformed number"},
    {"{\"camera_angle_x\": .7}", 1, 20, "a value was expected"},
    {"{\"camera_angle_x\": 1.}", 1, 20, "no digit after its decimal point"},
    {"{\"a\": \"\\q\", " TAIL, 1, 8, "unknown escape"},
    {"{\"a\": \"x\ty\", " TAIL, 1, 9, "control character"},
    {"{\"a\": \"\xff\", " TAIL, 1, 8, "not valid UTF-8"},
    {"{\"a\": tru, " TAIL, 1, 7, "unknown word"},
    {"{\"a\": [1, 2}, " TAIL, 1, 12, "',' or ']'"},
    {"{\"a\": 1 " TAIL, 1, 9, "',' or '}'"},
    {"{" TAIL "\n{", 2, 1, "more text after"},
    {"{\"camera_angle_x\": 0.7, \"frames\": [", 1, 36, "ends inside"},
    {"{\"a\": \"open", 1, 7, "closing quote"},
    {"{\"a\": [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]"
     "]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]}",
     1, 70, "nested more than 64"},
    {"{\"camera_angle_x\": 0.7}", 1, 24, "no frames"},
    {"{\"camera_angle_x\": 0.7, \"frames\": [{\"transform_matrix\": [[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}]}", 1, 36,
     "without file_path"},
    {"{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"a\"}]}", 1, 36, "without transform_matrix"},
    {"{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"a\", \"fl_x\": 3}]}", 1, 56, "intrinsics per frame"},
    {"{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"a\", \"transform_matrix\": "
     "[[2,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}]}", 1, 56, "orthonormal"},
    {"{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"a\", \"transform_matrix\": "
     "[[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,1,1]]}]}", 1, 56, "last row"},
    {"{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"a\", \"transform_matrix\": [[1,0,0,0]]}]}", 1, 85,
     "4 rows of 4"},
    {"{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": \"a\\ud800b\", \"transform_matrix\": "
     "[[1,0,0,0],[0,1,0,0],[0,0,1,3],[0,0,0,1]]}]}", 1, 51, "unpaired"},
    {"{\"camera_angle_x\": 0.7, \"frames\": [{\"file_path\": 3}]}", 1, 50, "must be a string"},
    {"{\"k1\": 0.1, " TAIL, 1, 3, "lens distortion"},
    {"{\"frames\": [" FRAME "]}", 1, 96, "no field of view"},
    {"{\"camera_angle_x\": 4, \"frames\": [" FRAME "]}", 1, 3, "between 0 and pi"},
    {"{\"fl_x\": 100, \"fl_y\": 120, \"w\": 10, \"h\": 10, \"frames\": [" FRAME "]}", 1, 3, "non-square pixels"},
    {"{\"w\": 10, " TAIL, 1, 3, "w and h"},
    {"{\"cx\": 5, \"cy\": 5, " TAIL, 1, 3, "cx and cy need"},
    {"{\"largesteps_sh\": [1, 2], " TAIL, 1, 24, "27 finite numbers"},
    {"{\"largesteps_lighting\": \"sun\", " TAIL, 1, 26, "must be \"mask\""},
    {"{\"largesteps_clip\": [2, 1], " TAIL, 1, 3, "0 < near < far"},
    {"{\"frames\": [], " TAIL, 1, 40, "frames given twice"},
};

static void transforms_errors_are_named(void)
{
    check_bad_cases(bad_json, sizeof bad_json / sizeof bad_json[0], ls_scene_parse_transforms,
                    ls_scene_parse_transforms_bytes);
}

typedef struct scene_job {
    const char *text;
    int xml;
    ls_scene s;
} scene_job;
static ls_status scene_run(void *ctx, ls_arena *arena)
{
    scene_job *j = (scene_job *)ctx;
    if (j->xml == 2) return ls_scene_parse_transforms(j->text, strlen(j->text), arena, &j->s, NULL);
    return j->xml ? ls_scene_parse_mitsuba(j->text, strlen(j->text), arena, &j->s, NULL)
                  : ls_scene_parse(j->text, strlen(j->text), arena, &j->s, NULL);
}
static uint64_t scene_hash(void *ctx)
{
    scene_job *j = (scene_job *)ctx;
    return test_hash(&j->s, sizeof j->s, TEST_HASH_SEED);
}
static void scene_reset(void *ctx)
{
    scene_job *j = (scene_job *)ctx;
    memset(&j->s, 0, sizeof j->s);
}

static void scene_arena_sweeps(void)
{
    scene_job job;
    sweep_job sj;
    memset(&sj, 0, sizeof sj);
    memset(&job, 0, sizeof job);
    sj.run = scene_run;
    sj.state_hash = scene_hash;
    sj.reset = scene_reset;
    sj.ctx = &job;
    sj.exact = 1;
    job.text = good_text;
    sj.name = "scene_parse";
    REQUIRE(ls_scene_parse_bytes(good_text, sizeof good_text - 1, &sj.answer, NULL) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
    job.text = mitsuba_text;
    job.xml = 1;
    sj.name = "scene_parse_mitsuba";
    REQUIRE(ls_scene_parse_mitsuba_bytes(mitsuba_text, sizeof mitsuba_text - 1, &sj.answer, NULL) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
    job.text = transforms_text;
    job.xml = 2;
    sj.name = "scene_parse_transforms";
    REQUIRE(ls_scene_parse_transforms_bytes(transforms_text, sizeof transforms_text - 1, &sj.answer, NULL) == LS_OK);
    CHECK_EQ(sweep_arena(&sj), 0);
}

int main(void)
{
    TEST_INIT("test_scene");
    TEST_RUN(scene_text_reads_back);
    TEST_RUN(scene_text_errors_are_named);
    TEST_RUN(scene_mitsuba_reads_back);
    TEST_RUN(scene_mitsuba_errors_are_named);
    TEST_RUN(transforms_reads_back);
    TEST_RUN(transforms_intrinsics);
    TEST_RUN(transforms_errors_are_named);
    TEST_RUN(scene_arena_sweeps);
    return TEST_END();
}
