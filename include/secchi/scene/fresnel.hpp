#pragma once
// Unpolarised Fresnel reflectance and Snell refraction at a flat interface
// (Mobley 1994, "Light and Water", eq. 4.19-4.21; the manual ch. 2.5.4, eq. 2.28-2.29).
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include <algorithm>
#include <cmath>

namespace secchi::SECCHI_ISA {

/// Reflectance for unpolarised light arriving with cosine `cos_i` (> 0, measured from the
/// normal on the incident side) going from index n1 into index n2. Total internal
/// reflection (sin_t > 1) gives 1. R = (r_s^2 + r_p^2) / 2.
inline double fresnel_reflectance(double cos_i, double n1, double n2) {
    cos_i = std::clamp(cos_i, 0.0, 1.0);
    const double eta = n1 / n2;
    const double sin_t2 = eta * eta * (1.0 - cos_i * cos_i);
    if (sin_t2 >= 1.0) return 1.0;
    const double cos_t = std::sqrt(1.0 - sin_t2);
    const double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    const double rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

/// Refracted direction through a horizontal interface (normal along z) from index n1 into
/// index n2 (Snell's law): horizontal components scale by n1/n2, the vertical sign is kept.
/// Precondition: no total internal reflection.
inline vec3 refract_horizontal(const vec3& dir, double n1, double n2) {
    const double eta = n1 / n2;
    const double sx = eta * dir.x, sy = eta * dir.y;
    const double uz = std::sqrt(std::max(0.0, 1.0 - sx * sx - sy * sy));
    return {sx, sy, std::copysign(uz, dir.z)};
}

/// Reflection about a tilted facet of unit normal m facing the incident side (m . d < 0, with
/// cos_i = -m . d): d' = d + 2 cos_i m (Mobley 1994, "Light and Water", eq. 4.11).
inline vec3 reflect_about(const vec3& d, const vec3& m, double cos_i) { return d + (2.0 * cos_i) * m; }

/// Refraction through a tilted facet (unit normal m facing the incident side, cos_i = -m . d)
/// from index n1 into n2, the vector form of Snell's law (Mobley 1994, eq. 4.12):
/// d' = eta d + (eta cos_i - cos_t) m, eta = n1 / n2, cos_t = sqrt(1 - eta^2 (1 - cos_i^2)).
/// Precondition: no total internal reflection.
inline vec3 refract_through(const vec3& d, const vec3& m, double cos_i, double n1, double n2) {
    const double eta = n1 / n2;
    const double cos_t = std::sqrt(std::max(0.0, 1.0 - eta * eta * (1.0 - cos_i * cos_i)));
    return glm::normalize(eta * d + (eta * cos_i - cos_t) * m);
}

/// Critical angle (radians) for light in the denser medium n_dense against n_rare.
inline double critical_angle(double n_dense, double n_rare) { return std::asin(n_rare / n_dense); }

}  // namespace secchi
