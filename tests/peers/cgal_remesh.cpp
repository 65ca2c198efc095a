// tests/peers/cgal_remesh.cpp - the remeshing peer: CGAL's isotropic remeshing
// (Polygon_mesh_processing::isotropic_remeshing, Debian libcgal-dev; bench and
// test only, never linked into the library) on the same input and target h as
// `largesteps remesh` / tests/bench/bench_remesh.c, with the same statistics:
// CPU time (std::clock, minimum of REPEAT runs), edge lengths over the 3 edges of every face
// (mean / h, fraction in [4/5 h, 4/3 h]), corner angles (min, 1 %, 5 %,
// median), vertex-sampled Hausdorff distance to the input in both directions
// (like libigl's hausdorff), vertex and face counts.
//
// usage: cgal_remesh MESH.obj FACTOR [ITERS] [REPEAT]
//   target h = FACTOR x mean edge length (over the 3 edges of every face).
// Prints one line:
//   cgal <mesh> <V_in> <V_out> <F_out> <ms> <mean/h> <in_range> <amin> <a1> <a5> <a50> <haus/h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef CGAL::AABB_face_graph_triangle_primitive<Mesh> Primitive;
typedef CGAL::AABB_traits<K, Primitive> Traits;
typedef CGAL::AABB_tree<Traits> Tree;
namespace PMP = CGAL::Polygon_mesh_processing;

static double mean_edge(const Mesh &m)
{
    double s = 0;
    std::size_t n = 0;
    for (auto f : m.faces())
        for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
            s += std::sqrt(CGAL::squared_distance(m.point(m.source(h)), m.point(m.target(h))));
            n++;
        }
    return s / (double)n;
}

// Largest distance from a vertex of `from` to the surface of `to`.
static double one_sided(const Mesh &from, const Mesh &to)
{
    Tree tree(faces(to).first, faces(to).second, to);
    tree.accelerate_distance_queries();
    double worst = 0;
    for (auto v : from.vertices()) worst = std::max(worst, std::sqrt(tree.squared_distance(from.point(v))));
    return worst;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        std::fprintf(stderr, "usage: cgal_remesh MESH FACTOR [ITERS] [REPEAT]\n");
        return 2;
    }
    double factor = std::atof(argv[2]);
    unsigned iters = argc > 3 ? (unsigned)std::atoi(argv[3]) : 5u;
    int repeat = argc > 4 ? std::atoi(argv[4]) : 3;
    Mesh in;
    if (!PMP::IO::read_polygon_mesh(argv[1], in) || !CGAL::is_triangle_mesh(in)) {
        std::fprintf(stderr, "cgal_remesh: cannot read %s\n", argv[1]);
        return 1;
    }
    double h = factor * mean_edge(in), best = 1e300;
    Mesh out;
    for (int r = 0; r < repeat; r++) {
        Mesh m = in;
        std::clock_t t0 = std::clock();
        PMP::isotropic_remeshing(faces(m), h, m, CGAL::parameters::number_of_iterations(iters));
        std::clock_t t1 = std::clock();
        best = std::min(best, 1000.0 * (double)(t1 - t0) / (double)CLOCKS_PER_SEC);
        if (r == 0) out = m;
    }
    out.collect_garbage();
    std::vector<double> ang;
    double sum = 0;
    std::size_t n = 0, inside = 0;
    for (auto f : out.faces()) {
        std::vector<Point> p;
        for (auto v : CGAL::vertices_around_face(out.halfedge(f), out)) p.push_back(out.point(v));
        for (int j = 0; j < 3; j++) {
            K::Vector_3 u = p[(j + 1) % 3] - p[j], w = p[(j + 2) % 3] - p[j];
            double lu = std::sqrt(u.squared_length()), lw = std::sqrt(w.squared_length());
            double d = (u * w) / (lu * lw);
            ang.push_back(std::acos(std::max(-1.0, std::min(1.0, d))) * 180.0 / 3.14159265358979323846);
            sum += lu;
            n++;
            if (lu >= 0.8 * h && lu <= 4.0 / 3.0 * h) inside++;
        }
    }
    std::sort(ang.begin(), ang.end());
    double haus = std::max(one_sided(out, in), one_sided(in, out));
    const char *name = std::strrchr(argv[1], '/') ? std::strrchr(argv[1], '/') + 1 : argv[1];
    std::printf("cgal %s %zu %zu %zu %.3f %.4f %.4f %.2f %.2f %.2f %.2f %.4f\n", name, (std::size_t)in.number_of_vertices(),
                (std::size_t)out.number_of_vertices(), (std::size_t)out.number_of_faces(), best, sum / (double)n / h,
                (double)inside / (double)n, ang[0], ang[n / 100], ang[n / 20], ang[n / 2], haus / h);
    return 0;
}
