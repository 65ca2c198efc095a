/* own_gradient.c - large steps with a gradient of your own: the mesh, the
 * parameterization and UniformAdam, as the reference's Python
 *
 *   M = compute_matrix(v, f, lambda_=19)
 *   u = to_differential(M, v)
 *   opt = AdamUniform([u], lr)
 *   for it in range(n):
 *       v = from_differential(M, u); loss = f(v); loss.backward(); opt.step()
 *
 * Here the loss is the mean squared distance of the vertices to a target (the
 * sphere stretched into an ellipsoid); its gradient dL/dx comes from you,
 * ls_param_adjoint turns it into dL/du, and UniformAdam steps u.
 */
#include <stdio.h>
#include <largesteps.h>

static LS_ARENA_BUFFER(work, 4 << 20);

int main(void)
{
    ls_arena arena;
    ls_mesh mesh;
    ls_param M;
    ls_param_config pc;
    ls_optim opt;
    ls_optim_config oc;
    ls_diag diag;
    ls_real *x, *u, *gx, *gu, *target;
    uint32_t i, it, n3;
    ls_status st = ls_arena_init(&arena, work.bytes, sizeof work.bytes);

    /* The mesh: an icosphere of 642 vertices; the target: it, stretched. */
    if (st == LS_OK) st = ls_icosphere(3, &arena, &mesh);
    if (st != LS_OK) return 1;
    n3 = 3u * mesh.vertex_count;
    x = ls_arena_alloc(&arena, n3, sizeof(ls_real));
    u = ls_arena_alloc(&arena, n3, sizeof(ls_real));
    gx = ls_arena_alloc(&arena, n3, sizeof(ls_real));
    gu = ls_arena_alloc(&arena, n3, sizeof(ls_real));
    target = ls_arena_alloc(&arena, n3, sizeof(ls_real));
    if (target == NULL) return 1;
    for (i = 0; i < n3; i++) target[i] = mesh.positions[i] * (i % 3 == 0 ? (ls_real)1.5 : (ls_real)0.75);

    /* M = I + 19 L and u = M x; UniformAdam on u, one block of 3n values. */
    ls_param_config_default(&pc);
    st = ls_param_init_mesh(&M, &mesh, &pc, &arena, &diag);
    if (st == LS_OK) st = ls_param_to_differential(&M, mesh.positions, u);
    if (st == LS_OK) st = ls_optim_config_default(LS_OPTIM_UNIFORM_ADAM, &oc);
    oc.lr = (ls_real)0.02;
    if (st == LS_OK) st = ls_optim_init(&opt, &oc, n3, 1, &n3, &arena);
    if (st != LS_OK) {
        printf("setup: %s (%s)\n", ls_status_str(st), diag.what);
        return 1;
    }

    for (it = 0; it <= 200 && st == LS_OK; it++) {
        ls_real loss = 0;
        st = ls_param_from_differential(&M, u, x);          /* x = M^-1 u */
        for (i = 0; i < n3; i++) {                          /* your loss and dL/dx */
            ls_real d = x[i] - target[i];
            loss += d * d / (ls_real)n3;
            gx[i] = 2 * d / (ls_real)n3;
        }
        if (it % 40 == 0) printf("iteration %3u: loss %.4e\n", it, (double)loss);
        if (st == LS_OK) st = ls_param_adjoint(&M, gx, gu); /* dL/du = M^-1 dL/dx */
        if (st == LS_OK) st = ls_optim_step(&opt, u, gu, &diag);
    }
    if (st != LS_OK) {
        printf("iteration %u: %s (%s)\n", it, ls_status_str(st), diag.what);
        return 1;
    }
    printf("vertex 0: (%.3f, %.3f, %.3f), target (%.3f, %.3f, %.3f)\n", (double)x[0], (double)x[1], (double)x[2],
           (double)target[0], (double)target[1], (double)target[2]);
    return 0;
}
