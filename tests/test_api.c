/* test_api.c - the way in: configuration defaults, the parameterization of a
 * mesh in one call with one exact sizing query, configurations whose zeros
 * would do nothing refused, diag cleared on success, and invalid-argument
 * errors that name the argument or field and its allowed range (param,
 * optim, fit). */
#include "test.h"

static LS_ARENA_BUFFER(buf_, 4 << 20);
#define BUF buf_.bytes

static ls_mesh sphere;
static ls_arena sphere_arena;
static LS_ARENA_BUFFER(sphere_buf_, 256 << 10);

static int make_sphere(void)
{
    ls_arena_init(&sphere_arena, sphere_buf_.bytes, sizeof sphere_buf_.bytes);
    return ls_icosphere(3, &sphere_arena, &sphere) == LS_OK; /* 642 vertices */
}

static int contains(const char *text, const char *part)
{
    return text != NULL && strstr(text, part) != NULL;
}

static void param_config_default_is_the_papers(void)
{
    ls_param_config c;
    memset(&c, 0x5A, sizeof c);
    ls_param_config_default(&c);
    CHECK_EQ(c.solver, LS_PARAM_LDLT);
    CHECK_EQ(c.form, LS_SYSTEM_LAMBDA);
    CHECK(c.weight == (ls_real)19);
    CHECK_EQ(c.k, 3);
    CHECK_EQ(c.order, LS_ORDER_AUTO);
    CHECK_EQ(c.cg_max_iter, 1000);
    CHECK(c.cg_tol == (ls_real)1e-6);
    ls_param_config_default(NULL); /* ignored */
}

/* ls_param_mesh_bytes is exactly the arena's high-water mark of
 * ls_param_init_mesh, for both solvers; one byte short fails with nothing
 * written; the result equals ls_param_init on a Laplacian built by hand. */
static void param_init_mesh_sizing_is_exact(void)
{
    uint32_t solvers[2] = {LS_PARAM_LDLT, LS_PARAM_CG};
    int s;
    REQUIRE(make_sphere());
    for (s = 0; s < 2; s++) {
        ls_param_config c;
        ls_param p, q, sentinel;
        ls_arena a, b;
        ls_csc lap;
        ls_diag d;
        size_t bytes = 0, used;
        ls_real *x1, *x2, *u;
        size_t nk = 3u * (size_t)sphere.vertex_count, i;
        ls_param_config_default(&c);
        c.solver = solvers[s];
        ls_arena_init(&a, BUF, sizeof BUF);
        CHECK_STATUS(ls_param_mesh_bytes(&sphere, &c, &a, &bytes), LS_OK);
        CHECK_EQ(ls_arena_used(&a), 0); /* the query releases its scratch */
        CHECK(bytes > 0);
        /* the whole object: the arena's peak equals the query */
        ls_arena_init(&a, BUF, sizeof BUF);
        memset(&d, 0x5A, sizeof d);
        CHECK_STATUS(ls_param_init_mesh(&p, &sphere, &c, &a, &d), LS_OK);
        CHECK_EQ(a.peak, bytes);
        CHECK(d.status == LS_OK && d.what != NULL && d.what[0] == 0); /* cleared on success */
        /* an arena of exactly that many bytes builds it */
        REQUIRE(bytes <= (1u << 20));
        ls_arena_init(&b, BUF + (1u << 20), bytes);
        CHECK_STATUS(ls_param_init_mesh(&q, &sphere, &c, &b, NULL), LS_OK);
        used = ls_arena_used(&b);
        CHECK(used <= bytes);
        /* one byte short (8 after the arena's rounding): LS_ERR_NOMEM, nothing written */
        ls_arena_init(&b, BUF + (2u << 20), bytes - 1u);
        memset(&sentinel, 0xA5, sizeof sentinel);
        q = sentinel;
        CHECK_STATUS(ls_param_init_mesh(&q, &sphere, &c, &b, &d), LS_ERR_NOMEM);
        CHECK(memcmp(&q, &sentinel, sizeof q) == 0);
        CHECK_EQ(b.bottom, 0);
        CHECK_EQ(b.top, 0);
        CHECK_EQ(d.status, LS_ERR_NOMEM);
        /* the same numbers as the Laplacian built by hand */
        ls_arena_init(&b, BUF + (3u << 20), 1u << 20);
        REQUIRE(ls_laplacian_uniform(&sphere, LS_LAP_UPPER, &b, &lap, NULL) == LS_OK);
        REQUIRE(ls_param_init(&q, &lap, &c, sphere.positions, &b, NULL) == LS_OK);
        x1 = (ls_real *)ls_arena_alloc(&b, nk, sizeof(ls_real));
        x2 = (ls_real *)ls_arena_alloc(&b, nk, sizeof(ls_real));
        u = (ls_real *)ls_arena_alloc(&b, nk, sizeof(ls_real));
        REQUIRE(x1 != NULL && x2 != NULL && u != NULL);
        REQUIRE(ls_param_to_differential(&p, sphere.positions, u) == LS_OK);
        REQUIRE(ls_param_from_differential(&p, u, x1) == LS_OK);
        REQUIRE(ls_param_to_differential(&q, sphere.positions, u) == LS_OK);
        REQUIRE(ls_param_from_differential(&q, u, x2) == LS_OK);
        CHECK(memcmp(x1, x2, nk * sizeof(ls_real)) == 0);
        for (i = 0; i < nk; i++) CHECK_NEAR(x1[i], sphere.positions[i], 1e-4);
        printf("     %s: %zu bytes for %u vertices\n", s == 0 ? "ldlt" : "cg", bytes, sphere.vertex_count);
    }
}

/* A zeroed configuration with the CG solver once returned LS_OK and a
 * wrong result (0 iterations): it is refused, naming the field. */
static void zeros_that_would_do_nothing_are_refused(void)
{
    ls_param_config c;
    ls_param p;
    ls_arena a;
    ls_diag d;
    REQUIRE(make_sphere());
    ls_arena_init(&a, BUF, sizeof BUF);
    memset(&c, 0, sizeof c);
    c.solver = LS_PARAM_CG;
    c.k = 3;
    CHECK_STATUS(ls_param_init_mesh(&p, &sphere, &c, &a, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "cg_max_iter"));
    CHECK(contains(d.what, ">= 1"));
    CHECK_EQ(ls_arena_used(&a), 0);
    /* a zeroed configuration: k = 0 is named */
    memset(&c, 0, sizeof c);
    CHECK_STATUS(ls_param_init_mesh(&p, &sphere, &c, &a, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "cfg->k"));
    CHECK(contains(d.what, "1 .. LS_CG_MAX_K"));
    CHECK(d.has_value && d.value == (ls_real)0);
}

static void param_errors_name_the_field(void)
{
    static const struct {
        uint32_t solver, form, k, cg_max_iter;
        double weight, cg_tol;
        const char *field, *range;
    } cases[] = {
        {9, LS_SYSTEM_LAMBDA, 3, 10, 19, 1e-6, "cfg->solver", "LS_PARAM_LDLT"},
        {LS_PARAM_GRID, LS_SYSTEM_LAMBDA, 3, 10, 19, 1e-6, "cfg->solver", "for grids"},
        {LS_PARAM_LDLT, LS_SYSTEM_LAMBDA, 5, 10, 19, 1e-6, "cfg->k", "1 .. LS_CG_MAX_K"},
        {LS_PARAM_LDLT, 7, 3, 10, 19, 1e-6, "cfg->form", "LS_SYSTEM_ALPHA"},
        {LS_PARAM_LDLT, LS_SYSTEM_LAMBDA, 3, 10, -1, 1e-6, "cfg->weight", ">= 0"},
        {LS_PARAM_LDLT, LS_SYSTEM_ALPHA, 3, 10, 1, 1e-6, "cfg->weight", "[0, 1)"},
        {LS_PARAM_CG, LS_SYSTEM_LAMBDA, 3, 10, 19, -1, "cfg->cg_tol", ">= 0"},
    };
    size_t i;
    REQUIRE(make_sphere());
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ls_param_config c;
        ls_param p;
        ls_arena a;
        ls_diag d;
        size_t bytes = 1;
        ls_param_config_default(&c);
        c.solver = cases[i].solver;
        c.form = cases[i].form;
        c.k = cases[i].k;
        c.cg_max_iter = cases[i].cg_max_iter;
        c.weight = (ls_real)cases[i].weight;
        c.cg_tol = (ls_real)cases[i].cg_tol;
        ls_arena_init(&a, BUF, sizeof BUF);
        CHECK_STATUS(ls_param_init_mesh(&p, &sphere, &c, &a, &d), LS_ERR_INVALID);
        CHECK_MSG(contains(d.what, cases[i].field) && contains(d.what, cases[i].range), "case %zu: \"%s\"", i,
                  d.what);
        CHECK_EQ(d.status, LS_ERR_INVALID);
        CHECK_STATUS(ls_param_mesh_bytes(&sphere, &c, &a, &bytes), LS_ERR_INVALID);
        CHECK_EQ(bytes, 0);
        CHECK_EQ(ls_arena_used(&a), 0);
    }
    {
        ls_param_config c;
        ls_param p;
        ls_arena a;
        ls_diag d;
        ls_param_config_default(&c);
        ls_arena_init(&a, BUF, sizeof BUF);
        CHECK_STATUS(ls_param_init_mesh(&p, NULL, &c, &a, &d), LS_ERR_INVALID);
        CHECK(contains(d.what, "mesh"));
        CHECK_STATUS(ls_param_init(&p, NULL, &c, NULL, &a, &d), LS_ERR_INVALID);
        CHECK(contains(d.what, "lap"));
    }
}

/* A failure's diag does not survive the next success. */
static void diag_cleared_on_success(void)
{
    ls_param_config c;
    ls_param p;
    ls_arena a;
    ls_diag d;
    REQUIRE(make_sphere());
    ls_param_config_default(&c);
    ls_arena_init(&a, BUF, sizeof BUF);
    c.k = 0;
    CHECK_STATUS(ls_param_init_mesh(&p, &sphere, &c, &a, &d), LS_ERR_INVALID);
    CHECK(d.what[0] != 0);
    c.k = 3;
    CHECK_STATUS(ls_param_init_mesh(&p, &sphere, &c, &a, &d), LS_OK);
    CHECK_EQ(d.status, LS_OK);
    CHECK(d.what != NULL && d.what[0] == 0);
    CHECK(!d.has_value && !d.has_index);
    /* set_weight: a refused weight, then an accepted one */
    CHECK_STATUS(ls_param_set_weight(&p, (ls_real)-1, &d), LS_ERR_INVALID);
    CHECK(d.what[0] != 0);
    CHECK_STATUS(ls_param_set_weight(&p, (ls_real)4, &d), LS_OK);
    CHECK(d.what[0] == 0 && d.status == LS_OK);
}

/* Every call that takes a diag clears it first: a success leaves no stale
 * message from an earlier failure (a reader, the Laplacian, the rasterizer). */
static void diag_cleared_everywhere(void)
{
    static const char bad[] = "v 1 2\n", good[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    ls_arena a;
    ls_mesh m;
    ls_csc lap;
    ls_vis vis;
    ls_diag d;
    ls_real mvp[16];
    ls_arena_init(&a, BUF, sizeof BUF);
    CHECK_STATUS(ls_mesh_read(bad, sizeof bad - 1u, LS_MESH_FORMAT_AUTO, &a, &m, &d), LS_ERR_PARSE);
    CHECK(d.what[0] != 0 && d.has_line && d.line == 1);
    CHECK_STATUS(ls_mesh_read(good, sizeof good - 1u, LS_MESH_FORMAT_AUTO, &a, &m, &d), LS_OK);
    CHECK(d.status == LS_OK && d.what[0] == 0 && !d.has_line);
    CHECK_EQ(m.vertex_count, 3);
    m.triangles[2] = 7; /* out of range */
    CHECK_STATUS(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &lap, &d), LS_ERR_MESH);
    CHECK(d.what[0] != 0);
    m.triangles[2] = 2;
    CHECK_STATUS(ls_laplacian_uniform(&m, LS_LAP_UPPER, &a, &lap, &d), LS_OK);
    CHECK(d.what[0] == 0);
    ls_mat4_identity(mvp);
    REQUIRE(ls_vis_init(&vis, &a, 8, 8, 1, 3) == LS_OK);
    m.triangles[0] = 9;
    CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles, .triangle_count = 1,
            .vertex_count = 3, .mvp = mvp}, &a, &d), LS_ERR_MESH);
    CHECK(d.what[0] != 0 && d.has_index);
    m.triangles[0] = 0;
    CHECK_STATUS(ls_raster(&vis, &(ls_view){.positions = m.positions, .indices = m.triangles, .triangle_count = 1,
            .vertex_count = 3, .mvp = mvp}, &a, &d), LS_OK);
    CHECK(d.what[0] == 0 && !d.has_index);
}

static void optim_errors_name_the_field(void)
{
    ls_optim_config c;
    ls_optim o;
    ls_arena a;
    ls_diag d;
    ls_real params[4] = {1, 2, 3, 4}, grad[4] = {1, -1, 0.5, 0};
    uint32_t block = 4;
    CHECK_STATUS(ls_optim_config_default(LS_OPTIM_UNIFORM_ADAM, &c), LS_OK);
    CHECK_STATUS(ls_optim_config_check(&c, &d), LS_OK);
    CHECK(d.what[0] == 0);
    c.lr = 0;
    CHECK_STATUS(ls_optim_config_check(&c, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "config->lr") && contains(d.what, "> 0"));
    CHECK(d.has_value && d.value == (ls_real)0);
    c.lr = (ls_real)0.1;
    c.beta2 = (ls_real)1;
    CHECK_STATUS(ls_optim_config_check(&c, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "config->beta2") && contains(d.what, "[0, 1)"));
    CHECK(d.value == (ls_real)1);
    c.method = 0;
    CHECK_STATUS(ls_optim_config_check(&c, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "config->method"));
    CHECK_STATUS(ls_optim_config_check(NULL, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "config"));
    /* a step: an uninitialised optimizer is named; a good step clears the diag */
    memset(&o, 0, sizeof o);
    CHECK_STATUS(ls_optim_step(&o, params, grad, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "not initialised"));
    CHECK_STATUS(ls_optim_config_default(LS_OPTIM_UNIFORM_ADAM, &c), LS_OK);
    ls_arena_init(&a, BUF, sizeof BUF);
    REQUIRE(ls_optim_init(&o, &c, 4, 1, &block, &a) == LS_OK);
    CHECK_STATUS(ls_optim_step(&o, params, grad, &d), LS_OK);
    CHECK(d.what[0] == 0 && d.status == LS_OK);
    /* UniformAdam's first step moves every element of the block by lr * g / max|g| */
    CHECK_NEAR(params[0], 0.9, 1e-6);
    CHECK_NEAR(params[1], 2.1, 1e-6);
    CHECK_NEAR(params[2], 2.95, 1e-6);
    CHECK(params[3] == (ls_real)4);
}

static void fit_errors_name_the_field(void)
{
    static ls_real target[4 * 8 * 8];
    const ls_real *targets[1];
    ls_real mvp[16];
    ls_fit_config c;
    ls_fit_views v;
    ls_arena a;
    ls_diag d;
    size_t bytes = 0;
    REQUIRE(make_sphere());
    ls_mat4_identity(mvp);
    targets[0] = target;
    v.count = 1;
    v.mvp = mvp;
    v.targets = targets;
    ls_arena_init(&a, BUF, sizeof BUF);
    ls_fit_config_default(&c);
    c.width = c.height = 8;
    c.weight = (ls_real)-1;
    CHECK_STATUS(ls_fit_bytes(&c, &v, &sphere, &a, &bytes, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "config->weight") && contains(d.what, ">= 0"));
    ls_fit_config_default(&c);
    c.width = 0;
    CHECK_STATUS(ls_fit_bytes(&c, &v, &sphere, &a, &bytes, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "config->width") && contains(d.what, ">= 1"));
    ls_fit_config_default(&c);
    c.width = c.height = 8;
    c.optim.lr = 0;
    CHECK_STATUS(ls_fit_bytes(&c, &v, &sphere, &a, &bytes, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "config->lr") && contains(d.what, "> 0"));
    ls_fit_config_default(&c);
    c.width = c.height = 8;
    c.power = 3;
    CHECK_STATUS(ls_fit_bytes(&c, &v, &sphere, &a, &bytes, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "config->power"));
    v.count = 0;
    ls_fit_config_default(&c);
    CHECK_STATUS(ls_fit_bytes(&c, &v, &sphere, &a, &bytes, &d), LS_ERR_INVALID);
    CHECK(contains(d.what, "views->count"));
    v.count = 1;
    /* and a good configuration clears it */
    c.width = c.height = 8;
    CHECK_STATUS(ls_fit_bytes(&c, &v, &sphere, &a, &bytes, &d), LS_OK);
    CHECK(d.what[0] == 0 && d.status == LS_OK);
    CHECK(bytes > 0);
    CHECK_EQ(ls_arena_used(&a), 0);
}

int main(void)
{
    TEST_INIT("test_api");
    TEST_RUN(param_config_default_is_the_papers);
    TEST_RUN(param_init_mesh_sizing_is_exact);
    TEST_RUN(zeros_that_would_do_nothing_are_refused);
    TEST_RUN(param_errors_name_the_field);
    TEST_RUN(diag_cleared_on_success);
    TEST_RUN(diag_cleared_everywhere);
    TEST_RUN(optim_errors_name_the_field);
    TEST_RUN(fit_errors_name_the_field);
    return TEST_END();
}
