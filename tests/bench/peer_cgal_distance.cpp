// tests/bench/peer_cgal_distance.cpp - the CGAL peer of bench_distance.c:
// CGAL's AABB tree (AABB_triangle_primitive, Simple_cartesian<double>,
// accelerate_distance_queries) on the same mesh and the same query points:
// build time, memory (growth of the peak RSS), closest-point throughput,
// agreement with our distances (DIR/ours.txt, written by bench_distance), and
// the vertex-sampled symmetric Hausdorff distance (what igl::hausdorff and our
// ls_mesh_distance with 0 face samples compute) against DIR/perturbed.obj.
//
//   peer_cgal_distance MESH.obj DIR [REPEAT]
//
// Bench-only dependency: Debian libcgal-dev (header-only here). CPU times,
// minimum of REPEAT runs. Output: "key value" lines like bench_distance.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <sys/resource.h>
#include <time.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

typedef CGAL::Simple_cartesian<double> K;
typedef K::Point_3 Point;
typedef K::Triangle_3 Triangle;
typedef std::vector<Triangle>::const_iterator Iterator;
typedef CGAL::AABB_triangle_primitive<K, Iterator> Primitive;
typedef CGAL::AABB_traits<K, Primitive> Traits;
typedef CGAL::AABB_tree<Traits> Tree;

static double now_ms()
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static long peak_rss_kb()
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss;
}

// "v x y z" and "f a b c" (1-based, optionally a/b/c forms; triangles only).
static bool read_obj(const char *path, std::vector<Point> &v, std::vector<unsigned> &f)
{
    std::ifstream in(path);
    if (!in) return false;
    std::string line;
    while (std::getline(in, line)) {
        if (line.size() < 2) continue;
        if (line[0] == 'v' && line[1] == ' ') {
            double x, y, z;
            if (std::sscanf(line.c_str() + 2, "%lf %lf %lf", &x, &y, &z) == 3) v.push_back(Point(x, y, z));
        } else if (line[0] == 'f' && line[1] == ' ') {
            std::istringstream ss(line.substr(2));
            std::string tok;
            std::vector<unsigned> poly;
            while (ss >> tok) poly.push_back((unsigned)std::strtoul(tok.c_str(), NULL, 10) - 1u);
            for (size_t k = 1; k + 1 < poly.size(); k++) {
                f.push_back(poly[0]);
                f.push_back(poly[k]);
                f.push_back(poly[k + 1]);
            }
        }
    }
    return true;
}

static void triangles(const std::vector<Point> &v, const std::vector<unsigned> &f, std::vector<Triangle> &t)
{
    for (size_t i = 0; i + 2 < f.size(); i += 3) t.push_back(Triangle(v[f[i]], v[f[i + 1]], v[f[i + 2]]));
}

static double max_dist(const Tree &tree, const std::vector<Point> &pts)
{
    double m = 0;
    for (size_t i = 0; i < pts.size(); i++) {
        double d = tree.squared_distance(pts[i]);
        if (d > m) m = d;
    }
    return std::sqrt(m);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        std::fprintf(stderr, "usage: peer_cgal_distance MESH.obj DIR [REPEAT]\n");
        return 2;
    }
    std::string dir = argv[2];
    int repeat = argc > 3 ? std::atoi(argv[3]) : 3;
    std::vector<Point> va, vb, q;
    std::vector<unsigned> fa, fb;
    if (!read_obj(argv[1], va, fa) || !read_obj((dir + "/perturbed.obj").c_str(), vb, fb)) {
        std::fprintf(stderr, "peer_cgal_distance: cannot read the meshes\n");
        return 1;
    }
    std::vector<Triangle> ta, tb;
    triangles(va, fa, ta);
    triangles(vb, fb, tb);
    {
        std::ifstream in((dir + "/queries.txt").c_str());
        unsigned n = 0;
        in >> n;
        for (unsigned i = 0; i < n; i++) {
            double x, y, z;
            in >> x >> y >> z;
            q.push_back(Point(x, y, z));
        }
    }
    // build
    double best = 1e300;
    long rss0 = peak_rss_kb(), rss1 = rss0;
    for (int r = 0; r < repeat; r++) {
        double t0 = now_ms();
        Tree tree(ta.begin(), ta.end());
        tree.build();
        tree.accelerate_distance_queries();
        double t1 = now_ms();
        if (t1 - t0 < best) best = t1 - t0;
        if (r == 0) rss1 = peak_rss_kb();
    }
    std::printf("cgal_build faces %lu ms %.3f rss_growth_bytes %ld\n", (unsigned long)ta.size(), best,
                (rss1 - rss0) * 1024L);
    // queries, and agreement with ours
    Tree tree(ta.begin(), ta.end());
    tree.build();
    tree.accelerate_distance_queries();
    std::vector<double> d2(q.size());
    std::vector<size_t> face(q.size());
    best = 1e300;
    double sum = 0;
    for (int r = 0; r < repeat; r++) {
        sum = 0;
        double t0 = now_ms();
        for (size_t i = 0; i < q.size(); i++) {
            Tree::Point_and_primitive_id pp = tree.closest_point_and_primitive(q[i]);
            d2[i] = CGAL::squared_distance(q[i], pp.first);
            face[i] = (size_t)(pp.second - ta.begin());
            sum += std::sqrt(d2[i]);
        }
        double t1 = now_ms();
        if (t1 - t0 < best) best = t1 - t0;
    }
    std::printf("cgal_queries n %lu ms %.3f per_s %.0f sum_dist %.12g\n", (unsigned long)q.size(), best,
                q.size() / (best * 1e-3), sum);
    {
        std::ifstream in((dir + "/ours.txt").c_str());
        size_t agree = 0, same_face = 0, n = 0;
        double worst = 0;
        for (size_t i = 0; i < q.size(); i++) {
            double od2;
            unsigned long of;
            if (!(in >> of >> od2)) break;
            n++;
            double rel = std::fabs(od2 - d2[i]) / (od2 > 1e-300 ? od2 : 1e-300);
            if (rel > worst) worst = rel;
            if (rel <= 1e-9) agree++;
            if (of == face[i]) same_face++;
        }
        std::printf("cgal_agreement n %lu dist2_within_1e-9 %lu same_face %lu worst_rel %.3g\n", (unsigned long)n,
                    (unsigned long)agree, (unsigned long)same_face, worst);
    }
    // vertex-sampled symmetric Hausdorff (igl::hausdorff), both trees built inside the timing
    best = 1e300;
    double h = 0;
    for (int r = 0; r < repeat; r++) {
        double t0 = now_ms();
        Tree a(ta.begin(), ta.end()), b(tb.begin(), tb.end());
        a.build();
        b.build();
        a.accelerate_distance_queries();
        b.accelerate_distance_queries();
        double hab = max_dist(b, va), hba = max_dist(a, vb);
        h = hab > hba ? hab : hba;
        double t1 = now_ms();
        if (t1 - t0 < best) best = t1 - t0;
    }
    std::printf("cgal_metric vertex ms %.3f H_vertex %.9g\n", best, h);
    return 0;
}
