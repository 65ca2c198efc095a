/* tests/fuzz/fuzz_mitsuba.c - libFuzzer target: the Mitsuba XML subset
 * (ls_scene_parse_mitsuba); see fuzz_scene.h. */
#define FUZZ_SCENE_BYTES ls_scene_parse_mitsuba_bytes
#define FUZZ_SCENE_PARSE ls_scene_parse_mitsuba
#include "fuzz_scene.h"
