// Plane-sphere test (Eq. 1) at its edges: planes tangent to a sphere or
// through its centre, at every placement, in every format and with the PSI
// without normalisation. With the host's conservative margin on the radius a
// tangent plane must never miss; planes clearly outside are counted.
#include "stress.hpp"

namespace stress {
namespace {

std::vector<std::string> psi_formats() {
    std::vector<std::string> f = formats();
    f.push_back("fp1-7-16-psiunnorm");
    f.push_back("fp1-7-16-rtz-psiunnorm");
    f.push_back("fp1-8-15-psiunnorm");
    return f;
}

bool psi(const NumFormat& f, const Plane& p, const Sphere& s) {
    return with_arith(f, [&](const auto& a) { return plane_hits_sphere(a, load(a, p), load(a, s)); });
}

class Planes : public ::testing::TestWithParam<std::string> {};

TEST_P(Planes, TangentAndCentralPlanesNeverMissAMarginedSphere) {
    const NumFormat f = NumFormat::parse(GetParam());
    Rng rng(41);
    struct Case {
        const char* name;
        double centre, offset, rmin, rmax, extent;
    };
    // extent: the largest coordinate of the scene the sphere sits in
    const Case cases[] = {{"unit", 1.0, 0.0, 0.01, 0.5, 2.0},     {"tiny", 1e-6, 0.0, 1e-8, 5e-7, 1.0},
                          {"far", 1.0, 1e4, 0.01, 0.5, 1.2e4},    {"huge", 1e6, 0.0, 1e4, 5e5, 2e6},
                          {"huge7", 1e7, 0.0, 1e5, 5e6, 2e7}};
    for (const Case& cs : cases) {
        const double margin = conservative_margin(f.unit_roundoff(), cs.extent);
        std::uint64_t tangent = 0, tangent_missed = 0, central = 0, central_missed = 0, outside = 0, outside_hit = 0;
        std::uint64_t bare_tangent_missed = 0, bare_central_missed = 0;  // without the margin: information only
        for (int i = 0; i < 400; ++i) {
            const Vec3d c = rvec(rng, -cs.centre, cs.centre) + Vec3d(cs.offset, -cs.offset * 0.5, cs.offset * 0.25);
            const double r = uni(rng, cs.rmin, cs.rmax);
            const Vec3f cf = to_f(c);
            // radius about the stored centre, rounded up, plus the margin (as the host does)
            const Sphere s{cf, std::nextafter(float(r + margin), INFINITY)};
            const Sphere bare{cf, std::nextafter(float(r), INFINITY)};
            const Vec3f n = to_f(random_unit(rng));
            const Vec3d nd = to_d(n);
            const double nc = dot(nd, to_d(cf));
            for (double side : {-1.0, 1.0}) {
                const Plane tp{n, float(-nc + side * r)};
                ++tangent;
                tangent_missed += !psi(f, tp, s);
                bare_tangent_missed += !psi(f, tp, bare);
                const Plane op{n, float(-nc + side * (r + 2 * margin + 0.01 * r))};
                ++outside;
                outside_hit += psi(f, op, s);
            }
            ++central;
            central_missed += !psi(f, Plane{n, float(-nc)}, s);
            bare_central_missed += !psi(f, Plane{n, float(-nc)}, bare);
        }
        std::printf("planes %-22s %-5s tangent missed %llu of %llu (without margin %llu), central missed %llu of %llu "
                    "(without margin %llu), outside hit %llu of %llu\n",
                    f.name().c_str(), cs.name, (unsigned long long)tangent_missed, (unsigned long long)tangent,
                    (unsigned long long)bare_tangent_missed, (unsigned long long)central_missed,
                    (unsigned long long)central, (unsigned long long)bare_central_missed,
                    (unsigned long long)outside_hit, (unsigned long long)outside);
        EXPECT_EQ(tangent_missed, 0u) << f.name() << " " << cs.name;
        EXPECT_EQ(central_missed, 0u) << f.name() << " " << cs.name;
        // beyond twice the margin a plane is outside in every format that does not overflow
        const bool overflows = cs.extent > f.max_finite() / 8;
        if (!overflows) {
            EXPECT_EQ(outside_hit, 0u) << f.name() << " " << cs.name;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Formats, Planes, ::testing::ValuesIn(psi_formats()), param_name);

}  // namespace
}  // namespace stress
