#pragma once
// A pinhole camera: the rays of an image (z positive down, depth below the surface at z = 0).
// The camera sits at `position`, looks along `forward`, with the image's up towards `up`
// (made perpendicular to forward), a vertical field of view `fov_deg` and width x height
// pixels of square aspect. Pixel (x, y), row y = 0 at the top, is sampled at (x + u, y + v)
// for u, v in [0, 1) (0.5, 0.5: its centre).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/map/store.hpp"
#include <cmath>

namespace secchi::SECCHI_ISA {

struct PinholeCameraSpec {
    vec3 position{0.5, 0.5, 5.0};
    vec3 forward{0.0, 0.0, -1.0};  ///< looking straight up by default
    vec3 up{1.0, 0.0, 0.0};        ///< the image's up: the world's -z unless forward is vertical
    double fov_deg = 60.0;         ///< vertical field of view
    int width = 256, height = 256;
};

class PinholeCamera {
public:
    explicit PinholeCamera(const PinholeCameraSpec& spec) : spec_(spec) {
        require(std::isfinite(spec.fov_deg) && spec.fov_deg > 0.0 && spec.fov_deg < 180.0, "field of view (deg)",
                spec.fov_deg, "must lie in (0, 180)");
        require(spec.width > 0 && spec.height > 0, "camera resolution", spec.width * spec.height, "must be > 0 each way");
        require(glm::length(spec.forward) > 0.0, "camera forward", glm::length(spec.forward), "must not be 0");
        forward_ = glm::normalize(spec.forward);
        const vec3 right = glm::cross(forward_, spec.up);
        require(glm::length(right) > 1e-9, "camera up", glm::length(right), "must not be parallel to forward");
        right_ = glm::normalize(right);
        up_ = glm::cross(right_, forward_);
        half_height_ = std::tan(0.5 * spec.fov_deg * deg);
    }
    [[nodiscard]] int width() const { return spec_.width; }
    [[nodiscard]] int height() const { return spec_.height; }
    [[nodiscard]] const vec3& position() const { return spec_.position; }

    /// The ray through image point (x + u, y + v), unbounded.
    [[nodiscard]] Ray ray(int x, int y, double u = 0.5, double v = 0.5) const {
        const double sx = (2.0 * (x + u) / spec_.width - 1.0) * half_height_ * spec_.width / spec_.height;
        const double sy = (1.0 - 2.0 * (y + v) / spec_.height) * half_height_;
        return {spec_.position, glm::normalize(forward_ + sx * right_ + sy * up_), INFINITY};
    }

private:
    PinholeCameraSpec spec_;
    vec3 forward_{}, right_{}, up_{};
    double half_height_ = 0.0;
};

}  // namespace secchi
