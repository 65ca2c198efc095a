/* largesteps/scene.h - reconstruction scenes: cameras, resolution, lighting,
 * the target and the initial mesh, read from a small text format or from the
 * subset of Mitsuba XML that the reference's published scenes use.
 *
 * The library opens no file: a scene names its files (meshes, images, the
 * environment map) by path, and the caller (the command-line program, or
 * firmware with its own storage) loads them. Paths are copied into the arena,
 * NUL-terminated, exactly as written in the scene.
 *
 * The text format ("largesteps-scene 1"), one statement per line; `#` starts
 * a comment; a token with spaces is written in double quotes; angles are in
 * degrees, lengths in scene units:
 *
 *   largesteps-scene 1                    first statement, required
 *   resolution W H                        image size (required, 1..65536 each)
 *   fov DEGREES [x|y]                     field of view for the cameras that
 *                                         follow (default 45 x: horizontal)
 *   clip NEAR FAR                         clip planes for the cameras that
 *                                         follow (default 0.01 100)
 *   camera EX EY EZ TX TY TZ [UX UY UZ]   a look-at camera (up default 0 1 0)
 *   views fibonacci N DISTANCE [CX CY CZ] N cameras on a Fibonacci sphere of
 *                                         radius DISTANCE around C (default 0)
 *   views rings R P DISTANCE [CX CY CZ]   R rings of P cameras (camera.h)
 *   image PATH                            target image of the last camera
 *   lighting mask                         silhouettes only (white on black)
 *   lighting sh C0 ... C26                9 RGB SH coefficients (shade.h order)
 *   lighting envmap PATH [SCALE]          equirectangular map (PFM), SH
 *                                         projected by the caller; scale 1
 *   background R G B                      constant background (default 0 0 0)
 *   target mesh PATH                      render the target from this mesh
 *   target images                         the cameras' `image` files
 *   initial mesh PATH                     start from this mesh
 *   initial icosphere LEVEL               start from an icosphere (default 3)
 *
 * Every malformed statement gives LS_ERR_PARSE with diag->line, column and
 * `what` naming the problem (an unknown keyword, a missing or extra value, a
 * number out of range, a statement given twice, a camera looking at its own
 * position, ...); a scene without cameras, resolution or target is rejected
 * with LS_ERR_PARSE naming what is missing.
 *
 * Mitsuba XML (ls_scene_parse_mitsuba): <default name= value=> substitutions
 * ($name), <sensor type="perspective"> with fov, fov_axis (x, y; others
 * rejected), near_clip, far_clip, a to_world <transform> of <translate>,
 * <rotate> (axis x/y/z or value, angle in degrees), <scale>, <lookat> and
 * <matrix> applied in document order, and <film> width/height; an <emitter
 * type="envmap"> with filename and scale; <shape type="ply"> with filename,
 * the one with id "mesh-target" as the target and "mesh-source" as the
 * initial mesh. Mitsuba cameras look down +z with +x to the left; ours look
 * down -z with +x to the right, so view = R_y(pi) inverse(to_world). Other
 * elements are skipped. No recursion: an explicit element stack of at most
 * LS_SCENE_XML_DEPTH levels.
 *
 * Camera datasets (ls_scene_parse_transforms): the NeRF-synthetic / Blender
 * / instant-ngp `transforms.json`, one JSON object (RFC 8259, read strictly:
 * a malformed text is LS_ERR_PARSE with its line and column, also inside
 * members that are skipped). Members:
 *   frames             [{"file_path": PATH, "transform_matrix": [[4], [4],
 *                      [4], [4]]}, ...]: one camera a frame. file_path is
 *                      relative to the JSON file; ".png" is added when its
 *                      last component has no extension. transform_matrix is
 *                      camera-to-world, rows first, OpenGL camera axes (the
 *                      camera looks down -z, +y up): a rotation and a
 *                      translation, last row 0 0 0 1. Other frame members are
 *                      skipped; intrinsics per frame are refused.
 *   camera_angle_x     horizontal field of view, radians; or camera_angle_y
 *   fl_x, fl_y         focal lengths in pixels (with w, h; equal: square pixels)
 *   cx, cy             principal point in pixels (with w, h): camera.center
 *   w, h               resolution; without them width = height = 0, and the
 *                      caller sets them from the images' size
 *   k1 k2 k3 p1 p2     lens distortion: refused unless 0
 *   largesteps_sh      27 numbers: the SH lighting the images were rendered
 *                      with; largesteps_lighting "mask": silhouettes only;
 *                      neither: LS_SCENE_LIGHT_UNKNOWN
 *   largesteps_background [R, G, B]; largesteps_clip [near, far]
 *                      (default 0.01 100)
 * Other members (aabb_scale, scale, offset, ...) are skipped. The target is
 * LS_SCENE_TARGET_IMAGES (RGBA images: alpha is the mask), the start the
 * default icosphere.
 */
#ifndef LARGESTEPS_SCENE_H
#define LARGESTEPS_SCENE_H

#include <largesteps/core.h>
#include <largesteps/status.h>
#include <largesteps/arena.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LS_SCENE_LIGHT_MASK   0u /* silhouettes only */
#define LS_SCENE_LIGHT_SH     1u /* scene.sh holds the coefficients */
#define LS_SCENE_LIGHT_ENVMAP 2u /* scene.envmap names the map, scene.envmap_scale scales it */
#define LS_SCENE_LIGHT_UNKNOWN 3u /* a dataset that does not say: the caller estimates it or fits masks */

#define LS_SCENE_TARGET_MESH   1u /* render scene.target_mesh */
#define LS_SCENE_TARGET_IMAGES 2u /* every camera has an image */

#define LS_SCENE_INITIAL_ICOSPHERE 1u /* ls_icosphere(initial_level), fitted by the caller */
#define LS_SCENE_INITIAL_MESH      2u /* scene.initial_mesh */

#define LS_SCENE_MAX_VIEWS 4096u /* cameras per scene */
#define LS_SCENE_XML_DEPTH 32u   /* nesting of Mitsuba XML elements */

typedef struct ls_scene_camera {
    ls_real view[16];   /* world -> view (camera.h conventions) */
    ls_real fov;        /* full field of view, radians */
    uint32_t fov_axis;  /* LS_FOV_X or LS_FOV_Y */
    ls_real near_plane; /* 0 < near < far */
    ls_real far_plane;
    const char *image;  /* target image path, or NULL */
    ls_real center[2];  /* principal point in normalised device coordinates ((0, 0): the image centre) */
} ls_scene_camera;

typedef struct ls_scene {
    uint32_t width, height;
    uint32_t camera_count;
    ls_scene_camera *cameras;
    uint32_t lighting;      /* LS_SCENE_LIGHT_* */
    ls_real sh[27];         /* LS_SCENE_LIGHT_SH */
    const char *envmap;     /* LS_SCENE_LIGHT_ENVMAP */
    ls_real envmap_scale;
    ls_real background[3];
    uint32_t target;        /* LS_SCENE_TARGET_* */
    const char *target_mesh;
    uint32_t initial;       /* LS_SCENE_INITIAL_* */
    uint32_t initial_level; /* icosphere level */
    const char *initial_mesh;
} ls_scene;

/* ls_scene_parse_bytes: exact arena bytes of ls_scene_parse on this text (a
 * first parsing pass that only counts). O(length). Errors: as
 * ls_scene_parse (a malformed scene is reported here already). */
ls_status ls_scene_parse_bytes(const char *text, size_t length, size_t *bytes, ls_diag *diag);

/* ls_scene_parse: reads a text scene (format above) into *scene: cameras
 * and paths from the arena's bottom. O(length + cameras). Errors:
 * LS_ERR_INVALID (NULL), LS_ERR_PARSE (diag: line, column, what),
 * LS_ERR_TOO_LARGE (more than LS_SCENE_MAX_VIEWS cameras), LS_ERR_NOMEM; on
 * failure the arena and *scene are unchanged. */
ls_status ls_scene_parse(const char *text, size_t length, ls_arena *arena, ls_scene *scene, ls_diag *diag);

/* ls_scene_parse_mitsuba_bytes / ls_scene_parse_mitsuba: the same for the
 * Mitsuba XML subset above. A scene without a sensor, or with a sensor
 * missing fov, is LS_ERR_PARSE; without a mesh-target shape, the target is
 * LS_SCENE_TARGET_IMAGES with no images (the caller supplies them); lighting
 * is LS_SCENE_LIGHT_ENVMAP when an envmap emitter is present, else
 * LS_SCENE_LIGHT_MASK. Costs and errors as ls_scene_parse. */
ls_status ls_scene_parse_mitsuba_bytes(const char *text, size_t length, size_t *bytes, ls_diag *diag);
ls_status ls_scene_parse_mitsuba(const char *text, size_t length, ls_arena *arena, ls_scene *scene,
                                 ls_diag *diag);

/* ls_scene_parse_transforms_bytes / ls_scene_parse_transforms: the same for
 * a camera dataset (transforms.json, above). Costs and errors as
 * ls_scene_parse. */
ls_status ls_scene_parse_transforms_bytes(const char *text, size_t length, size_t *bytes, ls_diag *diag);
ls_status ls_scene_parse_transforms(const char *text, size_t length, ls_arena *arena, ls_scene *scene,
                                    ls_diag *diag);

/* ls_scene_projection: the projection matrix of camera `index` for the
 * scene's resolution (ls_camera_perspective with aspect = width / height),
 * its principal point moved to camera.center. Errors: LS_ERR_INVALID (NULL,
 * index out of range, no resolution yet), as ls_camera_perspective. O(1). */
ls_status ls_scene_projection(const ls_scene *scene, uint32_t index, ls_real proj[16]);

#ifdef __cplusplus
}
#endif

#endif /* LARGESTEPS_SCENE_H */
