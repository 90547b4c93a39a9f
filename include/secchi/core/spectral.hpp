#pragma once
// The spectral band list: band centres in nm; a photon carries its band as a 1-byte index
// (manual 3.3.2.5), so at most 256 bands.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <cmath>
#include <cstdint>
#include <vector>

namespace secchi::SECCHI_ISA {

using band_index = std::uint8_t;

class BandList {
public:
    BandList() : centres_nm_{500.0} {}
    explicit BandList(std::vector<double> centres_nm) : centres_nm_(std::move(centres_nm)) {
        require(!centres_nm_.empty() && centres_nm_.size() <= 256, "band count", centres_nm_.size(),
                "must be 1..256 (one-byte band index, manual 3.3.2.5)");
        for (double w : centres_nm_)
            require(std::isfinite(w) && w > 0.0, "band centre (nm)", w, "must be finite and > 0");
    }
    [[nodiscard]] std::size_t size() const { return centres_nm_.size(); }
    [[nodiscard]] double wavelength_nm(band_index i) const { return centres_nm_.at(i); }

private:
    std::vector<double> centres_nm_;
};

}  // namespace secchi
