/* selftest.c - the first program: is the library built for this compiler's
 * ls_real, does this machine's floating point behave as the library needs
 * (ls_selftest), and how many bytes does a job take before any is given
 * (the sizing queries).
 *
 *   gcc selftest.c $(pkg-config --cflags --libs largesteps) -o selftest
 */
#include <stdio.h>
#include <largesteps.h>

static LS_ARENA_BUFFER(work, 1 << 20);

int main(void)
{
    ls_arena arena;
    ls_mesh sphere;
    ls_param_config cfg;
    size_t mesh_bytes = 0, ldlt_bytes = 0, cg_bytes = 0;
    ls_status st = ls_selftest(sizeof(ls_real));
    printf("ls_real = %s, self-test: %s\n", LS_REAL_NAME, ls_status_name(st));
    if (st != LS_OK) return 1;

    /* A mesh: ask for its bytes, then build it in an arena. */
    if (ls_icosphere_bytes(3, &mesh_bytes) != LS_OK || ls_arena_init(&arena, work.bytes, sizeof work.bytes) != LS_OK ||
        ls_icosphere(3, &arena, &sphere) != LS_OK)
        return 1;
    printf("icosphere of level 3: %u vertices, %u faces, %zu bytes\n", sphere.vertex_count, sphere.face_count,
           mesh_bytes);

    /* The parameterization of that mesh, with each solver: one query each. */
    ls_param_config_default(&cfg);
    st = ls_param_mesh_bytes(&sphere, &cfg, &arena, &ldlt_bytes);
    cfg.solver = LS_PARAM_CG;
    if (st == LS_OK) st = ls_param_mesh_bytes(&sphere, &cfg, &arena, &cg_bytes);
    if (st != LS_OK) {
        printf("sizing failed: %s\n", ls_status_str(st));
        return 1;
    }
    printf("parameterization, lambda = 19: %zu bytes with the LDL^T, %zu with CG\n", ldlt_bytes, cg_bytes);
    return 0;
}
