#pragma once
// Strong types for quantities that are easy to confuse. A collection radius is never a bare
// float that might already be squared (nanoflann's L2 metric works in squared distances).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <cmath>

namespace secchi::SECCHI_ISA {

/// A search / collection radius in metres (plain, not squared).
class Radius {
public:
    constexpr Radius() = default;
    explicit Radius(double metres) : r_(metres) {
        require(std::isfinite(metres) && metres > 0.0, "radius", metres, "must be finite and > 0");
    }
    [[nodiscard]] constexpr double value() const { return r_; }
    [[nodiscard]] constexpr double squared() const { return r_ * r_; }

private:
    double r_ = 1.0;
};

}  // namespace secchi
