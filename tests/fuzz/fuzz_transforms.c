/* tests/fuzz/fuzz_transforms.c - libFuzzer target: camera datasets
 * (transforms.json, ls_scene_parse_transforms, and the JSON reader under it);
 * see fuzz_scene.h. */
#define FUZZ_SCENE_BYTES ls_scene_parse_transforms_bytes
#define FUZZ_SCENE_PARSE ls_scene_parse_transforms
#define FUZZ_SCENE_DATASET 1
#include "fuzz_scene.h"
