// Grazing rays down to 1e-4 degrees, skinny triangles (1:1000), degenerate
// triangles, in every format: misses of points clearly inside and hits of
// points clearly outside are counted and held to docs/ACCURACY.md §5.
#include "stress.hpp"

namespace stress {
namespace {

// A random orthonormal frame: the triangle's plane is (e0, e1), normal e2.
struct Frame3 {
    Vec3d e0, e1, e2;
};
Frame3 random_frame(Rng& rng) {
    const Vec3d n = random_unit(rng);
    Vec3d t = normalize(cross(n, random_unit(rng)));
    return {t, cross(n, t), n};
}

TriangleRec record_of(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    Mesh m;
    m.materials.push_back(Material{});
    add_vertex(m, a);
    add_vertex(m, b);
    add_vertex(m, c);
    add_tri(m, 0, 1, 2);
    return make_triangle_record(m, 0);
}

struct MissCounts {
    std::uint64_t inside = 0, missed = 0, outside = 0, false_hits = 0;
    double max_t_error = 0;  // relative, over found hits
};

// A ray from `dist` away reaching point p of the triangle's plane at angle
// `deg` to the plane (from the front or the back); true barycentrics decide
// inside/outside.
Ray grazing_ray(const Frame3& fr, const Vec3d& p, double deg, double dist, Rng& rng) {
    const double pi = std::acos(-1.0);
    const double a = deg * pi / 180.0, phi = uni(rng, 0, 2 * pi);
    const Vec3d along = fr.e0 * std::cos(phi) + fr.e1 * std::sin(phi);
    const double side = rng() % 2 ? 1.0 : -1.0;
    const Vec3d d = along * std::cos(a) - fr.e2 * (side * std::sin(a));
    const Vec3f o = to_f(p - d * dist);
    return Ray{o, to_f(p - to_d(o)), 0.0f, FLT_MAX};
}

class Triangles : public ::testing::TestWithParam<std::string> {};

// Degrees of the grazing angles measured, and the allowed misses (of 200
// rays at points well inside) and false hits (of 200 well outside) per format.
struct GrazingBound {
    double deg;
    std::uint64_t missed, false_hits;
};

TEST_P(Triangles, GrazingRaysDownToATenThousandthOfADegree) {
    const NumFormat f = NumFormat::parse(GetParam());
    static const std::map<std::string, std::vector<GrazingBound>> bounds = {
#include "grazing_bounds.inc"
    };
    Rng rng(31);
    for (const GrazingBound& b : bounds.at(GetParam())) {
        MissCounts c;
        for (int i = 0; i < 200; ++i) {
            const Frame3 fr = random_frame(rng);
            const Vec3d a = fr.e0 * -1.0 + fr.e1 * -0.6, bb = fr.e0 * 1.0 + fr.e1 * -0.6, cc = fr.e1 * 1.1;
            const TriangleRec tr = record_of(a, bb, cc);
            // well inside: barycentrics >= 0.2; well outside: beyond an edge by 20% of the size
            const double u = uni(rng, 0.2, 0.6), v = uni(rng, 0.2, 0.8 - u);
            const Vec3d in = a + (bb - a) * u + (cc - a) * v;
            const Vec3d out = a + (bb - a) * uni(rng, 0.2, 0.8) - (cc - a) * 0.2;
            double t = 0;
            const Ray ri = grazing_ray(fr, in, b.deg, 2.0, rng);
            ++c.inside;
            if (rti(f, ri, tr, t)) {
                c.max_t_error = std::max(c.max_t_error, std::fabs(t - 1.0));
            } else {
                ++c.missed;
            }
            ++c.outside;
            c.false_hits += rti(f, grazing_ray(fr, out, b.deg, 2.0, rng), tr, t);
        }
        std::printf("grazing %-13s %8.0e deg: missed %3llu of %llu inside, hit %3llu of %llu outside, max |t-1| %.1e\n",
                    f.name().c_str(), b.deg, (unsigned long long)c.missed, (unsigned long long)c.inside,
                    (unsigned long long)c.false_hits, (unsigned long long)c.outside, c.max_t_error);
        EXPECT_LE(c.missed, b.missed) << f.name() << " at " << b.deg << " degrees";
        EXPECT_LE(c.false_hits, b.false_hits) << f.name() << " at " << b.deg << " degrees";
    }
}

TEST_P(Triangles, SkinnyTrianglesOneToAThousandAndThinner) {
    // Needles (two long edges, height 1/1000 of the length) and caps (an
    // obtuse apex 1/1000 of the base above its middle), randomly oriented,
    // hit from 20-90 degrees at points inside (the middle third of the
    // height) and outside (half to one height beyond an edge); then 1:10^4
    // and 1:10^5 to find where each format gives up.
    const NumFormat f = NumFormat::parse(GetParam());
    // per format: allowed misses and false hits at 1:10^3, 1:10^4, 1:10^5 (of 400 each)
    static const std::map<std::string, std::array<std::uint64_t, 6>> bounds = {
#include "skinny_bounds.inc"
    };
    Rng rng(32);
    for (int level = 0; level < 3; ++level) {
    const double h = std::pow(10.0, -3 - level);
    MissCounts c;
    for (int i = 0; i < 400; ++i) {
        const Frame3 fr = random_frame(rng);
        const bool needle = i % 2 == 0;
        // in frame coordinates: base (-1,0)-(1,0); apex (1, 2h) or (0, 2h)
        auto P = [&](double x, double y) { return fr.e0 * x + fr.e1 * y; };
        const TriangleRec tr = record_of(P(-1, 0), P(1, 0), needle ? P(1, 2 * h) : P(0, 2 * h));
        const double x = needle ? uni(rng, -0.9, 0.9) : uni(rng, -0.8, 0.8);
        const double height = needle ? h * (x + 1) : 2 * h * (1 - std::fabs(x));  // of the triangle at x
        const Vec3d in = P(x, height * uni(rng, 0.33, 0.67));
        const Vec3d out = i % 4 < 2 ? P(x, -height * uni(rng, 0.5, 1.0)) : P(x, height * uni(rng, 1.5, 2.0));
        double t;
        const double deg = uni(rng, 20, 90);
        ++c.inside;
        c.missed += !rti(f, grazing_ray(fr, in, deg, 2.0, rng), tr, t);
        ++c.outside;
        c.false_hits += rti(f, grazing_ray(fr, out, deg, 2.0, rng), tr, t);
    }
    std::printf("skinny  %-13s 1:%.0e missed %3llu of %llu inside, hit %3llu of %llu outside\n", f.name().c_str(),
                1 / h, (unsigned long long)c.missed, (unsigned long long)c.inside, (unsigned long long)c.false_hits,
                (unsigned long long)c.outside);
    EXPECT_LE(c.missed, bounds.at(GetParam())[std::size_t(2 * level)]) << f.name() << " 1:" << 1 / h;
    EXPECT_LE(c.false_hits, bounds.at(GetParam())[std::size_t(2 * level + 1)]) << f.name() << " 1:" << 1 / h;
    }
}

TEST_P(Triangles, DegenerateTrianglesAreNeverHit) {
    // Zero area: a repeated vertex, all three equal, exactly collinear
    // (integer and power-of-two coordinates, so the float32 records are
    // exact and E = 0). No format may report a hit, whatever the ray.
    const NumFormat f = NumFormat::parse(GetParam());
    Rng rng(33);
    std::vector<TriangleRec> degenerate;
    for (int i = 0; i < 60; ++i) {
        const Vec3d a{double(int(rng() % 9) - 4), double(int(rng() % 9) - 4), double(int(rng() % 9) - 4)};
        const Vec3d step{double(int(rng() % 5) - 2), double(int(rng() % 5) - 2), double(int(rng() % 5) - 2)};
        const double scale = std::ldexp(1.0, int(rng() % 41) - 20);
        switch (i % 4) {
            case 0: degenerate.push_back(record_of(a * scale, a * scale, (a + step) * scale)); break;
            case 1: degenerate.push_back(record_of(a * scale, a * scale, a * scale)); break;
            case 2: degenerate.push_back(record_of(a * scale, (a + step) * scale, (a + step * 2.0) * scale)); break;
            default: degenerate.push_back(record_of(a * scale, (a + step * 3.0) * scale, (a + step) * scale)); break;
        }
    }
    int tests = 0, hits = 0;
    for (const TriangleRec& tr : degenerate) {
        ASSERT_EQ(tr.n, Vec3f(0, 0, 0));
        const double scale = std::max(1e-30, double(max_abs(tr.v0)) + double(max_abs(tr.e1)) + double(max_abs(tr.e2)));
        for (int k = 0; k < 50; ++k) {
            // rays through a vertex, a point of the segment, and random ones
            const Vec3d target = to_d(tr.v0) + to_d(tr.e1) * (k % 3 == 0 ? 0.0 : uni(rng, 0, 1));
            const Vec3f o = to_f(target + random_unit(rng) * (scale * uni(rng, 0.5, 4)));
            const Ray r{o, k % 5 == 4 ? to_f(random_unit(rng)) : to_f(target - to_d(o)), 0.0f, FLT_MAX};
            double t;
            hits += rti(f, r, tr, t);
            ++tests;
        }
    }
    EXPECT_EQ(hits, 0) << f.name() << ": " << hits << " hits on zero-area triangles of " << tests << " rays";
}

INSTANTIATE_TEST_SUITE_P(Formats, Triangles, ::testing::ValuesIn(formats_with_watertight()), param_name);

}  // namespace
}  // namespace stress
