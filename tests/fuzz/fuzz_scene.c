/* tests/fuzz/fuzz_scene.c - libFuzzer target: text scenes
 * ("largesteps-scene 1", ls_scene_parse); see fuzz_scene.h. */
#define FUZZ_SCENE_BYTES ls_scene_parse_bytes
#define FUZZ_SCENE_PARSE ls_scene_parse
#include "fuzz_scene.h"
