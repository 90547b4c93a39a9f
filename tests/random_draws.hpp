#pragma once
// Random draws for the property tests of random rays (test_geometry.cpp, test_wave_surface.cpp):
// a seeded generator of uniforms, uniform directions on the sphere and directions on one side
// of a plane.
#include "secchi/core/math.hpp"
#include <cmath>
#include <cstdint>
#include <random>

namespace secchi::testing {

struct Rand {
    std::mt19937_64 gen;
    std::uniform_real_distribution<double> uni{0.0, 1.0};
    explicit Rand(std::uint64_t seed) : gen(seed) {}
    double operator()() { return uni(gen); }
    double in(double a, double b) { return a + (b - a) * uni(gen); }
    vec3 direction() {  // uniform on the sphere
        const double mu = in(-1.0, 1.0), phi = two_pi * uni(gen), s = std::sqrt(1.0 - mu * mu);
        return {s * std::cos(phi), s * std::sin(phi), mu};
    }
    /// A direction d with dot(d, n) of the sign of `sign` (n a unit vector).
    vec3 direction_against(const vec3& n, double sign) {
        while (true) {
            const vec3 d = direction();
            if (glm::dot(d, n) * sign > 1e-3) return d;
        }
    }
};

}  // namespace secchi::testing
