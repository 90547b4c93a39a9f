#include <catch2/catch.hpp>
#include "secchi/core/math.hpp"
#include "secchi/core/rng.hpp"
#include "secchi/map/record.hpp"
#include <cmath>
#include <vector>

using namespace secchi;

namespace {

/// The direction bytes by the defining formula, with acos and atan2.
std::pair<int, int> reference_bytes(const vec3& d) {
    const double theta = std::acos(std::clamp(d.z, -1.0, 1.0));
    double phi = std::atan2(d.y, d.x);
    if (phi < 0.0) phi += two_pi;
    return {std::min(255, static_cast<int>(theta * 256.0 / pi)), static_cast<int>(std::lround(phi * 256.0 / two_pi)) & 255};
}

// Angles in long double (64-bit or wider mantissa on the usual platforms): distance from the
// nearest bin boundary, theta boundaries k pi/256 (k = 1..255), phi boundaries (j + 1/2) 2 pi/256.
const long double pi_l = 3.141592653589793238462643383279502884L;

long double theta_boundary_distance(double dz) {
    const long double theta = std::acos(std::clamp(static_cast<long double>(dz), -1.0L, 1.0L));
    const long double k = std::round(theta * 256.0L / pi_l);
    return (k < 1.0L || k > 255.0L) ? 1.0L : std::abs(theta - k * pi_l / 256.0L);
}

long double phi_boundary_distance(double dx, double dy) {
    const long double bin = 2.0L * pi_l / 256.0L;
    const long double phi = std::atan2(static_cast<long double>(dy), static_cast<long double>(dx));
    const long double x = phi / bin - 0.5L;
    return std::abs(x - std::round(x)) * bin;
}

struct Comparison {
    long checked = 0, theta_ties = 0, phi_ties = 0, bad = 0;
    void check(const vec3& d) {
        const CompactRecord r = CompactRecord::make({0.0, 0.0, 0.0}, d, 0, 0);
        const auto [ti, pj] = reference_bytes(d);
        ++checked;
        if (r.theta != ti) {
            const bool tie = theta_boundary_distance(d.z) < 1e-12L && std::abs(r.theta - ti) == 1;
            theta_ties += tie;
            if (!tie) {
                ++bad;
                UNSCOPED_INFO("theta byte " << int(r.theta) << " != " << ti << " for dz = " << d.z);
            }
        }
        if (r.phi != pj) {
            const bool tie = phi_boundary_distance(d.x, d.y) < 1e-12L && (((r.phi - pj) & 255) == 1 || ((r.phi - pj) & 255) == 255);
            phi_ties += tie;
            if (!tie) {
                ++bad;
                UNSCOPED_INFO("phi byte " << int(r.phi) << " != " << pj << " for dx, dy = " << d.x << ", " << d.y);
            }
        }
    }
};

vec3 from_angles(long double theta, long double phi) {
    return {static_cast<double>(std::sin(theta) * std::cos(phi)), static_cast<double>(std::sin(theta) * std::sin(phi)),
            static_cast<double>(std::cos(theta))};
}

}  // namespace

TEST_CASE("compact direction encoding equals the acos/atan2 formula") {
    // 2e6 directions uniform on the sphere, normalised in double as the tracer's are: none
    // lies within 1e-12 rad of a boundary (for this seed), so all bytes must agree.
    Comparison random;
    PhotonRng rng(2024, 0);
    for (int i = 0; i < 2000000; ++i) {
        const double mu = 2.0 * rng.uniform() - 1.0, phi = two_pi * rng.uniform();
        const double s = std::sqrt(1.0 - mu * mu);
        random.check(glm::normalize(vec3(s * std::cos(phi), s * std::sin(phi), mu)));
    }
    CHECK(random.bad == 0);
    CHECK(random.theta_ties + random.phi_ties == 0);

    Comparison c;
    // On and next to every bin boundary, where the guess must be corrected.
    const long double tbin = pi_l / 256.0L, pbin = 2.0L * pi_l / 256.0L;
    for (long double off : {0.0L, 1e-15L, -1e-15L, 1e-13L, -1e-13L, 1e-11L, -1e-11L, 1e-8L, -1e-8L, 1e-4L, -1e-4L}) {
        for (int k = 1; k < 256; ++k)
            for (long double phi : {0.1L, 1.3L, 2.9L, 4.4L, 6.2L}) c.check(from_angles(k * tbin + off, phi));
        for (int j = 0; j < 256; ++j)
            for (long double theta : {1e-6L, 0.02L, 0.7L, 1.5L, 2.5L, 3.1L, pi_l - 1e-6L})
                c.check(from_angles(theta, (j + 0.5L) * pbin + off));
    }
    // Poles and axes with either sign of zero, near-polar directions, |dz| rounded above 1.
    for (double z0 : {0.0, -0.0})
        for (double x0 : {0.0, -0.0})
            for (double y0 : {0.0, -0.0}) {
                c.check({x0, y0, 1.0});
                c.check({x0, y0, -1.0});
                c.check({1.0, y0, z0});
                c.check({-1.0, y0, z0});
                c.check({x0, 1.0, z0});
                c.check({x0, -1.0, z0});
            }
    for (double t : {1e-300, 1e-30, 1e-10, 1e-5})
        for (double sx : {1.0, -1.0})
            for (double sy : {1.0, -1.0}) {
                c.check({sx * t, 0.5 * sy * t, 1.0});
                c.check({0.5 * sx * t, sy * t, -1.0});
            }
    c.check({0.0, 0.0, std::nextafter(1.0, 2.0)});
    c.check({0.0, 0.0, std::nextafter(-1.0, -2.0)});
    INFO(c.checked << " directions; ties at a boundary: theta " << c.theta_ties << ", phi " << c.phi_ties);
    CHECK(c.bad == 0);  // ties (either neighbouring byte) only within 1e-12 rad of a boundary
}

TEST_CASE("compact records keep position, band and batch; the direction decodes to the bin centre") {
    const CompactRecord r = CompactRecord::make({0.25, 0.5, 3.0}, glm::normalize(vec3(1.0, 1.0, 1.0)), 3, 17);
    CHECK(r.position() == vec3(0.25, 0.5, 3.0));
    CHECK(r.band() == 3);
    CHECK(r.batch() == 17);
    CHECK(int(r.theta) == int(std::acos(1.0 / std::sqrt(3.0)) * 256.0 / pi));
    CHECK(int(r.phi) == 32);  // 45 deg
    const vec3 d = r.direction();
    CHECK(std::acos(glm::dot(d, glm::normalize(vec3(1.0, 1.0, 1.0)))) < 0.5 * pi / 256.0 + 1e-12);
}

TEST_CASE("a compact record's store tag lives beside its batch without changing it") {
    CompactRecord r = CompactRecord::make({1.0, 2.0, 3.0}, vec3(0.0, 0.0, 1.0), 5, 63);
    CHECK(r.store_tag() == 0);
    for (std::uint8_t tag : {3, 1, 2, 0}) {
        r.set_store_tag(tag);
        CHECK(r.store_tag() == tag);
        CHECK(r.batch() == 63);
        CHECK(r.band() == 5);
        CHECK(r.position() == vec3(1.0, 2.0, 3.0));
    }
    CHECK(record_max_batches<CompactRecord>() == 64);
    CHECK(record_max_batches<FullRecord>() == 256);
}
