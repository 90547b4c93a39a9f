#pragma once
// Vectors through GLM, constants, and the frame rotation every scattering event needs.
#include <cmath>
#include <glm/glm.hpp>
#include <numbers>

namespace secchi {

using vec3 = glm::dvec3;   ///< positions and directions during transport (z positive down)
using vec3f = glm::vec3;   ///< compact storage

inline constexpr double pi = std::numbers::pi;
inline constexpr double two_pi = 2.0 * std::numbers::pi;
inline constexpr double four_pi = 4.0 * std::numbers::pi;
inline constexpr double deg = std::numbers::pi / 180.0;  ///< one degree in radians

/// Direction after scattering through angle psi (cos_psi) at azimuth phi about `dir`
/// (unit vector). Builds an orthonormal frame around dir (Duff et al. 2017 branchless basis).
inline vec3 rotate_direction(const vec3& dir, double cos_psi, double phi) {
    const double sin_psi = std::sqrt(std::max(0.0, 1.0 - cos_psi * cos_psi));
    const double sign = std::copysign(1.0, dir.z);
    const double a = -1.0 / (sign + dir.z);
    const double b = dir.x * dir.y * a;
    const vec3 t1(1.0 + sign * dir.x * dir.x * a, sign * b, -sign * dir.x);
    const vec3 t2(b, sign + dir.y * dir.y * a, -dir.y);
    const vec3 out = sin_psi * std::cos(phi) * t1 + sin_psi * std::sin(phi) * t2 + cos_psi * dir;
    return glm::normalize(out);
}

}  // namespace secchi
