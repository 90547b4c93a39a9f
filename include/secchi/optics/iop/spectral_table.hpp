#pragma once
// A tabulated spectrum f(lambda): the published data of the IOP models (pure-water absorption,
// specific absorption, ...) and the user's spectral files (the FILENAME parameters of manual
// 5.6.1, 5.6.2.1, 5.6.3.1). Between nodes the value is linearly interpolated, as the manual
// says of its data ("Data for wavelengths between sampling increments will be linearly
// interpolated", 5.3.3). Outside the table there is no data, and no extrapolation: a query
// there is an input_error naming the table, the wavelength and the table's range.
//
// Validated on construction: at least two nodes, wavelengths finite and strictly increasing,
// values finite (values may be negative: e.g. the Bricaud 1995 exponent B).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA::iop {

/// One node of a table: the form of the constexpr data arrays (optics/iop/data/).
struct SpectralPoint {
    double wavelength_nm;
    double value;
};

class SpectralTable {
public:
    /// name: how messages call the table (e.g. "Smith-Baker 1981" or the user's file name).
    SpectralTable(std::string name, std::span<const double> wavelengths_nm, std::span<const double> values)
        : name_(std::move(name)), wavelengths_(wavelengths_nm.begin(), wavelengths_nm.end()),
          values_(values.begin(), values.end()) {
        validate();
    }

    /// From {wavelength, value} pairs, e.g. a constexpr std::array<SpectralPoint, N>.
    SpectralTable(std::string name, std::span<const SpectralPoint> points) : name_(std::move(name)) {
        wavelengths_.reserve(points.size());
        values_.reserve(points.size());
        for (const SpectralPoint& p : points) {
            wavelengths_.push_back(p.wavelength_nm);
            values_.push_back(p.value);
        }
        validate();
    }

    /// The linearly interpolated value at `wavelength_nm` (exactly the node's value on a node).
    /// Throws input_error outside [min_wavelength(), max_wavelength()].
    [[nodiscard]] double at(double wavelength_nm) const {
        if (!covers(wavelength_nm)) reject_wavelength(wavelength_nm);
        const auto hi = std::upper_bound(wavelengths_.begin(), wavelengths_.end(), wavelength_nm);
        const auto i = static_cast<std::size_t>(hi - wavelengths_.begin()) - 1;  // wl[i] <= wl < wl[i+1]
        if (wavelengths_[i] == wavelength_nm) return values_[i];
        const double t = (wavelength_nm - wavelengths_[i]) / (wavelengths_[i + 1] - wavelengths_[i]);
        return values_[i] + t * (values_[i + 1] - values_[i]);
    }

    /// True when `wavelength_nm` is inside the table's closed range (false for NaN).
    [[nodiscard]] bool covers(double wavelength_nm) const {
        return wavelength_nm >= min_wavelength() && wavelength_nm <= max_wavelength();
    }

    [[nodiscard]] double min_wavelength() const { return wavelengths_.front(); }
    [[nodiscard]] double max_wavelength() const { return wavelengths_.back(); }
    [[nodiscard]] const std::string& name() const { return name_; }
    [[nodiscard]] std::size_t size() const { return values_.size(); }
    [[nodiscard]] std::span<const double> wavelengths() const { return wavelengths_; }
    [[nodiscard]] std::span<const double> values() const { return values_; }

    /// Throws input_error "invalid wavelength (nm) = <wl>: outside the <name> table, <min>-<max> nm".
    [[noreturn]] void reject_wavelength(double wavelength_nm) const {
        std::ostringstream why;
        why << "outside the " << name_ << " table, " << min_wavelength() << "-" << max_wavelength() << " nm";
        reject("wavelength (nm)", wavelength_nm, why.str());
    }

private:
    void validate() const {
        const std::string what = "table " + name_;
        require(wavelengths_.size() == values_.size(), "number of values of " + what, values_.size(),
                "must equal the number of wavelengths (" + std::to_string(wavelengths_.size()) + ")");
        require(wavelengths_.size() >= 2, "number of wavelengths of " + what, wavelengths_.size(),
                "a table needs at least two wavelengths to interpolate");
        for (std::size_t i = 0; i < wavelengths_.size(); ++i) {
            const std::string row = " of " + what + " (row " + std::to_string(i + 1) + ")";
            require(std::isfinite(wavelengths_[i]), "wavelength (nm)" + row, wavelengths_[i], "must be finite");
            require(std::isfinite(values_[i]), "value" + row, values_[i], "must be finite");
            if (i > 0)
                require(wavelengths_[i] > wavelengths_[i - 1], "wavelength (nm)" + row, wavelengths_[i],
                        "wavelengths must be strictly increasing");
        }
    }

    std::string name_;
    std::vector<double> wavelengths_;
    std::vector<double> values_;
};

}  // namespace secchi::iop
